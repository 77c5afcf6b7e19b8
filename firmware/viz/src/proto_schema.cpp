#include "proto_schema.hpp"

#include <google/protobuf/descriptor.pb.h>

#include <set>
#include <string>

namespace handscan::viz {
namespace {

// Depth first, imports before the file that imports them (the order protoc writes a set in).
void addFile(const google::protobuf::FileDescriptor* file, std::set<std::string>& seen,
             google::protobuf::FileDescriptorSet& set) {
    if (!seen.insert(file->name()).second) return;
    for (int i = 0; i < file->dependency_count(); ++i) addFile(file->dependency(i), seen, set);
    file->CopyTo(set.add_file());
}

}  // namespace

std::vector<std::uint8_t> fileDescriptorSet(const google::protobuf::Descriptor* message) {
    google::protobuf::FileDescriptorSet set;
    std::set<std::string> seen;
    addFile(message->file(), seen, set);
    std::vector<std::uint8_t> bytes(set.ByteSizeLong());
    set.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
    return bytes;
}

}  // namespace handscan::viz

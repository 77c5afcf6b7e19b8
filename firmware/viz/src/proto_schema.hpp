// The schema of a protobuf channel as MCAP's protobuf profile wants it in a Schema record: the
// message's full name, and a google.protobuf.FileDescriptorSet holding the message's .proto file
// and every file it imports (dependencies first), so a reader decodes without our .proto files.
#pragma once

#include <google/protobuf/descriptor.h>

#include <cstdint>
#include <vector>

namespace handscan::viz {

std::vector<std::uint8_t> fileDescriptorSet(const google::protobuf::Descriptor* message);

}  // namespace handscan::viz

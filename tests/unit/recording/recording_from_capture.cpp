// Turns a raw device capture into a recording of that device's raw channel, cut into pieces of
// varying size (as reads from a socket or tty would be) 1 ms apart in host time. Used to check
// that `handscan decode` gives the same samples from a recording as from the plain capture.
//
// usage: recording_from_capture CAPTURE TOPIC OUT.mcap [zstd|none]
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "handscan/recording/channels.hpp"
#include "handscan/recording/mcap_writer.hpp"

using namespace handscan;
using namespace handscan::recording;

int main(int argc, char** argv) {
    if (argc != 4 && argc != 5) {
        std::fprintf(stderr, "usage: %s CAPTURE TOPIC OUT.mcap [zstd|none]\n", argv[0]);
        return 2;
    }
    std::ifstream in(argv[1], std::ios::binary);
    const bool opened = static_cast<bool>(in);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
    const ChannelSpec* spec = findChannel(argv[2]);
    if (!opened || bytes.empty() || spec == nullptr) {
        std::fprintf(stderr, "%s: cannot read, or %s is not a known channel\n", argv[1], argv[2]);
        return 1;
    }
    McapWriterOptions o;
    o.chunk_size_bytes = 4096;  // several chunks even for a small capture
    if (argc == 5 && std::string(argv[4]) == "none") o.compression.clear();
    auto w = McapWriter::create(argv[3], o);
    if (!w) return 1;
    auto id = addChannel(**w, *spec);
    if (!id) return 1;
    const std::size_t pieces[] = {1, 7, 64, 300, 13, 2, 1024, 5};
    TimeNs t = 100 * kNsPerSec;
    std::size_t k = 0;
    for (std::size_t pos = 0; pos < bytes.size(); ++k, t += kNsPerMs) {
        const std::size_t n = std::min(pieces[k % std::size(pieces)], bytes.size() - pos);
        if (!(*w)->write(*id, t, std::span(bytes).subspan(pos, n))) return 1;
        pos += n;
    }
    return (*w)->close() ? 0 : 1;
}

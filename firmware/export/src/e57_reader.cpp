#include "handscan/export/e57_reader.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <memory>

#include "e57_format.hpp"
#include "e57_page_check.hpp"
#include "e57_xml_tree.hpp"

namespace handscan::exporter {
namespace {

using namespace e57;

class Fd {
public:
    explicit Fd(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {}
    ~Fd() {
        if (fd_ >= 0) ::close(fd_);
    }
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    int get() const { return fd_; }

private:
    int fd_;
};

bool readAt(int fd, std::uint8_t* out, std::size_t n, std::uint64_t offset) {
    while (n > 0) {
        const ssize_t r = ::pread(fd, out, n, static_cast<off_t>(offset));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        out += r;
        n -= static_cast<std::size_t>(r);
        offset += static_cast<std::uint64_t>(r);
    }
    return true;
}

// `n` logical bytes from logical offset `logical`: the pages' payloads without their CRCs.
bool readLogical(int fd, std::uint64_t logical, std::size_t n, std::vector<std::uint8_t>& out) {
    out.resize(n);
    std::size_t done = 0;
    while (done < n) {
        const std::uint64_t at = logical + done;
        const std::size_t k = std::min<std::size_t>(
            n - done, kPagePayload - static_cast<std::size_t>(at % kPagePayload));
        if (!readAt(fd, out.data() + done, k, physicalOf(at))) return false;
        done += k;
    }
    return true;
}

Status checkPages(int fd, const std::string& path, std::uint64_t length) {
    PageChecker checker;
    std::vector<std::uint8_t> buf(1 << 20);
    for (std::uint64_t at = 0; at < length;) {
        const std::size_t n =
            static_cast<std::size_t>(std::min<std::uint64_t>(buf.size(), length - at));
        if (!readAt(fd, buf.data(), n, at))
            return Status(StatusCode::kIoError,
                          path + ": read failed at byte " + std::to_string(at));
        if (std::string e = checker.feed({buf.data(), n}); !e.empty())
            return Status(StatusCode::kChecksumError, path + ": " + e);
        at += n;
    }
    if (std::string e = checker.finish(); !e.empty())
        return Status(StatusCode::kTruncated, path + ": " + e);
    return Status::ok();
}

// The bytes of one field's bytestream not yet decoded, across packets (values may straddle them).
struct BitStream {
    std::vector<std::uint8_t> bytes;
    std::uint64_t bit = 0;  // next unread bit in `bytes`
    std::uint64_t available(unsigned bits) const {
        return bits == 0 ? 0 : (bytes.size() * 8 - bit) / bits;
    }
    std::uint64_t take(unsigned bits) {  // least significant bit first (E57 9.4.5)
        std::uint64_t v = 0;
        for (unsigned got = 0; got < bits;) {
            const unsigned off = static_cast<unsigned>(bit % 8);
            const unsigned k = std::min(8 - off, bits - got);
            const std::uint64_t part = (bytes[bit / 8] >> off) & ((1u << k) - 1);
            v |= part << got;
            got += k;
            bit += k;
        }
        return v;
    }
    void compact() {
        bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bit / 8));
        bit %= 8;
    }
};

double decodeValue(const E57Field& f, BitStream& s) {
    if (f.kind == E57Field::Kind::kFloat) {
        const std::uint8_t* p = s.bytes.data() + s.bit / 8;  // floats are byte-aligned
        s.bit += f.bits;
        return f.single ? double(getLe<float>(p)) : getLe<double>(p);
    }
    const std::int64_t raw =
        static_cast<std::int64_t>(s.take(f.bits) + static_cast<std::uint64_t>(f.minimum));
    return f.kind == E57Field::Kind::kInteger ? double(raw) : double(raw) * f.scale + f.offset;
}

}  // namespace

int E57CompressedVector::field(const std::string& name) const {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

Result<E57Reader> E57Reader::open(const std::string& path, bool check_pages) {
    Fd fd(path);
    if (fd.get() < 0)
        return Status(StatusCode::kNotFound, path + ": cannot open: " + std::strerror(errno));
    std::uint8_t h[kFileHeaderBytes];
    if (!readAt(fd.get(), h, sizeof h, 0) || std::memcmp(h, kSignature, 8) != 0)
        return Status(StatusCode::kProtocolError,
                      path + ": not an E57 file (no ASTM-E57 signature)");
    E57Reader r;
    r.path_ = path;
    E57File& f = r.file_;
    f.version_major = getLe<std::uint32_t>(h + 8);
    f.version_minor = getLe<std::uint32_t>(h + 12);
    f.physical_length = getLe<std::uint64_t>(h + 16);
    f.xml_offset = getLe<std::uint64_t>(h + 24);
    f.xml_length = getLe<std::uint64_t>(h + 32);
    const std::uint64_t page_size = getLe<std::uint64_t>(h + 40);
    f.pages = f.physical_length / kPageBytes;
    if (f.version_major != 1 || page_size != kPageBytes) {
        return Status(StatusCode::kUnsupported,
                      path + ": E57 version " + std::to_string(f.version_major) + "." +
                          std::to_string(f.version_minor) + " with " + std::to_string(page_size) +
                          "-byte pages (expected 1.x with 1024)");
    }
    const off_t size = ::lseek(fd.get(), 0, SEEK_END);
    if (size < 0 || static_cast<std::uint64_t>(size) != f.physical_length) {
        return Status(StatusCode::kTruncated,
                      path + ": the header says " + std::to_string(f.physical_length) +
                          " bytes, the file has " + std::to_string(size) + " (truncated?)");
    }
    if (f.xml_offset + f.xml_length > f.physical_length || f.xml_length > (64u << 20))
        return Status(StatusCode::kProtocolError, path + ": the XML section lies outside the file");
    if (check_pages) {
        if (Status s = checkPages(fd.get(), path, f.physical_length); !s.isOk()) return s;
    }
    std::vector<std::uint8_t> xml;
    if (!readLogical(fd.get(), logicalOf(f.xml_offset), static_cast<std::size_t>(f.xml_length),
                     xml))
        return Status(StatusCode::kIoError, path + ": cannot read the XML section");
    if (Status s = parseXml(std::string(xml.begin(), xml.end()), path, f); !s.isOk()) return s;
    return r;
}

Status E57Reader::read(const E57CompressedVector& v, const Sink& sink) const {
    Fd fd(path_);
    const std::string where =
        path_ + ": compressed vector at byte " + std::to_string(v.file_offset);
    auto bad = [&](const std::string& what) {
        return Status(StatusCode::kProtocolError, where + ": " + what);
    };
    if (fd.get() < 0) return Status(StatusCode::kNotFound, path_ + ": cannot open");
    const std::uint64_t section = logicalOf(v.file_offset);
    std::vector<std::uint8_t> buf;
    if (!readLogical(fd.get(), section, kSectionHeaderBytes, buf) ||
        buf[0] != kSectionCompressedVector)
        return bad("no compressed vector section header there");
    const std::uint64_t end = section + getLe<std::uint64_t>(buf.data() + 8);
    std::uint64_t at = logicalOf(getLe<std::uint64_t>(buf.data() + 16));
    const std::size_t nf = v.fields.size();
    std::vector<BitStream> streams(nf);
    std::vector<std::vector<double>> pending(nf), block(nf);
    std::vector<std::uint64_t> decoded(nf, 0);
    std::uint64_t emitted = 0;
    while (emitted < v.records) {
        if (at + 4 > end)
            return bad("ends after " + std::to_string(emitted) + " of " +
                       std::to_string(v.records) + " records");
        if (!readLogical(fd.get(), at, 4, buf)) return bad("read failed");
        const std::size_t length = getLe<std::uint16_t>(buf.data() + 2) + 1u;
        if (buf[0] == kPacketData) {
            if (!readLogical(fd.get(), at, length, buf)) return bad("read failed");
            const std::size_t count = getLe<std::uint16_t>(buf.data() + 4);
            if (count != nf)
                return bad("a data packet has " + std::to_string(count) + " bytestreams for " +
                           std::to_string(nf) + " fields");
            std::size_t from = kDataPacketHeaderBytes + 2 * count;
            for (std::size_t i = 0; i < nf; ++i) {
                const std::size_t n =
                    getLe<std::uint16_t>(buf.data() + kDataPacketHeaderBytes + 2 * i);
                if (from + n > length) return bad("a bytestream runs past its packet");
                streams[i].bytes.insert(streams[i].bytes.end(),
                                        buf.begin() + static_cast<std::ptrdiff_t>(from),
                                        buf.begin() + static_cast<std::ptrdiff_t>(from + n));
                from += n;
            }
        } else if (buf[0] != kPacketIndex && buf[0] != kPacketEmpty) {
            return bad("unknown packet type " + std::to_string(buf[0]) + " at logical byte " +
                       std::to_string(at));
        }
        at += length;
        // Decode every whole value (never past the record count: the last byte's padding bits).
        std::size_t ready = std::numeric_limits<std::size_t>::max();
        for (std::size_t i = 0; i < nf; ++i) {
            const E57Field& f = v.fields[i];
            if (f.bits == 0) continue;
            const std::uint64_t n = std::min(streams[i].available(f.bits), v.records - decoded[i]);
            for (std::uint64_t k = 0; k < n; ++k) pending[i].push_back(decodeValue(f, streams[i]));
            decoded[i] += n;
            streams[i].compact();
            ready = std::min(ready, pending[i].size());
        }
        if (ready == std::numeric_limits<std::size_t>::max()) return bad("no field has any bits");
        if (ready == 0) continue;
        for (std::size_t i = 0; i < nf; ++i) {
            if (v.fields[i].bits == 0) {
                block[i].assign(ready, double(v.fields[i].minimum));
                continue;
            }
            block[i].assign(pending[i].begin(),
                            pending[i].begin() + static_cast<std::ptrdiff_t>(ready));
            pending[i].erase(pending[i].begin(),
                             pending[i].begin() + static_cast<std::ptrdiff_t>(ready));
        }
        sink(block, ready);
        emitted += ready;
    }
    return Status::ok();
}

}  // namespace handscan::exporter

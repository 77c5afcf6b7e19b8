// Little-endian primitives of MCAP serialisation: an appending writer and a bounds-checked reader
// (every read reports failure instead of running past the end, so truncated input is safe).
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace handscan::recording::detail {

class ByteWriter {
public:
    explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}

    void u8(std::uint8_t v) { out_.push_back(v); }
    void u16(std::uint16_t v) { le(v, 2); }
    void u32(std::uint32_t v) { le(v, 4); }
    void u64(std::uint64_t v) { le(v, 8); }
    void i32(std::int32_t v) { le(static_cast<std::uint32_t>(v), 4); }
    void i64(std::int64_t v) { le(static_cast<std::uint64_t>(v), 8); }
    void f32(float v) { le(std::bit_cast<std::uint32_t>(v), 4); }
    void f64(double v) { le(std::bit_cast<std::uint64_t>(v), 8); }
    void bytes(std::span<const std::uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }
    void string(std::string_view s) {
        u32(static_cast<std::uint32_t>(s.size()));
        out_.insert(out_.end(), s.begin(), s.end());
    }
    std::size_t size() const { return out_.size(); }
    // Overwrites a u32/u64 written earlier at `pos` (length prefixes known only afterwards).
    void patchU32(std::size_t pos, std::uint32_t v) { patch(pos, v, 4); }
    void patchU64(std::size_t pos, std::uint64_t v) { patch(pos, v, 8); }

private:
    void le(std::uint64_t v, int n) {
        for (int i = 0; i < n; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    }
    void patch(std::size_t pos, std::uint64_t v, int n) {
        for (int i = 0; i < n; ++i)
            out_[pos + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
    }
    std::vector<std::uint8_t>& out_;
};

class ByteReader {
public:
    explicit ByteReader(std::span<const std::uint8_t> in) : in_(in) {}

    bool u8(std::uint8_t& v) { return le(v); }
    bool u16(std::uint16_t& v) { return le(v); }
    bool u32(std::uint32_t& v) { return le(v); }
    bool u64(std::uint64_t& v) { return le(v); }
    bool i64(std::int64_t& v) {
        std::uint64_t u = 0;
        if (!le(u)) return false;
        v = static_cast<std::int64_t>(u);
        return true;
    }
    bool i32(std::int32_t& v) {
        std::uint32_t u = 0;
        if (!le(u)) return false;
        v = static_cast<std::int32_t>(u);
        return true;
    }
    bool f32(float& v) {
        std::uint32_t u = 0;
        if (!le(u)) return false;
        v = std::bit_cast<float>(u);
        return true;
    }
    bool f64(double& v) {
        std::uint64_t u = 0;
        if (!le(u)) return false;
        v = std::bit_cast<double>(u);
        return true;
    }
    bool bytes(std::size_t n, std::span<const std::uint8_t>& out) {
        if (remaining() < n) return false;
        out = in_.subspan(pos_, n);
        pos_ += n;
        return true;
    }
    bool string(std::string& s) {
        std::uint32_t n = 0;
        std::span<const std::uint8_t> b;
        if (!u32(n) || !bytes(n, b)) return false;
        s.assign(reinterpret_cast<const char*>(b.data()), b.size());
        return true;
    }
    bool skip(std::size_t n) {
        if (remaining() < n) return false;
        pos_ += n;
        return true;
    }
    std::size_t remaining() const { return in_.size() - pos_; }
    std::size_t position() const { return pos_; }

private:
    template <typename T>
    bool le(T& v) {
        if (remaining() < sizeof(T)) return false;
        std::uint64_t acc = 0;
        for (std::size_t i = 0; i < sizeof(T); ++i)
            acc |= static_cast<std::uint64_t>(in_[pos_ + i]) << (8 * i);
        v = static_cast<T>(acc);
        pos_ += sizeof(T);
        return true;
    }
    std::span<const std::uint8_t> in_;
    std::size_t pos_ = 0;
};

}  // namespace handscan::recording::detail

// A serial tty as a ByteStream: termios raw mode (no line discipline: no echo, no canonical
// buffering, no CR/LF translation, no software flow control), 8 data bits, no parity, one stop
// bit, no hardware flow control, at one of the standard rates up to 921600 baud (the Xbus rates).
// Reads wait in poll() for the timeout; VMIN = VTIME = 0 so read() itself never blocks and returns
// what the driver holds. The port is opened exclusively (TIOCEXCL) and flushed on open.
#pragma once

#include <optional>
#include <string>

#include "handscan/transport/byte_stream.hpp"

namespace handscan::transport {

struct SerialConfig {
    std::string path;  // /dev/ttyUSB0, /dev/serial/by-id/..., a pty slave in tests
    int baud = 921600;
    bool exclusive = true;  // TIOCEXCL: refuse other openers while we hold the port
};

class SerialStream : public ByteStream {
public:
    explicit SerialStream(SerialConfig config) : cfg_(std::move(config)) {}
    ~SerialStream() override;
    SerialStream(const SerialStream&) = delete;
    SerialStream& operator=(const SerialStream&) = delete;

    Status open() override;
    void close() override;
    bool isOpen() const override { return fd_ >= 0; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override;
    Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) override;
    std::string describe() const override;

    // Switches the line rate of an open port (after the device acknowledged SetBaudrate).
    Status setBaudrate(int baud);
    // True when `baud` is a rate this transport can set (9600 ... 921600, 2000000, 4000000).
    static bool supportsBaudrate(int baud);
    int fd() const { return fd_; }

private:
    Status applyTermios(int baud);

    SerialConfig cfg_;
    int fd_ = -1;
};

}  // namespace handscan::transport

// A byte-stream link to a device (TCP socket, serial tty, USB bulk endpoints, or a test double).
// Device state machines talk to a ByteStream and never to the OS, so tests and replay swap the
// transport, never the protocol code. Implementations live in this library (one file each);
// only they include socket / termios / libusb headers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::transport {

class ByteStream {
public:
    virtual ~ByteStream() = default;
    // (Re)connects. A stream that is already open is closed first.
    virtual Status open() = 0;
    virtual void close() = 0;
    virtual bool isOpen() const = 0;
    // Reads what is available, waiting at most `timeout`. Returns the number of bytes read (0 on
    // timeout) or kDisconnected when the peer went away.
    virtual Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) = 0;
    // Writes every byte or fails.
    virtual Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) = 0;
    // For messages: "tcp 192.168.0.10:10940", "serial /dev/ttyUSB0 921600".
    virtual std::string describe() const = 0;
};

}  // namespace handscan::transport

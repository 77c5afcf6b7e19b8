// TCP client link (the Hokuyo UTM-30LX-EW at 192.168.0.10:10940) and a loopback listener for fake
// devices in tests. Non-blocking connect with a timeout, poll()-based reads and writes, TCP_NODELAY
// (SCIP commands are a few bytes and must not wait for Nagle). Every error names host:port.
#pragma once

#include <memory>
#include <string>

#include "handscan/transport/byte_stream.hpp"

namespace handscan::transport {

class TcpStream final : public ByteStream {
public:
    TcpStream(std::string host, int port, TimeNs connect_timeout = 2 * kNsPerSec);
    ~TcpStream() override;
    TcpStream(const TcpStream&) = delete;
    TcpStream& operator=(const TcpStream&) = delete;

    Status open() override;
    void close() override;
    bool isOpen() const override { return fd_ >= 0; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override;
    Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) override;
    std::string describe() const override;

    // Wraps a connected socket (from TcpListener::accept); open() on it fails (no peer address to
    // dial), close() closes it.
    static std::unique_ptr<TcpStream> adopt(int fd, std::string peer);

private:
    std::string host_;
    int port_ = 0;
    TimeNs connect_timeout_;
    int fd_ = -1;
    bool adopted_ = false;
};

// Listens on a local address (127.0.0.1 by default; port 0 = an ephemeral port).
class TcpListener {
public:
    TcpListener() = default;
    ~TcpListener();
    TcpListener(const TcpListener&) = delete;
    TcpListener& operator=(const TcpListener&) = delete;

    Status listen(const std::string& address = "127.0.0.1", int port = 0);
    // Waits at most `timeout` for a client. nullptr (and an ok Result) on timeout.
    Result<std::unique_ptr<TcpStream>> accept(TimeNs timeout);
    void close();
    int port() const { return port_; }
    std::string describe() const;

private:
    int fd_ = -1;
    std::string address_;
    int port_ = 0;
};

}  // namespace handscan::transport

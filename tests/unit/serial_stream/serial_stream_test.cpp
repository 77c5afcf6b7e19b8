// SerialStream against a real pseudo-terminal: the termios settings it applies (read back from an
// independent descriptor of the same tty), every Xbus baud rate, bytes both ways unaltered (no
// CR/LF mapping, no echo, no XON/XOFF eating 0x11/0x13), timeouts, hang-up, clear open errors.
#include "handscan/transport/serial_stream.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <numeric>

namespace handscan::transport {
namespace {

// A pty pair in the kernel's default (cooked) mode, as a freshly plugged USB-serial adapter.
struct Pty {
    Pty() {
        master = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
        if (master < 0) return;
        char name[128];
        if (::grantpt(master) != 0 || ::unlockpt(master) != 0 ||
            ::ptsname_r(master, name, sizeof name) != 0) {
            ::close(master);
            master = -1;
            return;
        }
        path = name;
    }
    ~Pty() {
        if (master >= 0) ::close(master);
    }
    termios slaveTermios() const {
        const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
        termios t{};
        EXPECT_GE(fd, 0);
        EXPECT_EQ(::tcgetattr(fd, &t), 0);
        ::close(fd);
        return t;
    }
    int master = -1;
    std::string path;
};

#define REQUIRE_PTY(pty) \
    if ((pty).master < 0) GTEST_SKIP() << "no pseudo-terminals on this machine"

TEST(SerialStream, AppliesRaw8N1AtTheRequestedRate) {
    Pty pty;
    REQUIRE_PTY(pty);
    const termios before = pty.slaveTermios();
    ASSERT_NE(before.c_lflag & ICANON, 0u) << "expected a cooked pty to start from";
    SerialStream serial({pty.path, 921600});
    Status s = serial.open();
    ASSERT_TRUE(s.isOk()) << s.message();
    const termios t = pty.slaveTermios();
    EXPECT_EQ(::cfgetispeed(&t), static_cast<speed_t>(B921600));
    EXPECT_EQ(::cfgetospeed(&t), static_cast<speed_t>(B921600));
    EXPECT_EQ(t.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
    EXPECT_EQ(t.c_cflag & PARENB, 0u);
    EXPECT_EQ(t.c_cflag & CSTOPB, 0u);
    EXPECT_EQ(t.c_cflag & CRTSCTS, 0u);
    EXPECT_NE(t.c_cflag & CREAD, 0u);
    EXPECT_NE(t.c_cflag & CLOCAL, 0u);
    EXPECT_EQ(t.c_lflag & (ICANON | ECHO | ECHONL | ISIG | IEXTEN), 0u);
    EXPECT_EQ(t.c_iflag & (IXON | IXOFF | IXANY | ICRNL | INLCR | IGNCR | ISTRIP | BRKINT | PARMRK),
              0u);
    EXPECT_EQ(t.c_oflag & OPOST, 0u);
    EXPECT_EQ(t.c_cc[VMIN], 0);
    EXPECT_EQ(t.c_cc[VTIME], 0);
    EXPECT_EQ(serial.describe(), "serial " + pty.path + " 921600");
}

TEST(SerialStream, EveryXbusRate) {
    Pty pty;
    REQUIRE_PTY(pty);
    const std::pair<int, speed_t> rates[] = {
        {9600, B9600},     {19200, B19200},   {38400, B38400},   {57600, B57600},
        {115200, B115200}, {230400, B230400}, {460800, B460800}, {921600, B921600}};
    for (const auto& [baud, speed] : rates) {
        SerialStream serial({pty.path, baud});
        ASSERT_TRUE(serial.open().isOk()) << baud;
        const termios t = pty.slaveTermios();
        EXPECT_EQ(::cfgetispeed(&t), speed) << baud;
    }
    SerialStream serial({pty.path, 115200});
    ASSERT_TRUE(serial.open().isOk());
    ASSERT_TRUE(serial.setBaudrate(921600).isOk());
    const termios t = pty.slaveTermios();
    EXPECT_EQ(::cfgetospeed(&t), static_cast<speed_t>(B921600));
    EXPECT_EQ(serial.describe(), "serial " + pty.path + " 921600");
    Status bad = serial.setBaudrate(12345);
    EXPECT_EQ(bad.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(bad.message().find("12345"), std::string::npos);
}

TEST(SerialStream, EveryByteValuePassesUnalteredBothWays) {
    Pty pty;
    REQUIRE_PTY(pty);
    SerialStream serial({pty.path, 921600});
    ASSERT_TRUE(serial.open().isOk());
    std::vector<std::uint8_t> all(256);
    std::iota(all.begin(), all.end(), std::uint8_t{0});
    // device -> host
    ASSERT_EQ(::write(pty.master, all.data(), all.size()), 256);
    std::vector<std::uint8_t> got;
    std::vector<std::uint8_t> buf(64);
    for (int i = 0; i < 100 && got.size() < all.size(); ++i) {
        auto n = serial.read(buf, 100 * kNsPerMs);
        ASSERT_TRUE(n.isOk()) << n.status().message();
        got.insert(got.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(*n));
    }
    EXPECT_EQ(got, all);
    // host -> device (and nothing echoed back to the host)
    ASSERT_TRUE(serial.writeAll(all, kNsPerSec).isOk());
    std::vector<std::uint8_t> at_device(512);
    std::size_t have = 0;
    for (int i = 0; i < 100 && have < 256; ++i) {
        const ssize_t n = ::read(pty.master, at_device.data() + have, at_device.size() - have);
        if (n > 0) have += static_cast<std::size_t>(n);
    }
    at_device.resize(have);
    EXPECT_EQ(at_device, all);
    auto echo = serial.read(buf, 20 * kNsPerMs);
    ASSERT_TRUE(echo.isOk());
    EXPECT_EQ(*echo, 0u);
}

TEST(SerialStream, ReadTimesOutWithZeroBytes) {
    Pty pty;
    REQUIRE_PTY(pty);
    SerialStream serial({pty.path, 921600});
    ASSERT_TRUE(serial.open().isOk());
    std::vector<std::uint8_t> buf(16);
    const TimeNs t0 = monotonicNow();
    auto n = serial.read(buf, 30 * kNsPerMs);
    const TimeNs waited = monotonicNow() - t0;
    ASSERT_TRUE(n.isOk());
    EXPECT_EQ(*n, 0u);
    EXPECT_GE(waited, 25 * kNsPerMs);
    EXPECT_LT(waited, 500 * kNsPerMs);
}

TEST(SerialStream, HangUpIsADisconnect) {
    Pty pty;
    REQUIRE_PTY(pty);
    SerialStream serial({pty.path, 921600});
    ASSERT_TRUE(serial.open().isOk());
    ::close(pty.master);
    pty.master = -1;
    std::vector<std::uint8_t> buf(16);
    auto n = serial.read(buf, 100 * kNsPerMs);
    ASSERT_FALSE(n.isOk());
    EXPECT_EQ(n.status().code(), StatusCode::kDisconnected);
    EXPECT_NE(n.status().message().find(pty.path), std::string::npos);
}

TEST(SerialStream, OpenErrorsSayWhatAndWhere) {
    SerialStream missing({"/dev/handscan-no-such-tty", 921600});
    Status s = missing.open();
    EXPECT_EQ(s.code(), StatusCode::kNotFound);
    EXPECT_NE(s.message().find("/dev/handscan-no-such-tty"), std::string::npos);
    EXPECT_NE(s.message().find("plugged"), std::string::npos);
    SerialStream not_a_tty({"/dev/null", 921600});
    s = not_a_tty.open();
    EXPECT_FALSE(s.isOk());
    EXPECT_FALSE(not_a_tty.isOpen());
    Pty pty;
    REQUIRE_PTY(pty);
    SerialStream odd({pty.path, 12345});
    s = odd.open();
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
    EXPECT_FALSE(odd.isOpen());
    std::vector<std::uint8_t> buf(4);
    EXPECT_EQ(odd.read(buf, 0).status().code(), StatusCode::kDisconnected);
}

}  // namespace
}  // namespace handscan::transport

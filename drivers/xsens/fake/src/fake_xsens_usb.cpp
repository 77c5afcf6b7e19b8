#include "handscan/xsens_fake/fake_xsens_usb.hpp"

#include <algorithm>
#include <cstdio>

namespace handscan::xsens {
namespace {

constexpr std::uint8_t kBulkIn = 0x81;
constexpr std::uint8_t kBulkOut = 0x02;
constexpr int kMaxPacket = 64;
constexpr transport::UsbDeviceInfo kMti{0x2639, 0x0002, 1, 7};
constexpr transport::UsbDeviceInfo kMouse{0x046d, 0xc077, 1, 3};

}  // namespace

int FakeXsensUsbLayer::init() {
    calls.push_back("init");
    return transport::usb::kSuccess;
}

int FakeXsensUsbLayer::listDevices(std::vector<transport::UsbDeviceInfo>& out) {
    calls.push_back("list");
    out.push_back(kMouse);
    if (plugged_in) out.push_back(kMti);
    return static_cast<int>(out.size());
}

int FakeXsensUsbLayer::open(const transport::UsbDeviceInfo& d) {
    calls.push_back("open " + std::to_string(d.bus) + ":" + std::to_string(d.address));
    if (!plugged_in || d.address != kMti.address) return transport::usb::kErrorNoDevice;
    open_ = true;
    return transport::usb::kSuccess;
}

void FakeXsensUsbLayer::close() {
    calls.push_back("close");
    open_ = false;
    claimed_ = false;
}

int FakeXsensUsbLayer::endpoints(std::vector<transport::UsbEndpoint>& out) {
    if (!open_) return transport::usb::kErrorNoDevice;
    out.push_back({0, 0x83, 0x03, 8});  // CDC notification (interrupt) on interface 0
    out.push_back({1, kBulkIn, transport::usb::kTransferTypeBulk, kMaxPacket});
    out.push_back({1, kBulkOut, transport::usb::kTransferTypeBulk, kMaxPacket});
    return transport::usb::kSuccess;
}

int FakeXsensUsbLayer::kernelDriverActive(int itf) {
    return itf == 1 && kernel_driver_bound ? 1 : 0;
}

int FakeXsensUsbLayer::detachKernelDriver(int itf) {
    calls.push_back("detach " + std::to_string(itf));
    kernel_driver_bound = false;
    return transport::usb::kSuccess;
}

int FakeXsensUsbLayer::claimInterface(int itf) {
    calls.push_back("claim " + std::to_string(itf));
    if (interface_busy || kernel_driver_bound) return transport::usb::kErrorBusy;
    claimed_ = true;
    return transport::usb::kSuccess;
}

int FakeXsensUsbLayer::releaseInterface(int itf) {
    calls.push_back("release " + std::to_string(itf));
    claimed_ = false;
    return transport::usb::kSuccess;
}

int FakeXsensUsbLayer::clearHalt(std::uint8_t ep) {
    char b[16];
    std::snprintf(b, sizeof b, "clear_halt 0x%02x", ep);
    calls.push_back(b);
    return transport::usb::kSuccess;
}

int FakeXsensUsbLayer::bulkTransfer(std::uint8_t ep, std::uint8_t* data, int length,
                                    int* transferred, unsigned /*timeout_ms*/) {
    *transferred = 0;
    if (!plugged_in) return transport::usb::kErrorNoDevice;
    if (!claimed_) return transport::usb::kErrorIo;
    if (ep == kBulkOut) {
        device_.receive(std::span<const std::uint8_t>(data, static_cast<std::size_t>(length)));
        *transferred = length;
        return transport::usb::kSuccess;
    }
    if (ep != kBulkIn) return transport::usb::kErrorInvalidParam;
    if (length % kMaxPacket != 0) return transport::usb::kErrorOverflow;  // libusb would overflow
    if (stall_next_reads > 0) {
        --stall_next_reads;
        return transport::usb::kErrorPipe;
    }
    if (pending_.empty()) {
        if (!device_.hasOutput()) device_.emitPacket();
        pending_ = device_.takeOutput();
        if (pending_.empty()) return transport::usb::kErrorTimeout;
    }
    // One transfer ends at a short packet: hand out what is pending, up to the buffer.
    const std::size_t n = std::min(pending_.size(), static_cast<std::size_t>(length));
    std::copy_n(pending_.begin(), n, data);
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
    *transferred = static_cast<int>(n);
    return transport::usb::kSuccess;
}

std::string FakeXsensUsbLayer::errorName(int code) {
    switch (code) {
        case transport::usb::kErrorNoDevice:
            return "LIBUSB_ERROR_NO_DEVICE";
        case transport::usb::kErrorBusy:
            return "LIBUSB_ERROR_BUSY";
        case transport::usb::kErrorTimeout:
            return "LIBUSB_ERROR_TIMEOUT";
        case transport::usb::kErrorPipe:
            return "LIBUSB_ERROR_PIPE";
        case transport::usb::kErrorIo:
            return "LIBUSB_ERROR_IO";
        default:
            return "LIBUSB_ERROR_" + std::to_string(code);
    }
}

}  // namespace handscan::xsens

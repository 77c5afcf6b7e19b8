// A fake libusb device layer with the fake MTi-20 behind it: the USB device list holds an
// unrelated device and the MTi (2639:0002) whose interface 1 has bulk endpoints 0x81 (IN) and
// 0x02 (OUT) held by the kernel's xsens_mt driver until detached. Bulk IN transfers return the
// device's bytes in whole 64-byte packets, streaming as fast as they are read. Faults: unplug,
// interface busy, a stall on the IN endpoint. It records the libusb calls made, in order.
#pragma once

#include <string>
#include <vector>

#include "handscan/transport/usb_stream.hpp"
#include "handscan/xsens_fake/fake_xsens.hpp"

namespace handscan::xsens {

class FakeXsensUsbLayer : public transport::UsbDeviceLayer {
public:
    explicit FakeXsensUsbLayer(FakeXsens& device) : device_(device) {}

    int init() override;
    void exit() override { calls.push_back("exit"); }
    int listDevices(std::vector<transport::UsbDeviceInfo>& out) override;
    int open(const transport::UsbDeviceInfo& device) override;
    void close() override;
    int endpoints(std::vector<transport::UsbEndpoint>& out) override;
    int kernelDriverActive(int interface_number) override;
    int detachKernelDriver(int interface_number) override;
    int claimInterface(int interface_number) override;
    int releaseInterface(int interface_number) override;
    int clearHalt(std::uint8_t endpoint) override;
    int bulkTransfer(std::uint8_t endpoint, std::uint8_t* data, int length, int* transferred,
                     unsigned timeout_ms) override;
    std::string errorName(int code) override;

    std::vector<std::string> calls;  // "init", "open 1:7", "detach 1", "claim 1", "bulk 0x81", ...
    bool plugged_in = true;
    bool interface_busy = false;
    int stall_next_reads = 0;
    bool kernel_driver_bound = true;

private:
    FakeXsens& device_;
    std::vector<std::uint8_t> pending_;
    bool open_ = false;
    bool claimed_ = false;
};

}  // namespace handscan::xsens

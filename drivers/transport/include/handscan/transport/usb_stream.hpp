// USB bulk endpoints as a ByteStream (Xsens MTi over USB: vendor 0x2639, the interface with a
// bulk IN and a bulk OUT endpoint). UsbStream talks to libusb only through UsbDeviceLayer, a thin
// interface with one method per libusb call it uses and libusb's return codes, so that a fake
// device layer can test the stream logic without hardware; makeLibusbDeviceLayer() is the real
// one (built when HANDSCAN_WITH_LIBUSB).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "handscan/transport/byte_stream.hpp"

namespace handscan::transport {

// libusb's return codes (libusb.h enum libusb_error); the libusb layer checks they match.
namespace usb {
constexpr int kSuccess = 0;
constexpr int kErrorIo = -1;
constexpr int kErrorInvalidParam = -2;
constexpr int kErrorAccess = -3;
constexpr int kErrorNoDevice = -4;
constexpr int kErrorNotFound = -5;
constexpr int kErrorBusy = -6;
constexpr int kErrorTimeout = -7;
constexpr int kErrorOverflow = -8;
constexpr int kErrorPipe = -9;
constexpr int kErrorInterrupted = -10;
constexpr int kErrorNoMem = -11;
constexpr int kErrorNotSupported = -12;
constexpr std::uint8_t kEndpointIn = 0x80;        // LIBUSB_ENDPOINT_IN (address bit 7)
constexpr std::uint8_t kTransferTypeMask = 0x03;  // LIBUSB_TRANSFER_TYPE_MASK
constexpr std::uint8_t kTransferTypeBulk = 0x02;  // LIBUSB_TRANSFER_TYPE_BULK
}  // namespace usb

struct UsbDeviceInfo {
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::uint8_t bus = 0;
    std::uint8_t address = 0;
};

struct UsbEndpoint {
    int interface_number = 0;
    std::uint8_t address = 0;     // bit 7 set: IN
    std::uint8_t attributes = 0;  // bits 0-1: transfer type
    std::uint16_t max_packet_size = 0;
};

// One method per libusb call UsbStream makes; ints are libusb return codes.
class UsbDeviceLayer {
public:
    virtual ~UsbDeviceLayer() = default;
    virtual int init() = 0;   // libusb_init
    virtual void exit() = 0;  // libusb_exit
    virtual int listDevices(
        std::vector<UsbDeviceInfo>& out) = 0;           // libusb_get_device_list + _descriptor
    virtual int open(const UsbDeviceInfo& device) = 0;  // libusb_open
    virtual void close() = 0;                           // libusb_close
    virtual int endpoints(
        std::vector<UsbEndpoint>& out) = 0;  // libusb_get_active_config_descriptor
    virtual int kernelDriverActive(int interface_number) = 0;  // libusb_kernel_driver_active
    virtual int detachKernelDriver(int interface_number) = 0;  // libusb_detach_kernel_driver
    virtual int claimInterface(int interface_number) = 0;      // libusb_claim_interface
    virtual int releaseInterface(int interface_number) = 0;    // libusb_release_interface
    virtual int clearHalt(std::uint8_t endpoint) = 0;          // libusb_clear_halt
    virtual int bulkTransfer(std::uint8_t endpoint, std::uint8_t* data, int length,
                             int* transferred,
                             unsigned timeout_ms) = 0;  // libusb_bulk_transfer
    virtual std::string errorName(int code) = 0;        // libusb_error_name
};

#if defined(HANDSCAN_WITH_LIBUSB) && HANDSCAN_WITH_LIBUSB
std::unique_ptr<UsbDeviceLayer> makeLibusbDeviceLayer();
#endif

struct UsbConfig {
    std::uint16_t vendor_id = 0x2639;         // Xsens
    std::optional<std::uint16_t> product_id;  // any product of the vendor when unset
};

class UsbStream : public ByteStream {
public:
    UsbStream(UsbConfig config, std::unique_ptr<UsbDeviceLayer> layer);
    ~UsbStream() override;
    UsbStream(const UsbStream&) = delete;
    UsbStream& operator=(const UsbStream&) = delete;

    Status open() override;
    void close() override;
    bool isOpen() const override { return open_; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override;
    Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) override;
    std::string describe() const override;

private:
    Status fail(StatusCode code, const std::string& what, int rc);

    UsbConfig cfg_;
    std::unique_ptr<UsbDeviceLayer> layer_;
    bool initialised_ = false;
    bool open_ = false;
    bool detached_kernel_driver_ = false;
    UsbDeviceInfo device_;
    int interface_ = -1;
    UsbEndpoint in_;
    UsbEndpoint out_;
    std::vector<std::uint8_t> rx_;  // whole USB packets as received
    std::size_t rx_head_ = 0;
    std::size_t rx_size_ = 0;
};

}  // namespace handscan::transport

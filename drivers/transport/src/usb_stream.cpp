// UsbStream over UsbDeviceLayer, and (with HANDSCAN_WITH_LIBUSB) the libusb device layer.
#include "handscan/transport/usb_stream.hpp"

#include <algorithm>
#include <cstdio>

#if defined(HANDSCAN_WITH_LIBUSB) && HANDSCAN_WITH_LIBUSB
#include <libusb.h>
#endif

namespace handscan::transport {
namespace {

constexpr std::size_t kRxBuffer = 4096;  // a multiple of every bulk max packet size (64, 512)

unsigned timeoutMs(TimeNs timeout) {
    // 0 means "no timeout" to libusb: wait at least 1 ms instead.
    return static_cast<unsigned>(
        std::clamp<TimeNs>((timeout + kNsPerMs - 1) / kNsPerMs, 1, 60'000));
}

std::string hex4(std::uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof b, "%04x", v);
    return b;
}

bool isBulk(const UsbEndpoint& e) {
    return (e.attributes & usb::kTransferTypeMask) == usb::kTransferTypeBulk;
}

}  // namespace

UsbStream::UsbStream(UsbConfig config, std::unique_ptr<UsbDeviceLayer> layer)
    : cfg_(config), layer_(std::move(layer)), rx_(kRxBuffer) {}

UsbStream::~UsbStream() {
    close();
    if (initialised_) layer_->exit();
}

std::string UsbStream::describe() const {
    std::string s =
        "usb " + hex4(cfg_.vendor_id) + ":" + (cfg_.product_id ? hex4(*cfg_.product_id) : "*");
    if (open_)
        s += " (bus " + std::to_string(device_.bus) + " address " +
             std::to_string(device_.address) + ")";
    return s;
}

Status UsbStream::fail(StatusCode code, const std::string& what, int rc) {
    return {code, describe() + ": " + what + ": " + layer_->errorName(rc)};
}

Status UsbStream::open() {
    close();
    if (!initialised_) {
        if (int rc = layer_->init(); rc != usb::kSuccess)
            return fail(StatusCode::kIoError, "libusb_init", rc);
        initialised_ = true;
    }
    // 1. Find the device.
    std::vector<UsbDeviceInfo> devices;
    if (int rc = layer_->listDevices(devices); rc < 0)
        return fail(StatusCode::kIoError, "listing USB devices", rc);
    const auto it = std::find_if(devices.begin(), devices.end(), [&](const UsbDeviceInfo& d) {
        return d.vendor_id == cfg_.vendor_id &&
               (!cfg_.product_id || d.product_id == *cfg_.product_id);
    });
    if (it == devices.end()) {
        return {StatusCode::kNotFound,
                describe() + ": no such device among " + std::to_string(devices.size()) +
                    " USB devices; is the MTi plugged in (lsusb shows 2639:xxxx)?"};
    }
    device_ = *it;
    if (int rc = layer_->open(device_); rc != usb::kSuccess) {
        return fail(StatusCode::kIoError,
                    rc == usb::kErrorAccess
                        ? "libusb_open (no permission: install the udev rule for 2639:*)"
                        : "libusb_open",
                    rc);
    }
    // 2. The interface with a bulk IN and a bulk OUT endpoint (interface 1 on the MTi; the
    // kernel's xsens_mt driver binds to the same one).
    std::vector<UsbEndpoint> eps;
    if (int rc = layer_->endpoints(eps); rc != usb::kSuccess) {
        layer_->close();
        return fail(StatusCode::kIoError, "reading the configuration descriptor", rc);
    }
    for (const auto& e : eps) {
        if (!isBulk(e) || (e.address & usb::kEndpointIn) == 0) continue;
        const auto out = std::find_if(eps.begin(), eps.end(), [&](const UsbEndpoint& o) {
            return o.interface_number == e.interface_number && isBulk(o) &&
                   (o.address & usb::kEndpointIn) == 0;
        });
        if (out != eps.end()) {
            in_ = e;
            out_ = *out;
            interface_ = e.interface_number;
            break;
        }
    }
    if (interface_ < 0) {
        layer_->close();
        return {StatusCode::kProtocolError,
                describe() + ": no interface with bulk IN and OUT endpoints; not an MTi?"};
    }
    // 3. Take the interface from the kernel driver (xsens_mt / usbserial) if it holds it.
    if (layer_->kernelDriverActive(interface_) == 1) {
        if (int rc = layer_->detachKernelDriver(interface_); rc != usb::kSuccess) {
            Status s = fail(
                StatusCode::kIoError,
                "detaching the kernel driver from interface " + std::to_string(interface_), rc);
            layer_->close();
            interface_ = -1;
            return s;
        }
        detached_kernel_driver_ = true;
    }
    if (int rc = layer_->claimInterface(interface_); rc != usb::kSuccess) {
        Status s = fail(StatusCode::kIoError,
                        "claiming interface " + std::to_string(interface_) +
                            (rc == usb::kErrorBusy ? " (another process holds it)" : ""),
                        rc);
        layer_->close();
        interface_ = -1;
        return s;
    }
    open_ = true;
    rx_head_ = rx_size_ = 0;
    return Status::ok();
}

void UsbStream::close() {
    if (!open_ && interface_ < 0) return;
    if (interface_ >= 0) {
        layer_->releaseInterface(interface_);
        interface_ = -1;
    }
    layer_->close();
    open_ = false;
    detached_kernel_driver_ = false;
}

Result<std::size_t> UsbStream::read(std::span<std::uint8_t> buffer, TimeNs timeout) {
    if (!open_) return Status{StatusCode::kDisconnected, describe() + ": not open"};
    if (rx_head_ == rx_size_) {
        // Always ask for whole packets: a short buffer would make libusb report an overflow.
        int got = 0;
        const int rc = layer_->bulkTransfer(in_.address, rx_.data(), static_cast<int>(rx_.size()),
                                            &got, timeoutMs(timeout));
        if (rc == usb::kErrorNoDevice) {
            open_ = false;
            return Status{StatusCode::kDisconnected, describe() + ": the device was unplugged"};
        }
        if (rc == usb::kErrorPipe) {
            layer_->clearHalt(
                in_.address);  // a stalled endpoint: clear it and let the caller retry
            return std::size_t{0};
        }
        if (rc != usb::kSuccess && rc != usb::kErrorTimeout && rc != usb::kErrorInterrupted) {
            return fail(StatusCode::kIoError, "bulk read", rc);
        }
        rx_head_ = 0;
        rx_size_ = static_cast<std::size_t>(std::max(got, 0));
    }
    const std::size_t n = std::min(buffer.size(), rx_size_ - rx_head_);
    std::copy_n(rx_.begin() + static_cast<std::ptrdiff_t>(rx_head_), n, buffer.begin());
    rx_head_ += n;
    return n;
}

Status UsbStream::writeAll(std::span<const std::uint8_t> data, TimeNs timeout) {
    if (!open_) return {StatusCode::kDisconnected, describe() + ": not open"};
    const TimeNs deadline = monotonicNow() + timeout;
    std::size_t done = 0;
    std::vector<std::uint8_t> chunk;
    while (done < data.size()) {
        chunk.assign(data.begin() + static_cast<std::ptrdiff_t>(done), data.end());
        int sent = 0;
        const int rc =
            layer_->bulkTransfer(out_.address, chunk.data(), static_cast<int>(chunk.size()), &sent,
                                 timeoutMs(deadline - monotonicNow()));
        done += static_cast<std::size_t>(std::max(sent, 0));
        if (rc == usb::kErrorNoDevice) {
            open_ = false;
            return {StatusCode::kDisconnected, describe() + ": the device was unplugged"};
        }
        if (rc == usb::kErrorTimeout && monotonicNow() >= deadline && done < data.size()) {
            return {StatusCode::kTimeout, describe() + ": bulk write timed out with " +
                                              std::to_string(data.size() - done) + " bytes unsent"};
        }
        if (rc != usb::kSuccess && rc != usb::kErrorTimeout)
            return fail(StatusCode::kIoError, "bulk write", rc);
    }
    return Status::ok();
}

#if defined(HANDSCAN_WITH_LIBUSB) && HANDSCAN_WITH_LIBUSB

static_assert(usb::kErrorIo == LIBUSB_ERROR_IO && usb::kErrorNoDevice == LIBUSB_ERROR_NO_DEVICE &&
              usb::kErrorTimeout == LIBUSB_ERROR_TIMEOUT && usb::kErrorPipe == LIBUSB_ERROR_PIPE &&
              usb::kErrorBusy == LIBUSB_ERROR_BUSY && usb::kErrorAccess == LIBUSB_ERROR_ACCESS &&
              usb::kErrorOverflow == LIBUSB_ERROR_OVERFLOW &&
              usb::kErrorInterrupted == LIBUSB_ERROR_INTERRUPTED &&
              usb::kEndpointIn == LIBUSB_ENDPOINT_IN &&
              usb::kTransferTypeBulk == LIBUSB_TRANSFER_TYPE_BULK &&
              usb::kTransferTypeMask == LIBUSB_TRANSFER_TYPE_MASK);

namespace {

class LibusbDeviceLayer : public UsbDeviceLayer {
public:
    ~LibusbDeviceLayer() override {
        close();
        exit();
    }
    int init() override { return libusb_init(&ctx_); }
    void exit() override {
        if (ctx_ != nullptr) libusb_exit(ctx_);
        ctx_ = nullptr;
    }
    int listDevices(std::vector<UsbDeviceInfo>& out) override {
        libusb_device** list = nullptr;
        const ssize_t n = libusb_get_device_list(ctx_, &list);
        if (n < 0) return static_cast<int>(n);
        for (ssize_t i = 0; i < n; ++i) {
            libusb_device_descriptor d{};
            if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
            out.push_back({d.idVendor, d.idProduct, libusb_get_bus_number(list[i]),
                           libusb_get_device_address(list[i])});
        }
        libusb_free_device_list(list, 1);
        return static_cast<int>(out.size());
    }
    int open(const UsbDeviceInfo& info) override {
        libusb_device** list = nullptr;
        const ssize_t n = libusb_get_device_list(ctx_, &list);
        if (n < 0) return static_cast<int>(n);
        int rc = LIBUSB_ERROR_NO_DEVICE;
        for (ssize_t i = 0; i < n; ++i) {
            if (libusb_get_bus_number(list[i]) == info.bus &&
                libusb_get_device_address(list[i]) == info.address) {
                rc = libusb_open(list[i], &handle_);
                break;
            }
        }
        libusb_free_device_list(list, 1);
        return rc;
    }
    void close() override {
        if (handle_ != nullptr) libusb_close(handle_);
        handle_ = nullptr;
    }
    int endpoints(std::vector<UsbEndpoint>& out) override {
        libusb_config_descriptor* config = nullptr;
        const int rc = libusb_get_active_config_descriptor(libusb_get_device(handle_), &config);
        if (rc != 0) return rc;
        for (int i = 0; i < config->bNumInterfaces; ++i) {
            const libusb_interface& itf = config->interface[i];
            if (itf.num_altsetting < 1) continue;
            const libusb_interface_descriptor& alt = itf.altsetting[0];
            for (int e = 0; e < alt.bNumEndpoints; ++e) {
                const libusb_endpoint_descriptor& ep = alt.endpoint[e];
                out.push_back({alt.bInterfaceNumber, ep.bEndpointAddress, ep.bmAttributes,
                               ep.wMaxPacketSize});
            }
        }
        libusb_free_config_descriptor(config);
        return 0;
    }
    int kernelDriverActive(int itf) override { return libusb_kernel_driver_active(handle_, itf); }
    int detachKernelDriver(int itf) override { return libusb_detach_kernel_driver(handle_, itf); }
    int claimInterface(int itf) override { return libusb_claim_interface(handle_, itf); }
    int releaseInterface(int itf) override { return libusb_release_interface(handle_, itf); }
    int clearHalt(std::uint8_t ep) override { return libusb_clear_halt(handle_, ep); }
    int bulkTransfer(std::uint8_t ep, std::uint8_t* data, int length, int* transferred,
                     unsigned timeout_ms) override {
        return libusb_bulk_transfer(handle_, ep, data, length, transferred, timeout_ms);
    }
    std::string errorName(int code) override { return libusb_error_name(code); }

private:
    libusb_context* ctx_ = nullptr;
    libusb_device_handle* handle_ = nullptr;
};

}  // namespace

std::unique_ptr<UsbDeviceLayer> makeLibusbDeviceLayer() {
    return std::make_unique<LibusbDeviceLayer>();
}

#endif

}  // namespace handscan::transport

// The real UsbStream (the code above libusb) and the real XsensDevice against the fake MTi-20
// behind a fake libusb device layer: device discovery among other USB devices, kernel driver
// detach, interface claim, whole-packet bulk reads, samples equal to what was streamed, stall
// recovery, unplug, and clear errors.
#include <gtest/gtest.h>

#include "handscan/transport/usb_stream.hpp"
#include "handscan/xsens/xsens_device.hpp"
#include "handscan/xsens_fake/fake_xsens_usb.hpp"

namespace handscan::xsens {
namespace {

struct UsbRig {
    UsbRig() {
        auto owned = std::make_unique<FakeXsensUsbLayer>(fake);
        layer = owned.get();
        stream = std::make_unique<transport::UsbStream>(transport::UsbConfig{}, std::move(owned));
        device = std::make_unique<XsensDevice>(*stream);
    }
    FakeXsens fake;
    FakeXsensUsbLayer* layer = nullptr;
    std::unique_ptr<transport::UsbStream> stream;
    std::unique_ptr<XsensDevice> device;
};

TEST(XsensUsbHil, OpensTheMtiDetachesTheKernelDriverAndStreams) {
    UsbRig rig;
    Status s = rig.device->configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    const std::vector<std::string> first{"init", "list", "open 1:7", "detach 1", "claim 1"};
    ASSERT_GE(rig.layer->calls.size(), first.size());
    EXPECT_EQ(std::vector<std::string>(rig.layer->calls.begin(), rig.layer->calls.begin() + 5),
              first);
    EXPECT_EQ(rig.stream->describe(), "usb 2639:* (bus 1 address 7)");
    EXPECT_EQ(rig.fake.rateHz(), 200);
    std::vector<ImuSample> samples;
    while (samples.size() < 500) ASSERT_TRUE(rig.device->poll(samples, 10 * kNsPerMs).isOk());
    std::vector<StreamedPacket> truth;
    for (const auto& p : rig.fake.streamed()) {
        if (p.epoch == rig.fake.epoch()) truth.push_back(p);
    }
    ASSERT_GE(truth.size(), samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        ASSERT_EQ(samples[i].packet_counter, truth[i].packet_counter) << i;
        ASSERT_EQ(samples[i].accel_mps2_imu.cast<float>(), truth[i].accel_mps2.cast<float>()) << i;
        ASSERT_EQ(samples[i].gyro_radps_imu.cast<float>(), truth[i].gyro_radps.cast<float>()) << i;
    }
    EXPECT_EQ(rig.device->stats().gaps, 0u);
}

TEST(XsensUsbHil, StallIsClearedAndUnplugIsADisconnect) {
    UsbRig rig;
    ASSERT_TRUE(rig.device->configure().isOk());
    std::vector<ImuSample> samples;
    rig.layer->stall_next_reads = 2;
    while (samples.size() < 20) ASSERT_TRUE(rig.device->poll(samples, 10 * kNsPerMs).isOk());
    EXPECT_EQ(std::count(rig.layer->calls.begin(), rig.layer->calls.end(), "clear_halt 0x81"), 2);
    EXPECT_EQ(rig.device->stats().gaps, 0u);
    rig.layer->plugged_in = false;
    Status s = rig.device->poll(samples, 10 * kNsPerMs);
    EXPECT_EQ(s.code(), StatusCode::kDisconnected);
    EXPECT_NE(s.message().find("unplugged"), std::string::npos) << s.message();
    // Plugged back in: configure() reopens and streaming resumes.
    rig.layer->plugged_in = true;
    rig.stream->close();
    ASSERT_TRUE(rig.device->configure().isOk());
    samples.clear();
    while (samples.size() < 20) ASSERT_TRUE(rig.device->poll(samples, 10 * kNsPerMs).isOk());
}

TEST(XsensUsbHil, ClearErrorsWhenAbsentOrBusy) {
    UsbRig rig;
    rig.layer->plugged_in = false;
    Status s = rig.stream->open();
    EXPECT_EQ(s.code(), StatusCode::kNotFound);
    EXPECT_NE(s.message().find("usb 2639:*"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("plugged in"), std::string::npos) << s.message();
    rig.layer->plugged_in = true;
    rig.layer->interface_busy = true;
    s = rig.stream->open();
    EXPECT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("claiming interface 1"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("LIBUSB_ERROR_BUSY"), std::string::npos) << s.message();
    EXPECT_FALSE(rig.stream->isOpen());
}

}  // namespace
}  // namespace handscan::xsens

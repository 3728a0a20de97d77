// The EGL device platform's choices as functions of the extension strings EGL reports, so that what a
// GPU driver answers is tested without the GPU: which client extensions suffice (EGL_EXT_device_base
// alone does, as NVIDIA lists it), which devices are worth a context (not Mesa's software device), and
// how a device is named.
#include <gtest/gtest.h>

#include "gl/EglDevices.h"

namespace tandem {
namespace {

using gl::EglDeviceInfo;

TEST(EglDevicesTest, ExtensionNamesMatchWhole) {
  EXPECT_TRUE(gl::hasEglExtension("EGL_EXT_device_base EGL_EXT_platform_device", "EGL_EXT_platform_device"));
  EXPECT_TRUE(gl::hasEglExtension("EGL_EXT_device_base", "EGL_EXT_device_base"));
  EXPECT_FALSE(gl::hasEglExtension("EGL_EXT_device_base_extra EGL_X", "EGL_EXT_device_base"));
  EXPECT_FALSE(gl::hasEglExtension("EGL_EXT_device_enumeration", "EGL_EXT_device"));
  EXPECT_FALSE(gl::hasEglExtension(nullptr, "EGL_EXT_device_base"));
  EXPECT_FALSE(gl::hasEglExtension("", "EGL_EXT_device_base"));
}

TEST(EglDevicesTest, DeviceBaseAloneIsEnough) {
  // NVIDIA's client extensions: the combined EGL_EXT_device_base, not the split names.
  EXPECT_TRUE(gl::checkEglDeviceClientExtensions(
                  "EGL_EXT_platform_base EGL_EXT_device_base EGL_EXT_platform_device EGL_KHR_debug")
                  .ok());
  // The split names alone, and all three (Mesa lists all three).
  EXPECT_TRUE(
      gl::checkEglDeviceClientExtensions("EGL_EXT_device_enumeration EGL_EXT_device_query EGL_EXT_platform_device").ok());
  EXPECT_TRUE(gl::checkEglDeviceClientExtensions("EGL_EXT_device_base EGL_EXT_device_enumeration "
                                                 "EGL_EXT_device_query EGL_EXT_platform_base EGL_EXT_platform_device")
                  .ok());
}

TEST(EglDevicesTest, MissingExtensionsAreNamed) {
  auto noPlatform = gl::checkEglDeviceClientExtensions("EGL_EXT_device_base EGL_EXT_platform_base");
  ASSERT_FALSE(noPlatform.ok());
  EXPECT_EQ(noPlatform.error().message, "the EGL client extensions lack EGL_EXT_platform_device");
  auto noQuery = gl::checkEglDeviceClientExtensions("EGL_EXT_device_enumeration EGL_EXT_platform_device");
  ASSERT_FALSE(noQuery.ok());
  EXPECT_EQ(noQuery.error().message,
            "the EGL client extensions lack EGL_EXT_device_query (or EGL_EXT_device_base)");
  auto none = gl::checkEglDeviceClientExtensions(nullptr);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message,
            "the EGL client extensions lack EGL_EXT_platform_device, EGL_EXT_device_enumeration (or "
            "EGL_EXT_device_base), EGL_EXT_device_query (or EGL_EXT_device_base)");
}

TEST(EglDevicesTest, SoftwareDevicesAreSkipped) {
  const EglDeviceInfo software{"EGL_MESA_device_software EGL_EXT_device_drm_render_node", ""};
  const EglDeviceInfo nvidia{"EGL_NV_device_cuda EGL_EXT_device_drm EGL_EXT_device_query_name",
                             "/dev/dri/card1, NVIDIA GeForce RTX 4090"};
  const EglDeviceInfo intel{"EGL_EXT_device_drm EGL_EXT_device_drm_render_node", "/dev/dri/renderD128"};
  // The first hardware device first, whatever EGL lists before it; later ones in order as fallbacks.
  auto chosen = gl::hardwareEglDevices({software, nvidia});
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  EXPECT_EQ(*chosen, (std::vector<std::size_t>{1}));
  chosen = gl::hardwareEglDevices({intel, software, nvidia});
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  EXPECT_EQ(*chosen, (std::vector<std::size_t>{0, 2}));
  // A device that lists no extensions at all is not known to be software: it is tried.
  chosen = gl::hardwareEglDevices({EglDeviceInfo{"", ""}});
  ASSERT_TRUE(chosen.ok());
  EXPECT_EQ(*chosen, (std::vector<std::size_t>{0}));
}

TEST(EglDevicesTest, OnlySoftwareDevicesIsAnErrorNamingThem) {
  // This machine class: Mesa lists llvmpipe alone.
  const EglDeviceInfo software{"EGL_MESA_device_software EGL_EXT_device_drm_render_node", ""};
  auto one = gl::hardwareEglDevices({software});
  ASSERT_FALSE(one.ok());
  EXPECT_EQ(one.error().message,
            "no hardware EGL device: EGL lists 1, and device 0 is a software renderer (EGL_MESA_device_software)");
  auto two = gl::hardwareEglDevices({software, software});
  ASSERT_FALSE(two.ok());
  EXPECT_EQ(two.error().message,
            "no hardware EGL device: EGL lists 2, and device 0 is a software renderer (EGL_MESA_device_software), "
            "device 1 is a software renderer (EGL_MESA_device_software)");
  auto none = gl::hardwareEglDevices({});
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message, "no hardware EGL device: EGL lists none");
}

TEST(EglDevicesTest, DescribesTheDevice) {
  std::vector<EglDeviceInfo> devices{{"EGL_MESA_device_software", ""},
                                     {"EGL_EXT_device_drm", "/dev/dri/card1, NVIDIA GeForce RTX 4090"}};
  EXPECT_EQ(gl::describeEglDevice(1, devices), "device 1 of 2 (/dev/dri/card1, NVIDIA GeForce RTX 4090)");
  EXPECT_EQ(gl::describeEglDevice(0, devices), "device 0 of 2");
}

}  // namespace
}  // namespace tandem

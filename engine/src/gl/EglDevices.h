#pragma once
// Choosing an EGL device for the device platform, as plain functions of the extension strings EGL
// reports (no EGL call here), so the choice is testable without a GPU.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "tandem/Result.h"

namespace tandem::gl {

/// Whether `name` is one of the space-separated names in `list` (a null list has none).
bool hasEglExtension(const char* list, std::string_view name);

/// What the device platform needs from the client extensions: EGL_EXT_platform_device (a display from a
/// device), device enumeration (eglQueryDevicesEXT) and device query (eglQueryDeviceStringEXT, to tell a
/// software device from a GPU). EGL_EXT_device_base is the older extension that is enumeration and query
/// in one; a driver may list it alone (NVIDIA's do), the split EGL_EXT_device_enumeration and
/// EGL_EXT_device_query alone, or all three. The error names everything missing.
Result<void> checkEglDeviceClientExtensions(const char* clientExtensions);

struct EglDeviceInfo {
  std::string extensions;  // eglQueryDeviceStringEXT(device, EGL_EXTENSIONS)
  std::string name;        // its DRM node and renderer where it says them (describeEglDevice), else ""
};

/// The devices worth a context, in EGL's order: every one that is not a software renderer (Mesa lists
/// llvmpipe as a device advertising EGL_MESA_device_software; surfaceless and OSMesa already give it).
/// The error says how many devices EGL listed and why each was passed over.
Result<std::vector<std::size_t>> hardwareEglDevices(const std::vector<EglDeviceInfo>& devices);

/// "device 1 of 2 (/dev/dri/renderD129, NVIDIA GeForce RTX 4090)", "device 0 of 1" without a name.
std::string describeEglDevice(std::size_t index, const std::vector<EglDeviceInfo>& devices);

}  // namespace tandem::gl

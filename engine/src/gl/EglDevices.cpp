#include "gl/EglDevices.h"

namespace tandem::gl {

bool hasEglExtension(const char* list, std::string_view name) {
  if (list == nullptr || name.empty()) return false;
  std::string_view rest(list);
  while (!rest.empty()) {
    std::size_t space = rest.find(' ');
    if (rest.substr(0, space) == name) return true;
    if (space == std::string_view::npos) break;
    rest.remove_prefix(space + 1);
  }
  return false;
}

Result<void> checkEglDeviceClientExtensions(const char* clientExtensions) {
  const bool base = hasEglExtension(clientExtensions, "EGL_EXT_device_base");
  std::string missing;
  auto lacks = [&](const char* what) { missing += (missing.empty() ? "" : ", ") + std::string(what); };
  if (!hasEglExtension(clientExtensions, "EGL_EXT_platform_device")) lacks("EGL_EXT_platform_device");
  if (!base && !hasEglExtension(clientExtensions, "EGL_EXT_device_enumeration"))
    lacks("EGL_EXT_device_enumeration (or EGL_EXT_device_base)");
  if (!base && !hasEglExtension(clientExtensions, "EGL_EXT_device_query"))
    lacks("EGL_EXT_device_query (or EGL_EXT_device_base)");
  if (missing.empty()) return {};
  return Error{"the EGL client extensions lack " + missing};
}

Result<std::vector<std::size_t>> hardwareEglDevices(const std::vector<EglDeviceInfo>& devices) {
  std::vector<std::size_t> chosen;
  std::string skipped;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (hasEglExtension(devices[i].extensions.c_str(), "EGL_MESA_device_software")) {
      skipped += (skipped.empty() ? ", and device " : ", device ") + std::to_string(i) +
                 " is a software renderer (EGL_MESA_device_software)";
      continue;
    }
    chosen.push_back(i);
  }
  if (!chosen.empty()) return chosen;
  if (devices.empty()) return Error{"no hardware EGL device: EGL lists none"};
  return Error{"no hardware EGL device: EGL lists " + std::to_string(devices.size()) + skipped};
}

std::string describeEglDevice(std::size_t index, const std::vector<EglDeviceInfo>& devices) {
  std::string text = "device " + std::to_string(index) + " of " + std::to_string(devices.size());
  if (index < devices.size() && !devices[index].name.empty()) text += " (" + devices[index].name + ")";
  return text;
}

}  // namespace tandem::gl

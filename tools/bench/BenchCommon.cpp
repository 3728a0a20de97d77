#include "BenchCommon.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <embree3/rtcore_config.h>
#include <tbb/info.h>

#include "core/Shading.h"
#include <glm/gtc/matrix_transform.hpp>

#include "tandem/HeavyScene.h"
#include "tandem/Primitives.h"
#include "tandem/SceneFile.h"

namespace tandem::bench {

Stat summarize(std::vector<double> v) {
  Stat s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  std::size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.min = v.front();
  s.max = v.back();
  return s;
}

Machine describeMachine() {
  Machine m;
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0) {
      auto colon = line.find(':');
      if (colon != std::string::npos) m.cpu = line.substr(colon + 2);
      break;
    }
  if (m.cpu.empty()) m.cpu = "unknown CPU";
  m.logicalCpus = static_cast<int>(std::thread::hardware_concurrency());
  m.tbbThreads = tbb::info::default_concurrency();
  const char* lp = std::getenv("LP_NUM_THREADS");
  m.lpNumThreads = lp ? std::string(lp) : std::string("unset (llvmpipe uses one thread per CPU)");
  m.embreeVersion = RTC_VERSION_STRING;
  return m;
}

double currentRssMiB() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: KiB
}

Image toDisplay(const ImageF& linear, const FrameSettings& s) {
  Image out;
  out.width = linear.width;
  out.height = linear.height;
  out.rgba.resize(linear.rgb.size() * 4);
  for (std::size_t i = 0; i < linear.rgb.size(); ++i) {
    glm::vec3 c = shading::tdSrgbEncode(shading::tdToneMap(s.exposure * linear.rgb[i], shading::toneMapOp(s.toneMap)));
    for (std::size_t k = 0; k < 3; ++k)
      out.rgba[i * 4 + k] = static_cast<std::uint8_t>(std::lround(std::clamp(c[static_cast<int>(k)], 0.0f, 1.0f) * 255.0f));
    out.rgba[i * 4 + 3] = 255;
  }
  return out;
}

Result<Scene> loadBenchScene(const std::string& spec) {
  if (spec.rfind("heavy:", 0) == 0) {
    char* end = nullptr;
    unsigned long long n = std::strtoull(spec.c_str() + 6, &end, 10);
    if (end == spec.c_str() + 6 || *end != '\0') return Error{"bad heavy scene spec '" + spec + "' (heavy:N)"};
    return makeHeavyScene(static_cast<std::size_t>(n));
  }
  if (spec.rfind("mirrors:", 0) == 0) {
    char* end = nullptr;
    const unsigned long long n = std::strtoull(spec.c_str() + 8, &end, 10);
    if (end == spec.c_str() + 8 || *end != '\0' || n == 0 || n > 100000)
      return Error{"bad mirrors scene spec '" + spec + "' (mirrors:N, N in 1..100000)"};
    Scene s;
    s.name = "mirrors-" + std::to_string(n);
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
    const float extent = 2.5f * static_cast<float>(side);
    s.meshes = {makePlane(glm::vec2(extent + 8.0f), 1), makeSphere(1.0f, 24, 12)};
    Material floor, mirror;
    floor.kd = floor.ka = glm::vec3(0.7f);
    mirror.kd = mirror.ka = glm::vec3(0.2f);
    mirror.ks = glm::vec3(0.5f);
    mirror.kr = 0.6f;
    s.materials = {floor, mirror};
    Instance ground;
    ground.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f * extent, 0.0f, 0.5f * extent));
    s.instances.push_back(ground);
    for (unsigned long long k = 0; k < n; ++k) {
      Instance ball;
      ball.mesh = 1;
      ball.material = 1;
      ball.dynamic = k == 0;  // the one the benchmark moves
      ball.worldFromObject = glm::translate(
          glm::mat4(1.0f), glm::vec3(2.5f * static_cast<float>(k % side), 1.0f, 2.5f * static_cast<float>(k / side)));
      s.instances.push_back(ball);
    }
    Light ambient, sun;
    ambient.type = LightType::Ambient;
    ambient.intensity = 0.1f;
    sun.type = LightType::Directional;
    sun.dirW = glm::normalize(glm::vec3(-0.5f, -1.0f, -0.3f));
    sun.intensity = 0.9f;
    s.lights = {ambient, sun};
    s.camera.posW = {0.5f * extent, 0.8f * extent + 3.0f, 1.2f * extent + 4.0f};
    s.camera.targetW = {0.5f * extent, 0.0f, 0.5f * extent};
    return s;
  }
  return loadAnyScene(spec);
}

std::string sceneLabel(const std::string& spec) {
  if (spec.rfind("heavy:", 0) == 0) return "heavy-" + spec.substr(6);
  return std::filesystem::path(spec).stem().string();
}

std::string sourceDir() {
#ifdef TANDEM_SOURCE_DIR
  return TANDEM_SOURCE_DIR;
#else
  return ".";
#endif
}

std::string formatDuration(double seconds) {
  auto s = static_cast<long>(std::lround(std::max(0.0, seconds)));
  char buf[32];
  if (s >= 60) std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  else std::snprintf(buf, sizeof buf, "%lds", s);
  return buf;
}

}  // namespace tandem::bench

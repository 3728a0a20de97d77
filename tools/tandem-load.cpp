// tandem-load: loads one file the way the renderer would (JSON scene, glTF/GLB, or an image) without GL or
// Embree, and prints what it holds and what the load cost. For checking assets, and for the resource tests,
// which run it in a child process to measure its peak memory and time.
//   tandem-load FILE            one line: counts, input bytes, budget use, peak RSS; exit 1 with a one-line error
//   tandem-load FILE --json     the same as a JSON object
#include <sys/resource.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tandem/Gltf.h"
#include "tandem/Image.h"
#include "tandem/Log.h"
#include "tandem/SceneFile.h"

using namespace tandem;

namespace {

// This process image's own peak: VmHWM. getrusage's ru_maxrss would also count the memory of the process
// that spawned it (posix_spawn shares the parent's memory until exec, and Linux keeps that peak).
long peakRssKiB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  bool asJson = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") asJson = true;
    else if (a == "-h" || a == "--help") {
      std::printf("usage: tandem-load FILE [--json]   (FILE: .json scene, .gltf/.glb, .png/.jpg image)\n");
      return 0;
    } else if (path.empty()) path = a;
    else {
      std::fprintf(stderr, "tandem-load: unexpected argument '%s'\n", a.c_str());
      return 2;
    }
  }
  if (path.empty()) {
    std::fprintf(stderr, "tandem-load: no file given (tandem-load FILE [--json])\n");
    return 2;
  }
  // Warnings are counted, not printed: a hostile file may ask for many.
  std::size_t warnings = 0;
  setLogSink([&](LogLevel level, std::string_view) { warnings += level == LogLevel::Warning; });

  const auto start = std::chrono::steady_clock::now();
  nlohmann::json out;
  out["file"] = path;
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  std::string error;
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") {
    auto img = readPng(path);
    if (!img) error = img.error().message;
    else out["image"] = {{"width", img->width}, {"height", img->height}};
  } else {
    Scene scene;
    if (ext == ".gltf" || ext == ".glb") {
      GltfOptions opt;
      opt.onWarning = [&](const std::string&) {};
      auto r = loadGltfAsset(path, opt);
      if (!r) {
        error = r.error().message;
      } else {
        out["inputBytes"] = r->stats.inputBytes;
        out["modelEstimate"] = r->stats.modelEstimate;
        out["decodedBytes"] = r->stats.decodedBytes;
        out["budgetBytes"] = r->stats.budgetBytes;
        scene = std::move(r->scene);
      }
    } else {
      auto r = loadAnyScene(path);
      if (!r) error = r.error().message;
      else scene = std::move(*r);
    }
    if (error.empty()) {
      std::size_t triangles = 0, bytes = 0, texels = 0;
      for (const Mesh& m : scene.meshes) {
        triangles += m.triangleCount();
        bytes += m.bytes();
      }
      for (const Texture& t : scene.textures) texels += t.rgba8.size() / 4;
      out["meshes"] = scene.meshes.size();
      out["triangles"] = triangles;
      out["meshBytes"] = bytes;
      out["materials"] = scene.materials.size();
      out["textures"] = scene.textures.size();
      out["texels"] = texels;
      out["instances"] = scene.instances.size();
      out["lights"] = scene.lights.size();
    }
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  out["ok"] = error.empty();
  if (!error.empty()) out["error"] = error;
  out["warnings"] = warnings;
  out["ms"] = ms;
  out["peakRssKiB"] = peakRssKiB();
  if (asJson) {
    std::printf("%s\n", out.dump().c_str());
  } else if (error.empty()) {
    std::string line;
    for (auto it = out.begin(); it != out.end(); ++it)
      if (it.key() != "file" && it.key() != "ok") line += " " + it.key() + "=" + it.value().dump();
    std::printf("%s:%s\n", path.c_str(), line.c_str());
  }
  if (!error.empty()) {
    std::fprintf(stderr, "tandem-load: %s\n", error.c_str());
    return 1;
  }
  return 0;
}

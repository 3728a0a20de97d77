// libFuzzer target over the glTF loader: each input is written as the main file of a small asset
// folder (with a sibling .bin and .png, so URIs have something real to resolve) and loaded.
// The loader must never crash, trip a sanitizer, or open a file outside that folder.
//
//   tandem-gltf-fuzz -dict=../shared/assets/cgltf-fuzz-seeds/fuzz/gltf.dict corpus/ ../shared/assets/cgltf-fuzz-seeds/fuzz/data
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "tandem/Gltf.h"
#include "tandem/Log.h"

namespace {

namespace fs = std::filesystem;

struct Folder {
  fs::path dir;
  Folder() {
    dir = fs::temp_directory_path() / ("tandem-gltf-fuzz-" + std::to_string(::getpid())) / "asset";
    fs::create_directories(dir);
    std::ofstream(dir / "buffer.bin", std::ios::binary) << std::string(256, '\x01');
    // A 1×1 PNG (valid signature and IHDR; the data need not decode).
    static const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                        0, 0, 0, 1, 0, 0, 0, 1, 8, 6, 0, 0, 0, 0x1f, 0x15, 0xc4, 0x89};
    std::ofstream(dir / "image.png", std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
    tandem::setLogSink([](tandem::LogLevel, std::string_view) {});
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Folder folder;
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const fs::path main = folder.dir / (glb ? "input.glb" : "input.gltf");
  {
    std::ofstream out(main, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  const std::string root = fs::canonical(folder.dir).string() + "/";
  tandem::GltfOptions opt;
  // Small caps keep each run fast; the checks are the same at any size.
  opt.limits.maxFileBytes = 4u << 20;
  opt.limits.maxImagePixels = 1u << 20;
  opt.limits.maxTotalPixels = 4u << 20;
  opt.limits.maxTriangles = 1u << 20;
  opt.limits.maxNodes = 1u << 16;
  opt.onFileOpened = [&](const std::string& f) {
    if (f.compare(0, root.size(), root) != 0) {
      std::fprintf(stderr, "opened outside the asset folder: %s\n", f.c_str());
      std::abort();
    }
  };
  auto r = tandem::loadGltfAsset(main.string(), opt);
  if (r) {
    // Touch the result the way the renderer would: the animation evaluator over every clip.
    for (std::size_t c = 0; c < r->animation.clips.size(); ++c) r->animation.apply(c, 0.5f, r->scene);
  }
  return 0;
}

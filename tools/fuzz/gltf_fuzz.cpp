// libFuzzer target over the glTF loader. Each input is the main file (.glb when it starts with the GLB
// magic, else .gltf) of a fresh asset folder holding real files its URIs may name (FuzzFolder.h). The
// loader must never crash, trip a sanitizer, exceed the RSS limit, or open a file outside that folder.
//
//   tandem-gltf-fuzz -dict=tests/fuzz/gltf.dict corpus/ tests/fuzz/seeds/gltf
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "FuzzFolder.h"
#include "tandem/Gltf.h"
#include "tandem/Log.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tandem::setLogSink([](tandem::LogLevel, std::string_view) {});
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tandem::fuzz::Folder folder;
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const auto main = folder.write(glb ? "input.glb" : "input.gltf", data, size);
  const std::string root = folder.dir().string() + "/";
  tandem::GltfOptions opt;
  // Small caps keep each run fast; the checks are the same at any size.
  opt.limits.maxFileBytes = 4u << 20;
  opt.limits.maxImagePixels = 1u << 20;
  opt.limits.maxTotalPixels = 4u << 20;
  opt.limits.maxTriangles = 1u << 20;
  opt.limits.maxNodes = 1u << 16;
  opt.limits.budgetBaseBytes = 64u << 20;
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

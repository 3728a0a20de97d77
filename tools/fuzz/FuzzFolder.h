#pragma once
// A fresh asset folder per fuzz input, removed afterwards, so every run of an input sees exactly the same
// files whatever ran before it: the input as the main file, and beside it real files its URIs can name —
// buffer.bin (a triangle's positions and indices), image.png (a real 2×2 PNG) and model.gltf (a small valid
// glTF using both, for scene-file placements).
#include <stdlib.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <stb/stb_image_write.h>

namespace tandem::fuzz {

inline const std::vector<std::uint8_t>& realPng() {
  static const std::vector<std::uint8_t> png = [] {
    const std::uint8_t px[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};
    std::vector<std::uint8_t> out;
    stbi_write_png_to_func(
        [](void* ctx, void* data, int size) {
          auto* o = static_cast<std::vector<std::uint8_t>*>(ctx);
          o->insert(o->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
        },
        &out, 2, 2, 4, px, 8);
    return out;
  }();
  return png;
}

inline std::vector<std::uint8_t> triangleBuffer() {
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t idx[4] = {0, 1, 2, 0};  // padded to 4 bytes
  std::vector<std::uint8_t> b(sizeof pos + sizeof idx);
  std::memcpy(b.data(), pos, sizeof pos);
  std::memcpy(b.data() + sizeof pos, idx, sizeof idx);
  return b;
}

inline const char* modelGltf() {
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
"materials":[{"name":"m","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
"textures":[{"source":0}],"images":[{"uri":"image.png"}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],
"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
"buffers":[{"byteLength":44,"uri":"buffer.bin"}]})";
}

class Folder {
 public:
  Folder() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/tandem-fuzz-XXXXXX";
    if (!::mkdtemp(pattern.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    dir_ = std::filesystem::canonical(pattern);
    write("buffer.bin", triangleBuffer());
    write("image.png", realPng());
    const char* m = modelGltf();
    write("model.gltf", std::vector<std::uint8_t>(m, m + std::strlen(m)));
  }
  ~Folder() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;

  std::filesystem::path write(const std::string& name, const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return p;
  }
  std::filesystem::path write(const std::string& name, const std::vector<std::uint8_t>& b) {
    return write(name, b.data(), b.size());
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace tandem::fuzz

#pragma once
// Small glTF files made by the tests themselves (no third-party assets): a builder for a JSON document
// with one base64 buffer, written into a fresh folder under outputDir().
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <stb/stb_image_write.h>

#include "support/TestSupport.h"
#include "tandem/Gltf.h"
#include "tandem/Log.h"

namespace tandem::test {

inline std::string base64(const std::vector<std::uint8_t>& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t(in[i]) << 16) | (std::uint32_t(in[i + 1]) << 8) | in[i + 2];
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += t[v & 63];
  }
  if (i + 1 == in.size()) {
    const std::uint32_t v = std::uint32_t(in[i]) << 16;
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    const std::uint32_t v = (std::uint32_t(in[i]) << 16) | (std::uint32_t(in[i + 1]) << 8);
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

/// A byte buffer that glTF accessors point into.
struct Bytes {
  std::vector<std::uint8_t> data;
  template <class T>
  std::size_t add(const std::vector<T>& v) {
    while (data.size() % 4) data.push_back(0);
    const std::size_t off = data.size();
    data.resize(off + v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(data.data() + off, v.data(), v.size() * sizeof(T));
    return off;
  }
  std::string dataUri() const { return "data:application/octet-stream;base64," + base64(data); }
};

/// A fresh, empty folder for one test's files.
inline std::filesystem::path freshDir(const std::string& name) {
  std::filesystem::path d = std::filesystem::path(outputDir()) / "gltf" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

inline std::string writeBytes(const std::filesystem::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
  return p.string();
}

/// A w×h PNG whose texel (x, y) (row 0 on top) is texel(x, y), RGBA (stb_image_write is compiled into
/// tandem_core).
template <class Texel>
std::vector<std::uint8_t> pngOf(int w, int h, Texel texel) {
  std::vector<std::uint8_t> px, out;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::array<std::uint8_t, 4> c = texel(x, y);
      px.insert(px.end(), c.begin(), c.end());
    }
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) {
        auto* o = static_cast<std::vector<std::uint8_t>*>(ctx);
        o->insert(o->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
      },
      &out, w, h, 4, px.data(), w * 4);
  return out;
}

/// A w×h PNG of flat grey.
inline std::vector<std::uint8_t> pngBytes(int w, int h) {
  return pngOf(w, h, [](int, int) { return std::array<std::uint8_t, 4>{200, 200, 200, 200}; });
}

/// One triangle in the XY plane (counter-clockwise seen from +Z), indexed with unsigned shorts.
/// accessors: 0 positions, 1 indices. bufferViews: 0 positions, 1 indices.
inline nlohmann::json triangleDoc(Bytes* outBytes = nullptr) {
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t i = b.add(std::vector<std::uint16_t>{0, 1, 2});
  nlohmann::json d = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
         {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 36}},
                       {{"buffer", 0}, {"byteOffset", i}, {"byteLength", 6}}}},
      {"buffers", {{{"byteLength", b.data.size()}, {"uri", b.dataUri()}}}}};
  if (outBytes) *outBytes = b;
  return d;
}

/// What one loadGltf did: success or the error, its warnings, every file it opened, and its real textures.
struct LoadOutcome {
  bool ok = false;
  std::string error;
  std::vector<std::string> warnings;
  std::vector<std::string> opened;
  int textures = 0;  // decoded ones, not the fallback
};

/// loadGltf(path) with the log silenced and every warning and opened file recorded.
inline LoadOutcome loadRecording(const std::string& path, GltfOptions opt = {}) {
  LoadOutcome o;
  opt.onWarning = [&](const std::string& w) { o.warnings.push_back(w); };
  opt.onFileOpened = [&](const std::string& f) { o.opened.push_back(f); };
  LogSink old = setLogSink([](LogLevel, std::string_view) {});
  auto r = loadGltf(path, opt);
  setLogSink(old);
  o.ok = r.ok();
  if (!r.ok()) o.error = r.error().message;
  else
    for (const Texture& t : r->textures) o.textures += t.name != "fallback" ? 1 : 0;
  return o;
}

}  // namespace tandem::test

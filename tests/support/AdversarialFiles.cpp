#include "support/AdversarialFiles.h"

#include <array>
#include <cstring>
#include <fstream>

#include "unit/GltfTestUtil.h"

namespace tandem::test {

namespace fs = std::filesystem;

namespace {

std::string dataUri(const std::vector<std::uint8_t>& b, const char* type = "application/octet-stream") {
  return std::string("data:") + type + ";base64," + base64(b);
}

void writeFile(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }
void writeFile(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// `n` copies of `item` joined by commas.
std::string repeat(const std::string& item, std::size_t n) {
  std::string s;
  s.reserve(n * (item.size() + 1));
  for (std::size_t i = 0; i < n; ++i) {
    if (i) s += ',';
    s += item;
  }
  return s;
}
// Items built per index, joined by commas, until the text reaches `bytes`.
std::string fill(std::size_t bytes, const std::function<std::string(std::size_t)>& item, std::size_t* count = nullptr) {
  std::string s;
  std::size_t i = 0;
  while (s.size() < bytes) {
    if (i) s += ',';
    s += item(i++);
  }
  if (count) *count = i;
  return s;
}

const char* kAsset = R"("asset":{"version":"2.0"})";

// A buffer of `n` positions (a fan of distinct points: finite, non-degenerate triangles).
std::vector<std::uint8_t> positions(std::size_t n) {
  std::vector<float> p(n * 3);
  for (std::size_t i = 0; i < n; ++i) {
    p[3 * i] = float(i % 97);
    p[3 * i + 1] = float((i / 97) % 89);
    p[3 * i + 2] = float(i % 3);
  }
  std::vector<std::uint8_t> b(p.size() * 4);
  std::memcpy(b.data(), p.data(), b.size());
  return b;
}

std::string triangleBufferJson() {
  return R"("buffers":[{"byteLength":36,"uri":")" + dataUri(positions(3)) +
         R"("}],"bufferViews":[{"buffer":0,"byteLength":36}],)"
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[2,1,2]}])";
}

std::uint32_t crc32(const std::uint8_t* p, std::size_t n, std::uint32_t c = 0xFFFFFFFFu) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t v = i;
      for (int k = 0; k < 8; ++k) v = v & 1 ? 0xEDB88320u ^ (v >> 1) : v >> 1;
      t[i] = v;
    }
    return t;
  }();
  for (std::size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xFF] ^ (c >> 8);
  return c;
}

void put32(std::vector<std::uint8_t>& o, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) o.push_back(std::uint8_t(v >> s));
}

void chunk(std::vector<std::uint8_t>& png, const char* type, const std::vector<std::uint8_t>& data) {
  put32(png, std::uint32_t(data.size()));
  const std::size_t start = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), data.begin(), data.end());
  put32(png, crc32(png.data() + start, png.size() - start) ^ 0xFFFFFFFFu);
}

std::vector<std::uint8_t> png(int w, int h, const std::vector<std::uint8_t>& zlib) {
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> ihdr;
  put32(ihdr, std::uint32_t(w));
  put32(ihdr, std::uint32_t(h));
  ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});  // 8-bit RGBA
  chunk(out, "IHDR", ihdr);
  chunk(out, "IDAT", zlib);
  chunk(out, "IEND", {});
  return out;
}

// A zlib stream of `n` zero bytes: one fixed-Huffman block of a literal and copies of 258 (13 bits each).
std::vector<std::uint8_t> zeroStream(std::size_t n) {
  std::vector<std::uint8_t> out = {0x78, 0x01};
  std::uint32_t acc = 0;
  int bits = 0;
  auto lsb = [&](std::uint32_t v, int count) {  // header fields: least significant bit first
    acc |= v << bits;
    bits += count;
    while (bits >= 8) {
      out.push_back(std::uint8_t(acc));
      acc >>= 8;
      bits -= 8;
    }
  };
  auto code = [&](std::uint32_t c, int count) {  // Huffman codes: most significant bit first
    for (int i = count - 1; i >= 0; --i) lsb((c >> i) & 1u, 1);
  };
  lsb(1, 1);     // final block
  lsb(1, 2);     // fixed Huffman
  code(0x30, 8);  // literal 0
  std::size_t made = 1;
  while (made + 258 <= n) {
    code(0xC5, 8);  // length 258 (code 285)
    code(0, 5);     // distance 1
    made += 258;
  }
  while (made < n) {
    code(0x30, 8);
    ++made;
  }
  code(0, 7);  // end of block
  if (bits) lsb(0, 8 - bits);
  // Adler-32 of n zeros: a = 1, b = n mod 65521.
  put32(out, std::uint32_t((n % 65521) << 16 | 1));
  return out;
}

std::string glbOf(const std::string& json, const std::vector<std::uint8_t>& bin) {
  std::string j = json;
  while (j.size() % 4) j += ' ';
  std::vector<std::uint8_t> b = bin;
  while (b.size() % 4) b.push_back(0);
  auto le = [](std::string& s, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xFF);
  };
  std::string out = "glTF";
  le(out, 2);
  le(out, std::uint32_t(12 + 8 + j.size() + 8 + b.size()));
  le(out, std::uint32_t(j.size()));
  le(out, 0x4E4F534Au);
  out += j;
  le(out, std::uint32_t(b.size()));
  le(out, 0x004E4942u);
  out.append(reinterpret_cast<const char*>(b.data()), b.size());
  return out;
}

std::vector<AdversarialCase> makeCases() {
  std::vector<AdversarialCase> c;
  // ---- glTF: the JSON itself ----
  c.push_back({"long-key-arrays", "one key of half the file holding empty arrays (the path copied per item)",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 writeFile(f, "{" + std::string(kAsset) + ",\"" + std::string(n / 2, 'k') + "\":[" +
                                  repeat("[]", n / 6) + "]}");
                 return f;
               }});
  c.push_back({"extras-wide", "extras holding empty arrays (a tinygltf::Value each)",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 writeFile(f, "{" + std::string(kAsset) + ",\"extras\":[" + repeat("[]", n / 3) + "]}");
                 return f;
               }});
  c.push_back({"deep-nesting", "arrays nested to the depth cap, over and over",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::string chain = std::string(60, '[') + std::string(60, ']');
                 writeFile(f, "{" + std::string(kAsset) + ",\"extras\":[" + repeat(chain, n / 121) + "]}");
                 return f;
               }});
  c.push_back({"tiny-objects", "empty materials, textures, samplers, cameras and nodes (kilobytes each in tinygltf)",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::size_t k = n / 15;
                 writeFile(f, "{" + std::string(kAsset) + ",\"materials\":[" + repeat("{}", k) + "],\"samplers\":[" +
                                  repeat("{}", k) + "],\"nodes\":[" + repeat("{}", k) + "],\"scenes\":[" +
                                  repeat("{}", k) + "],\"textures\":[" + repeat("{}", k) + "]}");
                 return f;
               }});
  c.push_back({"many-extensions", "every node carries hundreds of unknown extensions",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 std::string ext = "{\"extensions\":{" + fill(2000, [](std::size_t i) {
                                     return "\"X_" + std::to_string(i) + "\":{\"v\":[1,2]}";
                                   }) + "}}";
                 std::string used = fill(n / 10, [](std::size_t i) { return "\"X_" + std::to_string(i) + "\""; });
                 writeFile(f, "{" + std::string(kAsset) + ",\"extensionsUsed\":[" + used + "],\"nodes\":[" +
                                  repeat(ext, (n * 9 / 10) / ext.size() + 1) + "]}");
                 return f;
               }});
  // ---- glTF: references multiplied ----
  c.push_back({"node-fanout", "nodes × primitives instances (every node draws a mesh of many primitives)",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 std::size_t nodes = 0;
                 const std::string prims = repeat(R"({"attributes":{"POSITION":0}})", n / 60);
                 const std::string nodeList = fill(n / 2, [](std::size_t) { return std::string(R"({"mesh":0})"); }, &nodes);
                 std::string roots;
                 for (std::size_t i = 0; i < nodes; ++i) roots += (i ? "," : "") + std::to_string(i);
                 writeFile(f, "{" + std::string(kAsset) + "," + triangleBufferJson() + ",\"meshes\":[{\"primitives\":[" +
                                  prims + "]}],\"nodes\":[" + nodeList + "],\"scenes\":[{\"nodes\":[" + roots +
                                  "]}],\"scene\":0}");
                 return f;
               }});
  c.push_back({"gpu-instancing-fanout", "EXT_mesh_gpu_instancing × many primitives",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::size_t count = n / 3 / 12;  // a third of the file as translations (base64 4/3)
                 std::vector<float> t(count * 3);
                 for (std::size_t i = 0; i < t.size(); ++i) t[i] = float(i % 1000);
                 std::vector<std::uint8_t> b(t.size() * 4);
                 std::memcpy(b.data(), t.data(), b.size());
                 const std::string buf = R"("buffers":[{"byteLength":36,"uri":")" + dataUri(positions(3)) +
                                         R"("},{"byteLength":)" + std::to_string(b.size()) + R"(,"uri":")" +
                                         dataUri(b) + R"("}],"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":1,"byteLength":)" +
                                         std::to_string(b.size()) + R"(}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[2,1,2]},{"bufferView":1,"componentType":5126,"count":)" +
                                         std::to_string(count) + R"(,"type":"VEC3"}])";
                 const std::string prims = repeat(R"({"attributes":{"POSITION":0}})", n / 3 / 31);
                 writeFile(f, "{" + std::string(kAsset) + R"(,"extensionsUsed":["EXT_mesh_gpu_instancing"],)" + buf +
                                  ",\"meshes\":[{\"primitives\":[" + prims +
                                  R"(]}],"nodes":[{"mesh":0,"extensions":{"EXT_mesh_gpu_instancing":{"attributes":{"TRANSLATION":1}}}}],"scenes":[{"nodes":[0]}]})");
                 return f;
               }});
  c.push_back({"accessor-aliasing", "many accessors over one big buffer view, each its own mesh",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::size_t verts = (n / 2) * 3 / 4 / 12;  // half the file as base64 positions
                 const std::vector<std::uint8_t> b = positions(verts / 3 * 3);
                 const std::size_t k = (n / 2) / 150;
                 std::string acc, meshes, nodes, roots;
                 for (std::size_t i = 0; i < k; ++i) {
                   const std::string s = std::to_string(i);
                   acc += (i ? "," : "") + std::string(R"({"bufferView":0,"componentType":5126,"count":)") +
                          std::to_string(verts / 3 * 3) + R"(,"type":"VEC3"})";
                   meshes += (i ? "," : "") + std::string(R"({"primitives":[{"attributes":{"POSITION":)") + s + "}}]}";
                   nodes += (i ? "," : "") + std::string(R"({"mesh":)") + s + "}";
                   roots += (i ? "," : "") + s;
                 }
                 writeFile(f, "{" + std::string(kAsset) + R"(,"buffers":[{"byteLength":)" + std::to_string(b.size()) +
                                  R"(,"uri":")" + dataUri(b) + R"("}],"bufferViews":[{"buffer":0,"byteLength":)" +
                                  std::to_string(b.size()) + "}],\"accessors\":[" + acc + "],\"meshes\":[" + meshes +
                                  "],\"nodes\":[" + nodes + "],\"scenes\":[{\"nodes\":[" + roots + "]}]}");
                 return f;
               }});
  c.push_back({"shared-index-vertices", "primitives each drawing one triangle of one big shared vertex array",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::size_t verts = (n / 2) / 16;
                 std::vector<std::uint8_t> b = positions(verts);
                 const std::size_t idxOff = b.size();
                 for (std::uint32_t i = 0; i < 3; ++i)
                   for (int k = 0; k < 4; ++k) b.push_back(std::uint8_t((i >> (8 * k)) & 0xFF));
                 const std::string prims = repeat(R"({"attributes":{"POSITION":0},"indices":1})", (n / 2) / 40);
                 writeFile(f, "{" + std::string(kAsset) + R"(,"buffers":[{"byteLength":)" + std::to_string(b.size()) +
                                  R"(,"uri":")" + dataUri(b) + R"("}],"bufferViews":[{"buffer":0,"byteLength":)" +
                                  std::to_string(idxOff) + R"(},{"buffer":0,"byteOffset":)" + std::to_string(idxOff) +
                                  R"(,"byteLength":12}],"accessors":[{"bufferView":0,"componentType":5126,"count":)" +
                                  std::to_string(verts) +
                                  R"(,"type":"VEC3"},{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}],"meshes":[{"primitives":[)" +
                                  prims + R"(]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
                 return f;
               }});
  c.push_back({"viewless-accessors", "accessors without a bufferView (all zeros), each as large as the cap allows",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::size_t k = n / 200;
                 std::string acc, meshes, nodes, roots;
                 for (std::size_t i = 0; i < k; ++i) {
                   const std::string s = std::to_string(i);
                   acc += (i ? "," : "") + std::string(R"({"componentType":5126,"count":3000000,"type":"VEC3"})");
                   meshes += (i ? "," : "") + std::string(R"({"primitives":[{"attributes":{"POSITION":)") + s + "}}]}";
                   nodes += (i ? "," : "") + std::string(R"({"mesh":)") + s + "}";
                   roots += (i ? "," : "") + s;
                 }
                 writeFile(f, "{" + std::string(kAsset) + ",\"accessors\":[" + acc + "],\"meshes\":[" + meshes +
                                  "],\"nodes\":[" + nodes + "],\"scenes\":[{\"nodes\":[" + roots + "]}]}");
                 return f;
               }});
  c.push_back({"animation-shared-sampler", "many channels reading one large keyframe accessor",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::size_t keys = (n / 3) / 16 / 4 * 3;
                 std::vector<float> v(keys * 4);
                 for (std::size_t i = 0; i < keys; ++i) {
                   v[i] = float(i);  // times (strictly increasing) in the first quarter
                 }
                 std::vector<std::uint8_t> b(keys * 4 + keys * 12);
                 std::memcpy(b.data(), v.data(), keys * 4);
                 const std::string chans = repeat(R"({"sampler":0,"target":{"node":0,"path":"translation"}})", (n / 3) / 56);
                 writeFile(f, "{" + std::string(kAsset) + R"(,"buffers":[{"byteLength":)" + std::to_string(b.size()) +
                                  R"(,"uri":")" + dataUri(b) + R"("}],"bufferViews":[{"buffer":0,"byteLength":)" +
                                  std::to_string(keys * 4) + R"(},{"buffer":0,"byteOffset":)" + std::to_string(keys * 4) +
                                  R"(,"byteLength":)" + std::to_string(keys * 12) +
                                  R"(}],"accessors":[{"bufferView":0,"componentType":5126,"count":)" + std::to_string(keys) +
                                  R"(,"type":"SCALAR","min":[0],"max":[)" + std::to_string(keys - 1) +
                                  R"(]},{"bufferView":1,"componentType":5126,"count":)" + std::to_string(keys) +
                                  R"(,"type":"VEC3"}],"nodes":[{}],"scenes":[{"nodes":[0]}],"animations":[{"samplers":[{"input":0,"output":1}],"channels":[)" +
                                  chans + "]}]}");
                 return f;
               }});
  c.push_back({"glb-bin-buffers", "a GLB whose buffers all claim the BIN chunk",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.glb";
                 std::vector<std::uint8_t> bin(n / 2, 7);
                 const std::string bufs = repeat("{\"byteLength\":" + std::to_string(bin.size()) + "}", (n / 2) / 24);
                 writeFile(f, glbOf("{" + std::string(kAsset) + ",\"buffers\":[" + bufs + "]}", bin));
                 return f;
               }});
  c.push_back({"repeated-buffer-file", "many buffers naming one .bin file beside it",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 std::vector<std::uint8_t> bin(n / 2, 7);
                 writeFile(d / "data.bin", bin);
                 const std::string bufs =
                     repeat("{\"byteLength\":" + std::to_string(bin.size()) + ",\"uri\":\"data.bin\"}", (n / 2) / 45);
                 writeFile(f, "{" + std::string(kAsset) + ",\"buffers\":[" + bufs + "]}");
                 return f;
               }});
  // ---- glTF: images ----
  c.push_back({"shared-image", "many images and textures naming one large, highly compressible PNG",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 writeFile(d / "big.png", flatPng(4096, 4096));
                 const std::size_t k = (n - std::min<std::size_t>(n / 2, fs::file_size(d / "big.png"))) / 160;
                 std::string images, textures, materials;
                 for (std::size_t i = 0; i < k; ++i) {
                   const std::string s = std::to_string(i);
                   images += (i ? "," : "") + std::string(R"({"uri":"big.png"})");
                   textures += (i ? "," : "") + std::string(R"({"source":)") + s + "}";
                   materials += (i ? "," : "") + std::string(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)") + s +
                                R"(},"metallicRoughnessTexture":{"index":)" + s + "}}}";
                 }
                 writeFile(f, "{" + std::string(kAsset) + ",\"images\":[" + images + "],\"textures\":[" + textures +
                                  "],\"materials\":[" + materials + "]}");
                 return f;
               }});
  c.push_back({"image-headers", "PNGs declaring 60000² pixels, and one 1×1 PNG whose zlib stream inflates 150×",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "a.gltf";
                 const std::vector<std::uint8_t> bomb = pngBomb(1, 1, n / 2 * 150);
                 const std::string huge = dataUri(pngHeaderOnly(60000, 60000), "image/png");
                 std::string images = R"({"uri":")" + dataUri(bomb, "image/png") + "\"}";
                 std::size_t k = 1;
                 while (images.size() < n) {
                   images += R"(,{"uri":")" + huge + "\"}";
                   ++k;
                 }
                 std::string textures, materials;
                 for (std::size_t i = 0; i < k; ++i) {
                   const std::string s = std::to_string(i);
                   textures += (i ? "," : "") + std::string(R"({"source":)") + s + "}";
                   materials += (i ? "," : "") + std::string(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)") + s + "}}}";
                 }
                 writeFile(f, "{" + std::string(kAsset) + ",\"images\":[" + images + "],\"textures\":[" + textures +
                                  "],\"materials\":[" + materials + "]}");
                 return f;
               }});
  // ---- the JSON scene file ----
  auto triangleGltf = [](const fs::path& d) {
    writeFile(d / "tri.gltf", "{" + std::string(kAsset) + "," + triangleBufferJson() +
                                  R"(,"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
  };
  c.push_back({"scene-placements", "one glTF file placed many times", [triangleGltf](const fs::path& d, std::size_t n) {
                 triangleGltf(d);
                 const fs::path f = d / "s.json";
                 writeFile(f, R"({"instances":[)" + repeat(R"({"gltf":"tri.gltf"})", n / 20) + "]}");
                 return f;
               }});
  c.push_back({"scene-placements-big", "a large glTF file placed many times (its meshes shared, not copied)",
               [](const fs::path& d, std::size_t n) {
                 const std::size_t verts = (n / 2) / 16;
                 const std::vector<std::uint8_t> b = positions(verts / 3 * 3);
                 writeFile(d / "big.gltf", "{" + std::string(kAsset) + R"(,"buffers":[{"byteLength":)" +
                                               std::to_string(b.size()) + R"(,"uri":")" + dataUri(b) +
                                               R"("}],"bufferViews":[{"buffer":0,"byteLength":)" + std::to_string(b.size()) +
                                               R"(}],"accessors":[{"bufferView":0,"componentType":5126,"count":)" +
                                               std::to_string(verts / 3 * 3) +
                                               R"(,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
                 const fs::path f = d / "s.json";
                 writeFile(f, R"({"instances":[)" + repeat(R"({"gltf":"big.gltf"})", (n / 2) / 20) + "]}");
                 return f;
               }});
  c.push_back({"scene-primitives", "meshes tessellated as finely as one primitive may be",
               [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "s.json";
                 writeFile(f, R"({"meshes":{)" + fill(n, [](std::size_t i) {
                                return "\"m" + std::to_string(i) + R"(":{"primitive":"sphere","segments":2048,"rings":1024})";
                              }) + "}}");
                 return f;
               }});
  c.push_back({"scene-flattened-gltf", "scene meshes each flattening a glTF file of many instances",
               [](const fs::path& d, std::size_t n) {
                 // fan.gltf: one 1000-triangle mesh drawn by many nodes; each scene mesh merges all of them.
                 const std::vector<std::uint8_t> b = positions(3000);
                 std::size_t nodes = 0;
                 const std::string nodeList = fill(n / 4, [](std::size_t) { return std::string(R"({"mesh":0})"); }, &nodes);
                 std::string roots;
                 for (std::size_t i = 0; i < nodes; ++i) roots += (i ? "," : "") + std::to_string(i);
                 writeFile(d / "fan.gltf", "{" + std::string(kAsset) + R"(,"buffers":[{"byteLength":)" +
                                               std::to_string(b.size()) + R"(,"uri":")" + dataUri(b) +
                                               R"("}],"bufferViews":[{"buffer":0,"byteLength":)" + std::to_string(b.size()) +
                                               R"(}],"accessors":[{"bufferView":0,"componentType":5126,"count":3000,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[)" +
                                               nodeList + R"(],"scenes":[{"nodes":[)" + roots + "]}]}");
                 const fs::path f = d / "s.json";
                 writeFile(f, R"({"meshes":{)" + fill(n / 4, [](std::size_t i) {
                                return "\"m" + std::to_string(i) + R"(":{"gltf":"fan.gltf"})";
                              }) + "}}");
                 return f;
               }});
  // ---- images on their own ----
  c.push_back({"png-bomb", "a 1×1 PNG whose zlib stream inflates 150× its size", [](const fs::path& d, std::size_t n) {
                 const fs::path f = d / "bomb.png";
                 writeFile(f, pngBomb(1, 1, n * 150));
                 return f;
               }});
  c.push_back({"png-huge-header", "a PNG declaring 60000² pixels", [](const fs::path& d, std::size_t) {
                 const fs::path f = d / "huge.png";
                 writeFile(f, pngHeaderOnly(60000, 60000));
                 return f;
               }});
  return c;
}

}  // namespace

std::vector<std::uint8_t> pngBomb(int w, int h, std::size_t inflatedBytes) { return png(w, h, zeroStream(inflatedBytes)); }

std::vector<std::uint8_t> pngHeaderOnly(int w, int h) { return png(w, h, zeroStream(std::size_t(w) * 4 + 1)); }

std::vector<std::uint8_t> flatPng(int w, int h) { return pngBytes(w, h); }

std::uint64_t folderBytes(const fs::path& dir) {
  std::uint64_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) n += e.file_size();
  return n;
}

const std::vector<AdversarialCase>& adversarialCases() {
  static const std::vector<AdversarialCase> cases = makeCases();
  return cases;
}

}  // namespace tandem::test

// Confinement of glTF file access (docs/gltf.md, "Confined file access"): a buffer or image uri reaches only
// files under the asset's own folder, whatever the spelling. Each case is tried for a buffer and for an image:
// a sibling folder whose name starts with the asset folder's (a string-prefix test would let it in), case
// variants of the folder's name, '.' and '..' mixed, symlinks out of the folder (to a sibling-prefix folder
// too) and an asset folder reached through a symlinked parent (loads inside it still work). An escape attempt
// fails the load with a message naming the uri.
#include <gtest/gtest.h>

#include <filesystem>

#include "tandem/Gltf.h"
#include "tandem/Log.h"
#include "unit/GltfTestUtil.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::Bytes;
using test::freshDir;
using test::pngBytes;
using test::triangleDoc;
using test::writeBytes;
using test::writeText;

using Loaded = test::LoadOutcome;

Loaded load(const fs::path& gltf) { return test::loadRecording(gltf.string()); }

// Files the load opened outside `folder` (by path components, not by string prefix).
std::vector<std::string> openedOutside(const Loaded& o, const fs::path& folder) {
  const fs::path root = fs::canonical(folder);
  std::vector<std::string> out;
  for (const std::string& f : o.opened) {
    const fs::path p = fs::path(f).lexically_normal();
    auto r = root.begin();
    auto q = p.begin();
    bool inside = true;
    for (; r != root.end(); ++r, ++q)
      if (q == p.end() || *q != *r) inside = false;
    if (!inside) out.push_back(f);
  }
  return out;
}

// A triangle whose buffer is `bufferUri` and whose material's base colour is the image `imageUri` (either may be
// empty: the buffer then lives in "tri.bin", no image).
json document(const std::string& bufferUri, const std::string& imageUri, std::vector<std::uint8_t>* bin) {
  Bytes b;
  json d = triangleDoc(&b);
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", bufferUri.empty() ? "tri.bin" : bufferUri}};
  *bin = b.data;
  if (!imageUri.empty()) {
    d["images"] = {{{"uri", imageUri}}};
    d["textures"] = {{{"source", 0}}};
    d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    d["meshes"][0]["primitives"][0]["material"] = 0;
  }
  return d;
}

// The asset folder `base/asset` and its sibling-prefix neighbour `base/asset-evil`, each with a buffer and an
// image; returns the asset folder.
fs::path twoFolders(const fs::path& base, std::vector<std::uint8_t>& bin) {
  json unused = document("", "", &bin);
  for (const char* folder : {"asset", "asset-evil", "ASSET"}) {
    fs::create_directories(base / folder);
    writeBytes(base / folder / "tri.bin", bin);
    writeBytes(base / folder / "tex.png", pngBytes(2, 2));
  }
  return base / "asset";
}

// A uri that must be refused, as a buffer and as an image: an escape attempt fails the whole load, with a
// message naming the uri (not a silent fallback), and nothing outside the folder is opened.
void expectRefused(const fs::path& asset, const std::string& uri, const char* what) {
  std::vector<std::uint8_t> bin;
  for (bool image : {false, true}) {
    const json doc = image ? document("", uri, &bin) : document(uri, "", &bin);
    const Loaded o = load(writeText(asset / "m.gltf", doc.dump()));
    const char* as = image ? "image" : "buffer";
    EXPECT_FALSE(o.ok) << what << ": " << as << " '" << uri << "' accepted";
    EXPECT_NE(o.error.find("uri '"), std::string::npos) << what << ": " << as << ": " << o.error;
    EXPECT_TRUE(openedOutside(o, asset).empty()) << what << ": " << as << " '" << uri << "' opened outside";
  }
}

void expectAllowed(const fs::path& asset, const std::string& bufferUri, const std::string& imageUri, const char* what) {
  std::vector<std::uint8_t> bin;
  const Loaded o = load(writeText(asset / "m.gltf", document(bufferUri, imageUri, &bin).dump()));
  EXPECT_TRUE(o.ok) << what << ": " << o.error;
  EXPECT_EQ(o.textures, 1) << what;
}

TEST(GltfConfinement, ASiblingFolderSharingTheNamesPrefixIsOutside) {
  std::vector<std::uint8_t> bin;
  const fs::path asset = twoFolders(freshDir("confine-prefix"), bin);
  expectAllowed(asset, "tri.bin", "tex.png", "inside");
  // Through a symlink inside the folder to the sibling whose name starts with the folder's.
  fs::create_symlink(asset.parent_path() / "asset-evil", asset / "neighbour");
  expectRefused(asset, "neighbour/tri.bin", "a symlinked sibling-prefix folder");
  expectRefused(asset, "neighbour/tex.png", "a symlinked sibling-prefix folder");
  fs::create_symlink(asset.parent_path() / "asset-evil" / "tex.png", asset / "evil.png");
  expectRefused(asset, "evil.png", "a symlinked file of the sibling-prefix folder");
  // Lexically too.
  expectRefused(asset, "../asset-evil/tri.bin", "'..' into the sibling-prefix folder");
}

TEST(GltfConfinement, CaseVariantsOfTheFolderNameAreOtherFolders) {
  std::vector<std::uint8_t> bin;
  const fs::path asset = twoFolders(freshDir("confine-case"), bin);
  fs::create_symlink(asset.parent_path() / "ASSET", asset / "upper");
  expectRefused(asset, "upper/tri.bin", "the folder's name in capitals");
  expectRefused(asset, "../ASSET/tex.png", "'..' into the capitalised folder");
}

TEST(GltfConfinement, DotAndDotDotMixtures) {
  std::vector<std::uint8_t> bin;
  const fs::path asset = twoFolders(freshDir("confine-dots"), bin);
  fs::create_directories(asset / "sub");
  writeBytes(asset / "sub" / "tri.bin", bin);
  writeBytes(asset / "sub" / "tex.png", pngBytes(2, 2));
  expectAllowed(asset, "./tri.bin", "./sub/./tex.png", "'.' stays where it is");
  expectAllowed(asset, "sub//tri.bin", "sub/tex.png", "doubled separators");
  // '..' is refused even when it would come back inside: nothing outside is probed.
  expectRefused(asset, "sub/../tri.bin", "'..' that comes back");
  expectRefused(asset, "./../asset/tri.bin", "'./..' out and back in");
  expectRefused(asset, "sub/./../../asset-evil/tex.png", "a mixture that ends in the sibling");
  expectRefused(asset, "sub/%2E%2E/%2e%2E/asset-evil/tri.bin", "percent-encoded '..'");
  expectRefused(asset, "..", "'..' alone");
}

TEST(GltfConfinement, AFolderReachedThroughASymlinkedParentStillConfines) {
  std::vector<std::uint8_t> bin;
  const fs::path base = freshDir("confine-parent");
  const fs::path real = twoFolders(base / "real", bin);
  // The asset opened as base/alias/asset, where alias -> real: its own files load, the sibling does not.
  fs::create_symlink(base / "real", base / "alias");
  const fs::path asset = base / "alias" / "asset";
  expectAllowed(asset, "tri.bin", "tex.png", "through the symlinked parent");
  fs::create_symlink(real.parent_path() / "asset-evil", real / "neighbour");
  expectRefused(asset, "neighbour/tri.bin", "the sibling, from a folder reached through a symlink");
  expectRefused(asset, "../asset-evil/tex.png", "'..' from a folder reached through a symlink");
}

}  // namespace
}  // namespace tandem

// Filesystem confinement and the checks made before tinygltf sees a byte (see GltfInternal.h).
#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/GltfInternal.h"

namespace tandem::gltf {

namespace fs = std::filesystem;

namespace {

bool hasScheme(const std::string& rel) {
  // RFC 3986: scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":". A relative reference cannot
  // start like that, so "file:", "http:", "https:", "data:<unsupported type>" all land here.
  if (rel.empty() || !std::isalpha(static_cast<unsigned char>(rel[0]))) return false;
  for (char ch : rel) {
    if (ch == ':') return true;
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '+' && ch != '-' && ch != '.') return false;
  }
  return false;
}

bool isInside(const fs::path& root, const fs::path& p) {
  auto r = root.begin();
  auto q = p.begin();
  for (; r != root.end(); ++r, ++q)
    if (q == p.end() || *q != *r) return false;
  return true;
}

// For messages: at most 200 bytes, control characters (NUL included) shown as '?'.
std::string shortUri(const std::string& s) {
  std::string r = s.size() > 200 ? s.substr(0, 200) + "…" : s;
  for (char& ch : r)
    if (static_cast<unsigned char>(ch) < 0x20) ch = '?';
  return r;
}

}  // namespace

Resolve resolveInside(Confinement& c, const std::string& joined, fs::path* out) {
  // tinygltf asks for JoinPath(baseDir, uri) first and JoinPath(".", uri) second (its current-directory
  // fallback). We gave it the canonical root as baseDir, so anything without that prefix is the fallback:
  // not found, silently, without touching the filesystem.
  if (joined.compare(0, c.rootPrefix.size(), c.rootPrefix) != 0) return Resolve::NotFound;
  const std::string rel = joined.substr(c.rootPrefix.size());
  auto refuse = [&](const std::string& why) {
    c.refusals.push_back("uri '" + shortUri(rel) + "': " + why);
    return Resolve::Refused;
  };
  // An empty uri is "missing", not hostile: tinygltf reports it as such.
  if (rel.empty()) return Resolve::NotFound;
  // data: URIs of media types tinygltf does not decode (image/webp, non-base64) reach us as paths:
  // unsupported, not an escape attempt. Buffers then fail as missing, images are skipped.
  if (rel.rfind("data:", 0) == 0) return Resolve::NotFound;
  if (rel.find('\0') != std::string::npos) return refuse("NUL byte in the path");
  if (hasScheme(rel)) return refuse("URI scheme not allowed (only relative paths and data: buffers/images)");
  if (rel[0] == '/') return refuse("absolute path outside the asset folder");
  // Lexical check first: '..' is refused even when it would come back inside, so nothing is opened
  // by probing outside the folder.
  std::size_t start = 0;
  while (start <= rel.size()) {
    std::size_t end = rel.find('/', start);
    if (end == std::string::npos) end = rel.size();
    if (rel.compare(start, end - start, "..") == 0 && end - start == 2) return refuse("'..' leaves the asset folder");
    start = end + 1;
  }
  std::error_code ec;
  fs::path canon = fs::canonical(c.root / rel, ec);
  if (ec) return Resolve::NotFound;
  if (!isInside(c.root, canon)) return refuse("resolves (through a symlink) outside the asset folder");
  struct stat st {};
  if (::stat(canon.c_str(), &st) != 0) return Resolve::NotFound;
  if (!S_ISREG(st.st_mode)) return refuse("not a regular file");
  if (static_cast<std::uint64_t>(st.st_size) > c.maxFileBytes)
    return refuse(std::to_string(st.st_size) + " bytes exceeds the file size cap maxFileBytes = " +
                  std::to_string(c.maxFileBytes));
  *out = canon;
  return Resolve::Ok;
}

Result<std::vector<std::uint8_t>> readFileCapped(const fs::path& canonical, std::uint64_t cap,
                                                 const std::function<void(const std::string&)>* onOpened) {
  struct stat st {};
  if (::stat(canonical.c_str(), &st) != 0) return Error{"cannot stat: " + std::string(std::strerror(errno))};
  if (!S_ISREG(st.st_mode)) return Error{"not a regular file"};
  if (static_cast<std::uint64_t>(st.st_size) > cap)
    return Error{std::to_string(st.st_size) + " bytes exceeds the file size cap maxFileBytes = " + std::to_string(cap)};
  if (onOpened && *onOpened) (*onOpened)(canonical.string());
  std::ifstream in(canonical, std::ios::binary);
  if (!in) return Error{"cannot open"};
  std::vector<std::uint8_t> data(static_cast<std::size_t>(st.st_size));
  if (!data.empty()) in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size()));
  // A file that shrank between stat and read is refused rather than half-used.
  if (static_cast<std::size_t>(in.gcount()) != data.size()) return Error{"short read"};
  return data;
}

namespace {

bool fsFileExists(const std::string& path, void* user) {
  fs::path p;
  return resolveInside(*static_cast<Confinement*>(user), path, &p) == Resolve::Ok;
}

// No expansion at all: tinygltf's default expands '~' and environment variables.
std::string fsExpand(const std::string& path, void*) { return path; }

bool fsRead(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto& c = *static_cast<Confinement*>(user);
  fs::path p;
  if (resolveInside(c, path, &p) != Resolve::Ok) {
    if (err) *err += "refused";
    return false;
  }
  if (c.budget) {
    std::error_code ec;
    const std::uint64_t size = fs::file_size(p, ec);
    if (ec) return false;
    if (c.filesRead.insert(p.string()).second) {
      c.budget->addInput(size);
    } else if (!c.budget->charge(size)) {
      const std::string why = c.budget->refusal("reading it once more", size);
      c.refusals.push_back("file '" + p.string() + "': " + why);
      if (err) *err += why;
      return false;
    }
  }
  auto r = readFileCapped(p, c.maxFileBytes, c.onFileOpened);
  if (!r) {
    c.refusals.push_back("file '" + p.string() + "': " + r.error().message);
    if (err) *err += r.error().message;
    return false;
  }
  *out = std::move(*r);
  return true;
}

bool fsWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is disabled";
  return false;
}

}  // namespace

tinygltf::FsCallbacks makeFsCallbacks(Confinement* c) {
  tinygltf::FsCallbacks cb{};
  cb.FileExists = &fsFileExists;
  cb.ExpandFilePath = &fsExpand;
  cb.ReadWholeFile = &fsRead;
  cb.WriteWholeFile = &fsWrite;
  cb.user_data = c;
  return cb;
}

Result<void> checkJsonDepth(const std::uint8_t* data, std::size_t size, int maxDepth) {
  int depth = 0;
  bool inString = false;
  for (std::size_t i = 0; i < size; ++i) {
    const std::uint8_t ch = data[i];
    if (inString) {
      if (ch == '\\') ++i;  // skip the escaped character (an escaped quote does not end the string)
      else if (ch == '"') inString = false;
      continue;
    }
    if (ch == '"') inString = true;
    else if (ch == '{' || ch == '[') {
      if (++depth > maxDepth)
        return Error{"JSON nested deeper than the cap maxJsonDepth = " + std::to_string(maxDepth) + " (at byte " +
                     std::to_string(i) + ")"};
    } else if (ch == '}' || ch == ']') {
      --depth;
    }
  }
  return {};
}

namespace {

// Properties whose numbers are indices, counts, offsets or enums. tinygltf reads them with
// static_cast<int>(int64), so 2^32 + 1 would silently become 1; a float would silently become "absent".
bool isIntegerKey(const std::string& k) {
  static const char* const keys[] = {"buffer",  "bufferView", "byteOffset", "byteLength", "byteStride", "count",
                                     "componentType", "index", "texCoord", "source", "sampler", "mesh",
                                     "camera", "skin", "material", "indices", "mode", "node", "input",
                                     "output", "scene", "skeleton", "inverseBindMatrices", "light",
                                     "magFilter", "minFilter", "wrapS", "wrapT", "target"};
  for (const char* key : keys)
    if (k == key) return true;
  return false;
}
bool isIndexArrayKey(const std::string& k) { return k == "children" || k == "nodes" || k == "joints"; }

bool validIndexNumber(const nlohmann::json& v) {
  if (v.is_number_unsigned()) return v.get<std::uint64_t>() <= std::uint64_t(std::numeric_limits<int>::max());
  if (v.is_number_integer()) return false;  // negative
  return false;                             // float or other type
}

}  // namespace

namespace {

using json = nlohmann::json;

// What tinygltf's Model costs per JSON element, for the estimate made before it parses (the structs are
// tinygltf's own; 48 bytes cover the allocation and container slot around each).
constexpr std::uint64_t kSlot = 48;
constexpr std::uint64_t kValueCost = sizeof(tinygltf::Value) + kSlot;  // any value under extras/extensions
constexpr std::uint64_t kStringCost = 32;                               // a std::string beside its bytes

std::uint64_t topLevelCost(std::string_view key) {
  struct Entry {
    const char* key;
    std::uint64_t bytes;
  };
  static const Entry table[] = {
      {"accessors", sizeof(tinygltf::Accessor)}, {"animations", sizeof(tinygltf::Animation)},
      {"buffers", sizeof(tinygltf::Buffer)},     {"bufferViews", sizeof(tinygltf::BufferView)},
      {"cameras", sizeof(tinygltf::Camera)},     {"images", sizeof(tinygltf::Image)},
      {"materials", sizeof(tinygltf::Material)}, {"meshes", sizeof(tinygltf::Mesh)},
      {"nodes", sizeof(tinygltf::Node)},         {"samplers", sizeof(tinygltf::Sampler)},
      {"scenes", sizeof(tinygltf::Scene)},       {"skins", sizeof(tinygltf::Skin)},
      {"textures", sizeof(tinygltf::Texture)},
  };
  for (const Entry& e : table)
    if (key == e.key) return e.bytes + kSlot;
  return 0;
}

// For messages: a key shortened to 64 bytes, control characters shown as '?'.
std::string shortKey(std::string_view k) {
  std::string r(k.substr(0, 64));
  if (k.size() > 64) r += "…";
  for (char& ch : r)
    if (static_cast<unsigned char>(ch) < 0x20) ch = '?';
  return r;
}

// One container being walked. The path to the current item is the stack itself, so nothing is copied per
// item (a copy of the path per item made memory quadratic in the file size: one long key over many arrays).
struct Frame {
  const json* v = nullptr;
  json::const_iterator member;  // objects: the next member
  std::size_t next = 0;         // arrays: the next element
  std::string_view key;         // the parent's name for this container (objects' members)
  std::size_t index = 0;        // the parent's index for this container (array elements)
  bool inArray = false;         // whether the parent is an array
  bool freeForm = false;        // under "extras" or an extension Tandem does not read: no type rules
  bool valueTree = false;       // under "extras" or "extensions": tinygltf keeps it as a Value tree
  bool attributeMap = false;    // an "attributes" object or a morph target: every member is an accessor index
  bool inTargets = false;       // the "targets" array: its elements are attribute maps
  std::uint64_t elementCost = 0;  // tinygltf struct bytes per element (typed arrays)
};

std::string pathOf(const std::vector<Frame>& stack, std::string_view leafKey, std::size_t leafIndex, bool leafInArray) {
  std::string p;
  auto append = [&p](bool inArray, std::size_t index, std::string_view key) {
    p.push_back('/');
    p.append(inArray ? std::to_string(index) : shortKey(key));
  };
  for (std::size_t i = 1; i < stack.size(); ++i) append(stack[i].inArray, stack[i].index, stack[i].key);
  append(leafInArray, leafIndex, leafKey);
  return p;
}

// The frame of the item just taken from `parent` (a member when parentIsObject, else an element).
Frame childFrame(const Frame& parent, bool parentIsObject, std::string_view key, std::size_t index, const json& v) {
  Frame child;
  child.v = &v;
  child.key = key;
  child.index = index;
  child.inArray = !parentIsObject;
  // An extension's own keys are its business ("mode" is a string in EXT_meshopt_compression): only the
  // extensions the importer reads keep the index rules, since it reads their numbers as indices.
  child.freeForm = parent.freeForm || (parentIsObject && key == "extras") ||
                   (parentIsObject && parent.key == "extensions" && !parent.inArray &&
                    !supportedExtension(std::string(key.substr(0, 64))));
  child.valueTree = parent.valueTree || (parentIsObject && (key == "extras" || key == "extensions"));
  child.attributeMap =
      (parentIsObject && !parent.freeForm && key == "attributes") || (!parentIsObject && parent.inTargets);
  child.inTargets = parentIsObject && !parent.freeForm && key == "targets";
  return child;
}

// What one item adds to the estimate of tinygltf's model.
std::uint64_t itemModelCost(const Frame& parent, const Frame& child, bool parentIsObject, std::string_view key,
                            const json& v) {
  std::uint64_t est = 0;
  if (child.valueTree) {
    est += kValueCost + (parentIsObject ? kStringCost + key.size() : 0);
  } else if (!parentIsObject) {
    est += parent.elementCost != 0 ? parent.elementCost : 8;  // a struct, or a number/index in a plain array
  } else if (parent.attributeMap) {
    est += kSlot + kStringCost + key.size() + 8;  // std::map<std::string, int> entry
  }
  if (v.is_string()) {
    const std::string& str = v.get_ref<const std::string&>();
    est += kStringCost + str.size();
    if (str.rfind("data:", 0) == 0) est += str.size() / 4 * 3;  // the decoded bytes beside the URI
  }
  return est;
}

// tinygltf struct bytes per element of an array the item opens (0: plain values or Value trees).
std::uint64_t arrayElementCost(const Frame& child, bool root, bool parentIsObject, std::string_view key,
                               const json& v) {
  if (!v.is_array() || child.freeForm || child.valueTree) return 0;
  if (root) return topLevelCost(key);
  if (parentIsObject && key == "primitives") return sizeof(tinygltf::Primitive) + kSlot;
  if (parentIsObject && key == "channels") return sizeof(tinygltf::AnimationChannel) + kSlot;
  if (parentIsObject && key == "samplers") return sizeof(tinygltf::AnimationSampler) + kSlot;
  return 0;
}

// The type rules of index members and index arrays, which tinygltf would otherwise convert silently.
Result<void> checkItemType(const std::vector<Frame>& stack, const Frame& parent, std::string_view key,
                           std::size_t index, const json& v, bool root) {
  const std::string k(key.size() <= 32 ? key : std::string_view{});  // every rule key is short
  if (parent.attributeMap || isIntegerKey(k)) {
    if (v.is_number() && !validIndexNumber(v))
      return Error{pathOf(stack, key, index, false) + ": " + v.dump() + " is not an integer in [0, 2^31)"};
    if (parent.attributeMap && !v.is_number())
      return Error{pathOf(stack, key, index, false) + ": attribute must be an accessor index"};
    // Objects are legitimate under some of these names (channel "target", sparse "indices") and are
    // walked; strings, booleans and null never are.
    if (!v.is_number() && !v.is_object() && !v.is_array())
      return Error{pathOf(stack, key, index, false) + ": expected an integer"};
  } else if (isIndexArrayKey(k) && v.is_array() && !root) {  // top-level "nodes" holds objects
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!validIndexNumber(v[i]))
        return Error{pathOf(stack, key, index, false) + "/" + std::to_string(i) + ": " + v[i].dump() +
                     " is not an integer in [0, 2^31)"};
  }
  return {};
}

}  // namespace

Result<JsonScan> prescanJson(const std::uint8_t* data, std::size_t size, bool glb) {
  json doc;
  try {
    doc = json::parse(data, data + size);
  } catch (const std::exception& e) {
    return Error{std::string("JSON parse error: ") + e.what()};
  }
  if (!doc.is_object()) return Error{"the JSON root is not an object"};
  // A file that needs an extension Tandem lacks is refused for that, before tinygltf reads it: its
  // buffers may hold what only the extension decodes (Draco, meshopt), which tinygltf would refuse in
  // its own words ("accessor[0] invalid bufferView").
  if (auto required = doc.find("extensionsRequired"); required != doc.end() && required->is_array()) {
    std::string unknown;
    int named = 0, more = 0;
    for (const json& e : *required) {
      if (!e.is_string() || supportedExtension(e.get_ref<const std::string&>())) continue;
      if (++named > 8) ++more;
      else unknown += (unknown.empty() ? "" : ", ") + shortKey(e.get_ref<const std::string&>());
    }
    if (more > 0) unknown += " and " + std::to_string(more) + " more";
    if (!unknown.empty()) return Error{"extensionsRequired names unsupported extensions: " + unknown};
  }
  JsonScan scan;
  std::vector<Frame> stack;
  Frame top;
  top.v = &doc;
  top.member = doc.begin();
  stack.push_back(top);
  while (!stack.empty()) {
    Frame& f = stack.back();
    const bool isObject = f.v->is_object();
    if (isObject ? f.member == f.v->end() : f.next >= f.v->size()) {
      stack.pop_back();
      continue;
    }
    // The current item: an object member (key, value) or an array element (index, value).
    std::string_view key;
    std::size_t index = 0;
    const json* vp = nullptr;
    if (isObject) {
      key = f.member.key();
      vp = &f.member.value();
      ++f.member;
    } else {
      index = f.next++;
      vp = &(*f.v)[index];
    }
    const json& v = *vp;
    const bool root = stack.size() == 1;
    Frame child = childFrame(f, isObject, key, index, v);
    scan.modelEstimate += itemModelCost(f, child, isObject, key, v);
    child.elementCost = arrayElementCost(child, root, isObject, key, v);
    if (!f.freeForm && isObject && key != "extras")
      if (auto typed = checkItemType(stack, f, key, index, v, root); !typed) return typed.error();
    // glTF 2.0, GLB-stored buffer: only buffers[0] may omit its uri. tinygltf would copy the whole BIN
    // chunk into every buffer without one, a product of two counts.
    if (glb && stack.size() == 2 && f.key == "buffers" && !f.inArray && !isObject && index > 0 && v.is_object() &&
        !v.contains("uri"))
      return Error{"/buffers/" + std::to_string(index) +
                   ": has no uri, but only buffers[0] may refer to the GLB's BIN chunk"};

    if (v.is_object()) {
      child.member = v.begin();
      stack.push_back(child);
    } else if (v.is_array()) {
      stack.push_back(child);
    }
  }
  return scan;
}

namespace {
std::uint32_t le32(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);  // glTF is little-endian, as is every machine this builds for
  return v;
}
}  // namespace

Result<void> checkGlb(const std::vector<std::uint8_t>& b, std::size_t* jsonOffset, std::size_t* jsonSize) {
  if (b.size() < 12) return Error{"GLB: " + std::to_string(b.size()) + " bytes, shorter than the 12-byte header"};
  if (std::memcmp(b.data(), "glTF", 4) != 0) return Error{"GLB: bad magic"};
  const std::uint32_t version = le32(b.data() + 4);
  if (version != 2) return Error{"GLB: container version " + std::to_string(version) + ", expected 2"};
  const std::uint32_t length = le32(b.data() + 8);
  if (length != b.size())
    return Error{"GLB: header length " + std::to_string(length) + " differs from the file size " +
                 std::to_string(b.size())};
  std::uint64_t pos = 12;
  int chunk = 0;
  bool haveJson = false;
  while (pos < b.size()) {
    if (b.size() - pos < 8) return Error{"GLB: chunk " + std::to_string(chunk) + " header truncated"};
    const std::uint64_t clen = le32(b.data() + pos);
    const std::uint32_t ctype = le32(b.data() + pos + 4);
    if (clen > b.size() - pos - 8)
      return Error{"GLB: chunk " + std::to_string(chunk) + " length " + std::to_string(clen) + " runs past the file"};
    if (clen % 4 != 0)
      return Error{"GLB: chunk " + std::to_string(chunk) + " length " + std::to_string(clen) +
                   " is not a multiple of 4"};
    if (chunk == 0) {
      if (ctype != 0x4E4F534Au) return Error{"GLB: the first chunk is not JSON"};
      if (clen == 0) return Error{"GLB: empty JSON chunk"};
      *jsonOffset = static_cast<std::size_t>(pos + 8);
      *jsonSize = static_cast<std::size_t>(clen);
      haveJson = true;
    } else if (chunk == 1 && ctype == 0x004E4942u && clen == 0) {
      return Error{"GLB: empty BIN chunk"};
    } else if (ctype == 0x4E4F534Au) {
      return Error{"GLB: chunk " + std::to_string(chunk) + " is a second JSON chunk"};
    } else if (chunk > 1 && ctype == 0x004E4942u) {
      return Error{"GLB: chunk " + std::to_string(chunk) + " is a BIN chunk that is not the second chunk"};
    }
    pos += 8 + clen;
    ++chunk;
  }
  if (!haveJson) return Error{"GLB: no JSON chunk"};
  return {};
}

bool recordImage(tinygltf::Image* image, int index, std::string*, std::string*, int, int, const unsigned char* bytes,
                 int size, void* user) {
  // bufferView images: the pointer tinygltf computed may lie outside the buffer. Touch nothing; the
  // importer reads them from the view after validation.
  if (image->bufferView >= 0) return true;
  if (bytes == nullptr || size <= 0) return true;
  auto* d = static_cast<DeferredImages*>(user);
  // FNV-1a: equal bytes are found by hash, then compared, so each distinct image is kept (and later
  // decoded) once however many images name it.
  std::uint64_t h = 1469598103934665603ull;
  for (int i = 0; i < size; ++i) h = (h ^ bytes[i]) * 1099511628211ull;
  auto [lo, hi] = d->byHash.equal_range(h);
  for (auto it = lo; it != hi; ++it) {
    const std::vector<std::uint8_t>& u = d->unique[std::size_t(it->second)];
    if (u.size() == std::size_t(size) && std::memcmp(u.data(), bytes, u.size()) == 0) {
      d->sourceOf[index] = it->second;
      return true;
    }
  }
  const int id = int(d->unique.size());
  d->unique.emplace_back(bytes, bytes + size);
  d->byHash.emplace(h, id);
  d->sourceOf[index] = id;
  return true;
}

}  // namespace tandem::gltf

// The glTF importer over the third-party corpora in ../shared/assets (README there). Needs only
// loadGltf (tandem_scene), so it can live in tests/unit as well. Skips when the assets are absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "support/TestSupport.h"
#include "tandem/Gltf.h"
#include "tandem/Log.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  bool ok = false;
  std::string error;
  std::vector<std::string> warnings;
  bool confined = true;
  std::string escaped;
  std::size_t instances = 0;
};

Outcome loadOne(const fs::path& file) {
  Outcome o;
  GltfOptions opt;
  std::error_code ec;
  const fs::path canon = fs::canonical(file, ec);
  const std::string root = (ec ? file.parent_path() : canon.parent_path()).string() + "/";
  opt.onWarning = [&](const std::string& w) { o.warnings.push_back(w); };
  opt.onFileOpened = [&](const std::string& f) {
    if (f.compare(0, root.size(), root) != 0) {
      o.confined = false;
      o.escaped = f;
    }
  };
  LogSink old = setLogSink([](LogLevel, std::string_view) {});
  auto r = loadGltf(file.string(), opt);
  setLogSink(old);
  o.ok = r.ok();
  if (!o.ok) o.error = r.error().message;
  else o.instances = r->instances.size();
  return o;
}

std::vector<fs::path> modelFiles(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    const std::string ext = it->path().extension().string();
    if (it->is_regular_file() && (ext == ".gltf" || ext == ".glb")) out.push_back(it->path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

#define REQUIRE_ASSETS()                                                                        \
  const std::string assets = test::sharedAssetsDir();                                           \
  if (assets.empty()) GTEST_SKIP() << "../shared/assets is absent: glTF corpus tests skipped"

TEST(GltfCorpus, SampleModelsLoad) {
  REQUIRE_ASSETS();
  auto files = modelFiles(fs::path(assets) / "gltf-sample-assets");
  ASSERT_FALSE(files.empty());
  int warned = 0;
  for (const auto& f : files) {
    Outcome o = loadOne(f);
    EXPECT_TRUE(o.ok) << f << ": " << o.error;
    EXPECT_TRUE(o.confined) << f << " opened " << o.escaped;
    if (o.ok) {
      EXPECT_GT(o.instances, 0u) << f;
    }
    if (!o.warnings.empty()) {
      ++warned;
      std::cout << "[warn] " << f.lexically_relative(assets).string() << ": " << o.warnings.front()
                << (o.warnings.size() > 1 ? " (+" + std::to_string(o.warnings.size() - 1) + " more)" : "") << "\n";
    }
  }
  std::cout << files.size() << " sample models, " << warned << " with warnings\n";
}

TEST(GltfCorpus, AssetGeneratorPositiveLoadsExceptCompatibility04And05) {
  REQUIRE_ASSETS();
  auto files = modelFiles(fs::path(assets) / "gltf-asset-generator" / "Positive");
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) {
    Outcome o = loadOne(f);
    EXPECT_TRUE(o.confined) << f << " opened " << o.escaped;
    const std::string name = f.stem().string();
    if (name == "Compatibility_04") {
      EXPECT_FALSE(o.ok);
      EXPECT_NE(o.error.find("minVersion 2.1"), std::string::npos) << o.error;
    } else if (name == "Compatibility_05") {
      EXPECT_FALSE(o.ok);
      EXPECT_NE(o.error.find("extensionsRequired"), std::string::npos) << o.error;
    } else {
      EXPECT_TRUE(o.ok) << f << ": " << o.error;
    }
  }
  // The one genuinely missing image: a warning and a fallback, the rest renders.
  Outcome neg = loadOne(fs::path(assets) / "gltf-asset-generator/Positive/Node_NegativeScale/Node_NegativeScale_01.gltf");
  if (neg.ok) {
    bool sawMissing = false;
    for (const auto& w : neg.warnings) sawMissing |= w.find("could not be read") != std::string::npos;
    std::cout << "Node_NegativeScale_01 warnings: " << neg.warnings.size() << (sawMissing ? " (missing image)" : "") << "\n";
  }
}

TEST(GltfCorpus, NegativeAndRegressionFilesNeverCrash) {
  REQUIRE_ASSETS();
  std::vector<fs::path> files;
  for (const char* d : {"gltf-asset-generator/Negative", "tinygltf-regression", "cgltf-fuzz-seeds"}) {
    auto f = modelFiles(fs::path(assets) / d);
    files.insert(files.end(), f.begin(), f.end());
  }
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) {
    Outcome o = loadOne(f);
    EXPECT_TRUE(o.confined) << f << " opened " << o.escaped;
    std::cout << (o.ok ? (o.warnings.empty() ? "[accept] " : "[skip]   ") : "[reject] ")
              << f.lexically_relative(assets).string() << ": "
              << (o.ok ? (o.warnings.empty() ? std::string("-") : o.warnings.front()) : o.error) << "\n";
  }
  for (const char* name : {"Mesh_NoPosition", "Mesh_PrimitiveRestart"}) {
    auto f = modelFiles(fs::path(assets) / "gltf-asset-generator/Negative" / name);
    for (const auto& p : f) {
      Outcome o = loadOne(p);
      EXPECT_TRUE(!o.ok || !o.warnings.empty()) << p << " was accepted silently";
    }
  }
}

TEST(GltfCorpus, ValidatorInvalidFilesRejectedOrDegraded) {
  REQUIRE_ASSETS();
  const fs::path root = fs::path(assets) / "gltf-validator-tests";
  auto files = modelFiles(root);
  ASSERT_FALSE(files.empty());
  int rejected = 0, skipped = 0, accepted = 0, nothingToDraw = 0, validOk = 0, validRejected = 0;
  std::map<std::string, int> acceptedCodes;
  std::vector<std::string> acceptedList, validRejectedList;
  for (const auto& f : files) {
    nlohmann::json report;
    {
      std::ifstream in(f.string() + ".report.json");
      if (!in) continue;
      try {
        in >> report;
      } catch (...) {
        continue;
      }
    }
    const int errors = report.value("/issues/numErrors"_json_pointer, 0);
    Outcome o = loadOne(f);
    EXPECT_TRUE(o.confined) << f << " opened " << o.escaped;
    const std::string rel = f.lexically_relative(root).string();
    if (errors == 0) {
      if (o.ok) ++validOk;
      else {
        ++validRejected;
        validRejectedList.push_back(rel + ": " + o.error);
      }
      continue;
    }
    std::string codes;
    for (const auto& m : report["issues"]["messages"])
      if (m.value("severity", 1) == 0) {
        const std::string c = m.value("code", "?");
        if (codes.find(c) == std::string::npos) codes += (codes.empty() ? "" : ",") + c;
      }
    // A warning counts as "skipped" only when it is about something dropped; "nothing to draw" alone
    // means the file was accepted (and had no geometry to begin with).
    const bool onlyEmpty = std::all_of(o.warnings.begin(), o.warnings.end(), [](const std::string& w) {
      return w.find("nothing to draw") != std::string::npos;
    });
    if (!o.ok) ++rejected;
    else if (!onlyEmpty) ++skipped;
    else {
      if (!o.warnings.empty()) ++nothingToDraw;
      ++accepted;
      acceptedList.push_back(rel + "  [" + codes + "]");
      for (const auto& m : report["issues"]["messages"])
        if (m.value("severity", 1) == 0) ++acceptedCodes[m.value("code", "?")];
    }
  }
  std::cout << "validator corpus, files with numErrors > 0: rejected " << rejected << ", skipped with warning "
            << skipped << ", accepted " << accepted << " (" << nothingToDraw << " of them with nothing to draw)\n";
  std::cout << "validator corpus, valid files (numErrors == 0): loaded " << validOk << ", rejected " << validRejected
            << "\n";
  for (const auto& a : acceptedList) std::cout << "  accepted: " << a << "\n";
  for (const auto& [code, n] : acceptedCodes) std::cout << "  accepted error code " << code << " × " << n << "\n";
  for (const auto& v : validRejectedList) std::cout << "  valid but rejected: " << v << "\n";
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace tandem

// The glTF importer over the third-party corpora in ../shared/assets (README there). Needs only
// loadGltf (tandem_scene), so it can live in tests/unit as well. Skips when the assets are absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "support/Goldens.h"
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

// Every file of the validator's corpus, its outcome against the validator's own report: files with errors are
// rejected, skipped in part (a warning naming what was dropped) or accepted (the error does not stop a render:
// an unknown extension object, an out-of-range value the loader clamps); valid files load, or are refused for a
// reason the loader documents (a feature it does not take: data:application/gltf-buffer, an external scheme).
// Each file's outcome is pinned in tests/corpus/validator-outcomes.txt, so a change in any one of them is seen
// and judged, not absorbed by a count; files without a report are loaded and pinned too.
TEST(GltfCorpus, ValidatorFilesKeepTheirPinnedOutcomes) {
  REQUIRE_ASSETS();
  const fs::path root = fs::path(assets) / "gltf-validator-tests";
  auto files = modelFiles(root);
  ASSERT_FALSE(files.empty());
  std::map<std::string, std::string> outcomes;
  std::map<std::string, int> tally;
  for (const auto& f : files) {
    nlohmann::json report;
    bool reported = false;
    if (std::ifstream in(f.string() + ".report.json"); in) {
      try {
        in >> report;
        reported = true;
      } catch (...) {
      }
    }
    Outcome o = loadOne(f);
    EXPECT_TRUE(o.confined) << f << " opened " << o.escaped;
    // A warning counts as "skip" only when it is about something dropped; "nothing to draw" alone is "empty".
    const bool onlyEmpty = std::all_of(o.warnings.begin(), o.warnings.end(), [](const std::string& w) {
      return w.find("nothing to draw") != std::string::npos;
    });
    const std::string loaded = !o.ok ? "reject" : !onlyEmpty ? "skip" : o.warnings.empty() ? "accept" : "empty";
    const int errors = reported ? report.value("/issues/numErrors"_json_pointer, 0) : 0;
    const std::string kind = !reported ? "unreported-" : errors == 0 ? "valid-" : "invalid-";
    outcomes[f.lexically_relative(root).string()] = kind + loaded;
    ++tally[kind + loaded];
  }
  for (const auto& [k, n] : tally) std::cout << "validator corpus: " << k << " " << n << "\n";
  const std::string pinned = test::sourceDir() + "/tests/corpus/validator-outcomes.txt";
  if (test::updatingGoldens()) {
    std::ofstream out(pinned);
    out << "# The glTF validator corpus (../shared/assets/gltf-validator-tests): each file's outcome in\n"
           "# GltfCorpus.ValidatorFilesKeepTheirPinnedOutcomes. Rewritten by the update-goldens target; review the diff.\n";
    for (const auto& [file, outcome] : outcomes) out << outcome << " " << file << "\n";
    GTEST_SKIP() << "rewrote " << pinned;
  }
  std::map<std::string, std::string> want;
  std::ifstream in(pinned);
  ASSERT_TRUE(in) << pinned << " is missing (cmake --build build --target update-goldens)";
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t sp = line.find(' ');
    want[line.substr(sp + 1)] = line.substr(0, sp);
  }
  int changed = 0;
  for (const auto& [file, outcome] : outcomes) {
    const auto w = want.find(file);
    if (w == want.end()) {
      ADD_FAILURE() << file << ": " << outcome << ", not pinned";
      ++changed;
    } else if (w->second != outcome) {
      ADD_FAILURE() << file << ": " << outcome << ", pinned " << w->second;
      ++changed;
    }
  }
  for (const auto& [file, outcome] : want)
    if (!outcomes.count(file)) ADD_FAILURE() << file << ": pinned " << outcome << ", not in the corpus";
  EXPECT_EQ(changed, 0);
  EXPECT_GT(tally["invalid-reject"], 100) << "the loader refuses most broken files";
}

}  // namespace
}  // namespace tandem

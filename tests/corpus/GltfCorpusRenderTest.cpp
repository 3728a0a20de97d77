// Every positive glTF in ../shared/assets (the Khronos sample models and the asset generator's Positive
// set, less Compatibility_04 / _05, which must be rejected) loads AND renders a finite, non-empty frame
// through the whole hybrid pipeline (raster + every ray-traced effect). Skips when the assets are absent.
// "Non-empty" means geometry is visible (the instance-id view covers some pixel): a perfect mirror in a
// uniform background (Material_MetallicRoughness_06) is rightly the background colour. Two documented
// exceptions must hold exactly: files whose only primitives are points or lines load with a warning and no
// instances (docs/gltf.md), and a MASK cutoff above 1 (Material_AlphaMask_03) cuts every pixel away.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "gl/GlTestUtil.h"
#include "tandem/Gltf.h"
#include "tandem/Log.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> positiveFiles(const fs::path& assets) {
  std::vector<fs::path> out;
  for (const char* dir : {"gltf-sample-assets", "gltf-asset-generator/Positive"}) {
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(assets / dir, ec); it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      if (ec) break;
      const std::string ext = it->path().extension().string();
      const std::string stem = it->path().stem().string();
      if (!it->is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
      if (stem == "Compatibility_04" || stem == "Compatibility_05") continue;
      out.push_back(it->path());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(GltfCorpusRender, EveryPositiveFileRendersAFiniteNonEmptyFrame) {
  const std::string assets = test::sharedAssetsDir();
  if (assets.empty()) GTEST_SKIP() << "../shared/assets is absent: glTF corpus render test skipped";
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_NE(renderer, nullptr);

  FrameSettings settings = *presetSettings("hybrid-full");
  settings.width = 96;
  settings.height = 54;
  const auto files = positiveFiles(assets);
  ASSERT_GT(files.size(), 100u);
  LogSink old = setLogSink([](LogLevel, std::string_view) {});
  int rendered = 0;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    std::vector<std::string> warnings;
    GltfOptions options;
    options.onWarning = [&](const std::string& w) { warnings.push_back(w); };
    auto scene = loadGltf(file.string(), options);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Camera camera = scene->camera;
    const bool noInstances = scene->instances.empty();
    bool allCutAway = !noInstances;
    for (const Instance& inst : scene->instances) {
      const Material& m = scene->materials[inst.material];
      allCutAway = allCutAway && m.alphaMode == AlphaMode::Mask && m.alphaCutoff > 1.0f;
    }
    ASSERT_TRUE(renderer->setScene(std::move(*scene)).ok());
    renderer->render(camera, settings);
    ImageF frame = renderer->readLinear();
    ASSERT_EQ(frame.width, settings.width);
    std::size_t nonFinite = 0;
    for (const glm::vec3& c : frame.rgb)
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) ++nonFinite;
    EXPECT_EQ(nonFinite, 0u) << "non-finite pixels";

    FrameSettings ids = settings;
    ids.debugView = DebugView::InstanceId;  // background is black in debug views
    renderer->render(camera, ids);
    Image idImage = renderer->readImage();
    std::size_t covered = 0;
    for (std::size_t i = 0; i < idImage.rgba.size(); i += 4)
      if (idImage.rgba[i] | idImage.rgba[i + 1] | idImage.rgba[i + 2]) ++covered;
    if (noInstances) {
      EXPECT_FALSE(warnings.empty()) << "a file with nothing to draw must say why";
      EXPECT_EQ(covered, 0u);
    } else if (allCutAway) {
      EXPECT_EQ(covered, 0u) << "alphaCutoff > 1 must discard every pixel";
    } else {
      EXPECT_GT(covered, 0u) << "no geometry visible in the frame";
    }
    ++rendered;
  }
  setLogSink(old);
  std::printf("rendered %d positive glTF files\n", rendered);
}

}  // namespace
}  // namespace tandem

// Real glTF files drawn as their authors meant them, where a sample model says what is right: probes of the
// frame at the places the model's own markers give (../shared/assets; skipped when absent).
//   TextureTransformTest: KHR_texture_transform's rotation, scale and all three at once turn and shrink an
//   arrow texture so that it points at a green marker; rotated the other way it points at a red one, not at
//   all at a yellow one.
//   NegativeScaleTest: single-sided quads turned away from the camera, each with a red X on its front and a
//   green check on a quad behind it; mirrored copies (negative scale) of the same. Every check shows and no X.
//   LightsPunctualLamp: a paper shade of thin-walled transmission around a bulb; the raster and the rays
//   both see through it, so the two presets' frames agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "gl/GlTestUtil.h"
#include "tandem/Gltf.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;

/// A sample model under ../shared/assets/gltf-sample-assets, or "" when the assets are absent.
std::string sampleModel(const std::string& name) {
  const std::string assets = test::sharedAssetsDir();
  if (assets.empty()) return {};
  return (fs::path(assets) / "gltf-sample-assets" / name / "glTF" / (name + ".gltf")).string();
}

// An orthographic camera looking down -z at the model's plane z = 0, `height` units high, centred on the origin.
Camera facingThePlane(float height) {
  Camera c;
  c.orthographic = true;
  c.orthoHeight = height;
  c.posW = glm::vec3(0.0f, 0.0f, 5.0f);
  c.targetW = glm::vec3(0.0f);
  c.upW = glm::vec3(0.0f, 1.0f, 0.0f);
  return c;
}

// TextureTransformTest's three arrow quads (unit squares about `centre`; their uv (0, 0) at the top left
// corner, where every transform pivots) and their markers, from the file's node translations (world units, the
// quad's own frame: each marker is a child of its quad).
struct ArrowQuad {
  const char* name;
  glm::vec2 centre;
  std::vector<std::pair<const char*, glm::vec2>> markers;  // the first is the green ("Correct") one
};
const std::vector<ArrowQuad>& arrowQuads() {
  static const std::vector<ArrowQuad> quads{
      {"Rotation", {-1.1f, -0.55f}, {{"Correct", {-0.0790f, -0.5163f}}, {"Not Supported", {0.2778f, -0.2778f}},
                                     {"Error", {0.5163f, 0.0790f}}}},
      {"Scale", {0.0f, -0.55f}, {{"Correct", {0.0185f, -0.0185f}}, {"Not Supported", {0.2778f, -0.2778f}}}},
      {"All", {1.1f, -0.55f}, {{"Correct", {-0.07f, -0.25f}}}},
  };
  return quads;
}

// The pixels 4-connected to `seed` for which `is(x, y)` holds, each visited once (visit(x, y)), marked in `seen`
// (one flag per pixel, kept across calls).
template <class Is, class Visit>
void floodFill(int width, int height, glm::ivec2 seed, std::vector<std::uint8_t>& seen, Is&& is, Visit&& visit) {
  auto flag = [&](glm::ivec2 p) -> std::uint8_t& {
    return seen[static_cast<std::size_t>(p.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(p.x)];
  };
  std::vector<glm::ivec2> stack{seed};
  flag(seed) = 1;
  while (!stack.empty()) {
    const glm::ivec2 p = stack.back();
    stack.pop_back();
    visit(p.x, p.y);
    for (const glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(-1, 0), glm::ivec2(0, 1), glm::ivec2(0, -1)}) {
      const glm::ivec2 n = p + d;
      if (n.x < 0 || n.y < 0 || n.x >= width || n.y >= height || flag(n) || !is(n.x, n.y)) continue;
      flag(n) = 1;
      stack.push_back(n);
    }
  }
}

// The arrow's tip in a frame of the model, in the quad's frame. The arrow is black (the textures' border is grey,
// their ground white), and the sampler's wrap is not represented (docs/gltf.md): the texture repeats, so the quad
// may show other copies of it. The arrow meant is the one whose tail lies nearest the corner every transform
// pivots about; its tip, the pixel of it farthest from that corner.
std::optional<glm::vec2> arrowTip(const ImageF& frame, const Camera& camera, const ArrowQuad& q) {
  const float height = camera.orthoHeight;
  const float width = height * static_cast<float>(frame.width) / static_cast<float>(frame.height);
  const glm::vec2 pivot(-0.5f, 0.5f);
  auto localOf = [&](int x, int y) {
    const glm::vec2 world((static_cast<float>(x) + 0.5f) / static_cast<float>(frame.width) * width - 0.5f * width,
                          0.5f * height - (static_cast<float>(y) + 0.5f) / static_cast<float>(frame.height) * height);
    return world - q.centre;
  };
  auto inQuad = [&](int x, int y) {
    const glm::vec2 l = localOf(x, y);
    return std::abs(l.x) < 0.48f && std::abs(l.y) < 0.48f;  // (clear of the quad's edge)
  };
  auto luminance = [&](int x, int y) {
    const glm::vec3 c = frame.at(x, y);
    return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
  };
  float brightest = 0.0f;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x)
      if (inQuad(x, y)) brightest = std::max(brightest, luminance(x, y));
  auto dark = [&](int x, int y) { return inQuad(x, y) && luminance(x, y) < 0.2f * brightest; };
  // The dark pixel nearest the pivot, then its arrow (the dark pixels joined to it).
  glm::ivec2 seed(-1);
  float nearest = std::numeric_limits<float>::infinity();
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x)
      if (dark(x, y) && glm::length(localOf(x, y) - pivot) < nearest) nearest = glm::length(localOf(x, y) - pivot), seed = {x, y};
  if (seed.x < 0) return std::nullopt;
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height), 0);
  glm::vec2 tip = localOf(seed.x, seed.y);
  floodFill(frame.width, frame.height, seed, seen, dark, [&](int x, int y) {
    if (glm::length(localOf(x, y) - pivot) > glm::length(tip - pivot)) tip = localOf(x, y);
  });
  return tip;
}

// The rotation, the scale and all three at once, in the raster frame and in the reference (every pixel by the
// ray pass's own texture lookups): each arrow's tip within 0.16 of its green marker (the markers sit a little
// past the tip) and nearer it than any other. The extension's README matrix turned the rotation's arrow to the
// red marker (the tip 0.12 from it, 0.8 from the green one) and the "all" arrow 0.5 from its green marker.
TEST(GltfAuthorsIntent, TextureTransformsArrowsPointAtTheirGreenMarkers) {
  const std::string file = sampleModel("TextureTransformTest");
  if (file.empty()) GTEST_SKIP() << "../shared/assets is absent: skipped";
  TD_REQUIRE_GL_CONTEXT();
  auto scene = loadGltf(file);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Camera camera = facingThePlane(2.6f);
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer->setScene(*scene).ok());
  for (const char* preset : {"raster", "reference"}) {
    FrameSettings s = *presetSettings(preset);
    s.width = 640;
    s.height = 400;
    s.referenceSpp = 1;
    ASSERT_TRUE(renderer->render(camera, s).error.empty());
    gltest::savePng(std::string("texture-transform-") + preset + ".png", renderer->readImage());
    const ImageF frame = renderer->readLinear();
    for (const ArrowQuad& q : arrowQuads()) {
      SCOPED_TRACE(std::string(preset) + ", " + q.name);
      const std::optional<glm::vec2> tip = arrowTip(frame, camera, q);
      ASSERT_TRUE(tip.has_value()) << "no arrow drawn";
      const float toGreen = glm::length(*tip - q.markers[0].second);
      EXPECT_LT(toGreen, 0.16f) << "the tip at " << tip->x << ", " << tip->y << " in the quad";
      for (std::size_t m = 1; m < q.markers.size(); ++m)
        EXPECT_LT(toGreen, glm::length(*tip - q.markers[m].second)) << "nearer the " << q.markers[m].first << " marker";
    }
  }
}

// The blobs (4-connected, at least 10 pixels) of the frame's plainly red pixels (the X's) and plainly green
// ones (the checks), linear values.
struct RedAndGreen {
  int red = 0, green = 0;
};
RedAndGreen countRedAndGreen(const ImageF& frame) {
  auto blobs = [&](auto&& is) {
    auto at = [&](int x, int y) { return is(frame.at(x, y)); };
    std::vector<std::uint8_t> seen(static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height), 0);
    int count = 0;
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x) {
        if (seen[static_cast<std::size_t>(y) * static_cast<std::size_t>(frame.width) + static_cast<std::size_t>(x)] ||
            !at(x, y))
          continue;
        int size = 0;
        floodFill(frame.width, frame.height, {x, y}, seen, at, [&](int, int) { ++size; });
        count += size >= 10 ? 1 : 0;
      }
    return count;
  };
  RedAndGreen n;
  n.red = blobs([](glm::vec3 c) { return c.r > 0.3f && c.g < 0.1f && c.b < 0.1f; });
  n.green = blobs([](glm::vec3 c) { return c.g > 0.3f && c.r < 0.15f && c.b < 0.15f; });
  return n;
}

// doubleSided: false culls the back faces (docs/gltf.md): the "back" column's quads turn their front, with its
// red X, away from the camera, so the raster must cull them and the rays (the reference's camera rays, Embree's
// filter) pass them; the mirrored row's winding is the importer's to flip. Six checks and no X.
TEST(GltfAuthorsIntent, SingleSidedFacesSeenFromBehindAreNotDrawn) {
  const std::string file = sampleModel("NegativeScaleTest");
  if (file.empty()) GTEST_SKIP() << "../shared/assets is absent: skipped";
  TD_REQUIRE_GL_CONTEXT();
  auto scene = loadGltf(file);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Camera camera = scene->camera;
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer->setScene(*scene).ok());
  for (const char* preset : {"raster", "reference"}) {
    SCOPED_TRACE(preset);
    FrameSettings s = *presetSettings(preset);
    s.width = 640;
    s.height = 360;
    s.referenceSpp = 1;
    ASSERT_TRUE(renderer->render(camera, s).error.empty());
    gltest::savePng(std::string("negative-scale-") + preset + ".png", renderer->readImage());
    const RedAndGreen n = countRedAndGreen(renderer->readLinear());
    EXPECT_EQ(n.red, 0) << "red X's (single-sided faces seen from behind) are drawn";
    EXPECT_EQ(n.green, 6) << "green checks";
  }
}

// The shade's material is thin-walled, rough transmission (KHR_materials_transmission, no volume: IOR 1), which
// the rays pass through to the bulb and the lamp behind, spread over the lobe. The raster shows what lies behind
// it from the frame's own view (gl/BehindView.h), blurred by the same lobe at the distance behind it of what it
// shows (the bulb close behind stays bright); it read the shade's probe, drawn
// from inside the bulb, and drew the shade an opaque cream. Against the rays' frame converged (16 samples).
TEST(GltfAuthorsIntent, TheLampsShadeIsSeeThroughInRasterAsInRays) {
  const std::string file = sampleModel("LightsPunctualLamp");
  if (file.empty()) GTEST_SKIP() << "../shared/assets is absent: skipped";
  TD_REQUIRE_GL_CONTEXT();
  auto scene = loadGltf(file);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Camera camera = scene->camera;
  gltest::SceneFrame f = gltest::sceneFrame(*glContext_, std::move(*scene), 480, 360);
  f.camera = camera;
  // The rays' frame converged (the shade's rough transmission is a glossy lobe, one sample a pixel a frame).
  std::vector<Image> frames;
  frames.push_back(gltest::drawFrame(f, gltest::presetFor(f, "raster")));
  frames.push_back(gltest::drawFrame(f, gltest::presetFor(f, "hybrid-full", 16)));
  gltest::savePng("lamp-raster.png", frames[0]);
  gltest::savePng("lamp-hybrid-full-16.png", frames[1]);
  // The shade: a box about the bell, from the model's bounds as the default camera frames it.
  auto crop = [](const Image& image) {
    Image out;
    out.width = 120;
    out.height = 80;
    out.rgba.resize(static_cast<std::size_t>(out.width) * out.height * 4);
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x)
        for (int c = 0; c < 4; ++c)
          out.rgba[(static_cast<std::size_t>(y) * out.width + x) * 4 + c] =
              image.rgba[(static_cast<std::size_t>(y + 105) * image.width + x + 155) * 4 + c];
    return out;
  };
  // Reading the shade's probe instead: FLIP 0.0341 over the frame, 0.231 over the shade and 80 % of its box's
  // pixels within 24/255 (the other raster-against-ray tests' measure, RasterEffectsGLTest); now 0.0291, 0.141
  // and 88 % (what is left: the probes' reflections on the metal, the third see-through layer).
  EXPECT_LT(gltest::flipMean(frames[0], frames[1]), 0.031);
  const Image shadeRaster = crop(frames[0]), shadeRays = crop(frames[1]);
  EXPECT_LT(gltest::flipMean(shadeRaster, shadeRays), 0.16);
  int close = 0;
  for (int y = 0; y < shadeRaster.height; ++y)
    for (int x = 0; x < shadeRaster.width; ++x) {
      int worst = 0;
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(shadeRaster.at(x, y)[c]) - int(shadeRays.at(x, y)[c])));
      close += worst <= 24 ? 1 : 0;
    }
  EXPECT_GE(close, shadeRaster.width * shadeRaster.height * 85 / 100);
}

}  // namespace
}  // namespace tandem

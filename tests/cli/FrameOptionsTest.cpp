// tandem-render's frame options, parsed from argument lists as the command line gives them: every value
// out of range, and every flag the chosen mode would ignore, is an error naming the flag (values a
// sentinel used to mistake for "not given", such as --depth -1, included).
#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "CliCommon.h"

namespace tandem::cli {
namespace {

Result<FrameSettings> resolveArgs(std::initializer_list<std::string> args, FrameSettings base = {}) {
  CLI::App app;
  FrameOptions o;
  addFrameOptions(app, o);
  std::vector<std::string> reversed(args.begin(), args.end());  // CLI11 takes them last first
  std::reverse(reversed.begin(), reversed.end());
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return Error{std::string("parse: ") + e.what()};
  }
  return resolveFrameOptions(o, base);
}

/// The error for `args`, or a failure naming the settings they were wrongly accepted as.
std::string errorOf(std::initializer_list<std::string> args) {
  auto r = resolveArgs(args);
  if (r) {
    ADD_FAILURE() << "accepted: depth " << r->maxDepth << ", scale " << r->rayScale << ", spp " << r->referenceSpp
                  << ", exposure " << r->exposure;
    return {};
  }
  EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << "not one line: " << r.error().message;
  return r.error().message;
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

TEST(FrameOptions, OutOfRangeValuesAreErrorsNamingTheFlagAndValue) {
  struct Case {
    std::initializer_list<std::string> args;
    std::string expected;  // the message's start
  };
  const Case cases[] = {
      {{"--depth", "-1"}, "--depth: must be 0..64, got -1"},
      {{"--depth", "65"}, "--depth: must be 0..64, got 65"},
      {{"--scale", "0"}, "--scale: must be 1, 2 or 4, got 0"},
      {{"--scale", "3"}, "--scale: must be 1, 2 or 4, got 3"},
      {{"--preset", "reference", "--spp", "0"}, "--spp: must be 1..64, got 0"},
      {{"--preset", "reference", "--spp", "65"}, "--spp: must be 1..64, got 65"},
      {{"--exposure", "0"}, "--exposure: must be a finite number > 0, got 0"},
      {{"--exposure", "-2"}, "--exposure: must be a finite number > 0, got -2"},
      {{"--exposure", "inf"}, "--exposure: must be a finite number > 0, got inf"},
      {{"--exposure", "nan"}, "--exposure: must be a finite number > 0"},
      {{"--target-fps", "0"}, "--target-fps: must be 0.1..1000 frames per second, got 0"},
      {{"--target-fps", "1001"}, "--target-fps: must be 0.1..1000 frames per second, got 1001"},
      {{"--target-fps", "nan"}, "--target-fps: must be 0.1..1000 frames per second"},
      {{"--preset", "reference", "--target-fps", "30"}, "--target-fps: the reference frame is never cut down"},
      {{"--size", "0x0"}, "--size: expected WxH"},
      {{"--preset", ""}, "--preset: unknown preset ''"},
      {{"--shadows", ""}, "--shadows: expected off, raster, ray or hybrid, got ''"},
      {{"--shadow-proofs", "gpu"}, "--shadow-proofs: expected auto, gl, cpu or shafts, got 'gpu'"},
      {{"--tonemap", "filmic"}, "--tonemap: expected none, reinhard or aces, got 'filmic'"},
      {{"--debug-view", "albedo"}, "--debug-view: unknown view 'albedo'"},
  };
  for (const Case& c : cases) {
    std::string message = errorOf(c.args);
    EXPECT_TRUE(startsWith(message, c.expected)) << "got: " << message << "\nexpected: " << c.expected << "...";
  }
}

TEST(FrameOptions, UnparsableNumbersAreParseErrorsNamingTheFlag) {
  for (auto args : {std::initializer_list<std::string>{"--depth", "abc"}, {"--spp", "1.5"}, {"--exposure", "x"}}) {
    std::string message = errorOf(args);
    EXPECT_NE(message.find(*args.begin()), std::string::npos) << message;
  }
}

TEST(FrameOptions, SppWithoutTheReferencePresetIsAnError) {
  // It used to be accepted and ignored: only the reference frame takes several samples per pixel.
  for (auto preset : {"raster", "hybrid-fast", "hybrid-full"})
    EXPECT_TRUE(startsWith(errorOf({"--preset", preset, "--spp", "4"}), "--spp: only the reference preset")) << preset;
  auto ok = resolveArgs({"--preset", "reference", "--spp", "4"});
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ(ok->referenceSpp, 4);
  // A base that is already a reference frame (a scene's render.preset) takes --spp without --preset.
  auto fromBase = resolveArgs({"--spp", "3"}, *presetSettings("reference"));
  ASSERT_TRUE(fromBase) << fromBase.error().message;
  EXPECT_EQ(fromBase->referenceSpp, 3);
}

TEST(FrameOptions, PathTracingIsTheReferencesAlone) {
  for (auto preset : {"raster", "hybrid-fast", "hybrid-full"})
    EXPECT_TRUE(startsWith(errorOf({"--preset", preset, "--gi", "path"}), "--gi: only the reference preset")) << preset;
  EXPECT_TRUE(startsWith(errorOf({"--preset", "reference", "--gi", "radiosity"}), "--gi: expected none or path"));
  auto ok = resolveArgs({"--preset", "reference", "--gi", "path"});
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ(ok->gi, GlobalIllumination::Path);
  auto none = resolveArgs({"--preset", "hybrid-full", "--gi", "none"});
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_EQ(none->gi, GlobalIllumination::None);
  // Settings made in code: resolved() keeps paths to the reference frame.
  FrameSettings s = *presetSettings("hybrid-full");
  s.gi = GlobalIllumination::Path;
  EXPECT_EQ(s.resolved().gi, GlobalIllumination::None);
  EXPECT_EQ(parseGlobalIllumination("path"), GlobalIllumination::Path);
  EXPECT_EQ(toString(GlobalIllumination::Path), "path");
}

TEST(FrameOptions, ScaleWithTheReferencePresetIsAnError) {
  EXPECT_TRUE(startsWith(errorOf({"--preset", "reference", "--scale", "2"}), "--scale: the reference preset"));
  auto ok = resolveArgs({"--preset", "hybrid-full", "--scale", "4"});
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ(ok->rayScale, 4);
}

TEST(FrameOptions, TargetFpsSetsTheFrameBudget) {
  auto r = resolveArgs({"--preset", "hybrid-full", "--target-fps", "20"});
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_FLOAT_EQ(r->targetMs, 50.0f);
  auto none = resolveArgs({"--preset", "hybrid-full"});
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_EQ(none->targetMs, 0.0f);
}

TEST(FrameOptions, ShadowProofsSayWhereHybridShadowsAreProved) {
  for (const auto& [name, where] : {std::pair{"auto", ShadowProofs::Auto}, std::pair{"gl", ShadowProofs::Gl},
                                    std::pair{"cpu", ShadowProofs::Cpu}, std::pair{"shafts", ShadowProofs::Shafts}}) {
    auto r = resolveArgs({"--shadows", "hybrid", "--shadow-proofs", name});
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_TRUE(r->hybridShadows);
    EXPECT_EQ(r->shadowProofs, where) << name;
  }
  auto none = resolveArgs({"--shadows", "hybrid"});
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_EQ(none->shadowProofs, ShadowProofs::Auto);
}

TEST(FrameOptions, ValidValuesAtTheEdgesAreTaken) {
  auto r = resolveArgs({"--preset", "reference", "--depth", "0", "--spp", "64", "--exposure", "0.125", "--tonemap",
                        "none", "--size", "3x2", "--shadows", "off", "--schlick", "--classic-whitted"});
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->maxDepth, 0);
  EXPECT_EQ(r->referenceSpp, 64);
  EXPECT_FLOAT_EQ(r->exposure, 0.125f);
  EXPECT_EQ(r->toneMap, ToneMap::None);
  EXPECT_EQ(r->width, 3);
  EXPECT_EQ(r->height, 2);
  EXPECT_EQ(r->shadows, EffectMode::Off);
  EXPECT_EQ(r->fresnel, FresnelMode::Schlick);
  EXPECT_FALSE(r->fresnelWeighted);
  auto deep = resolveArgs({"--depth", "64"});
  ASSERT_TRUE(deep) << deep.error().message;
  EXPECT_EQ(deep->maxDepth, 64);
}

Result<ResolvedFrame> resolveScene(std::initializer_list<std::string> args, const SceneRenderDefaults& scene) {
  CLI::App app;
  FrameOptions o;
  addFrameOptions(app, o);
  std::vector<std::string> reversed(args.begin(), args.end());
  std::reverse(reversed.begin(), reversed.end());
  app.parse(reversed);
  return resolveFrame(o, scene);
}

/// The fields a preset sets, compared one by one so a failure names the field.
void expectPresetFields(const FrameSettings& got, const FrameSettings& want) {
  EXPECT_EQ(got.shadows, want.shadows);
  EXPECT_EQ(got.reflections, want.reflections);
  EXPECT_EQ(got.refraction, want.refraction);
  EXPECT_EQ(got.maxDepth, want.maxDepth);
  EXPECT_EQ(got.minContribution, want.minContribution);
  EXPECT_EQ(got.rayScale, want.rayScale);
  EXPECT_EQ(got.reference, want.reference);
}

TEST(ResolveFrame, NoPresetAnywhereIsTheNamedDefault) {
  // It used to be FrameSettings{} (every effect by rays, depth 5), a combination no preset names.
  SceneRenderDefaults scene;
  scene.width = 320;
  scene.height = 200;
  auto r = resolveScene({}, scene);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->preset, kDefaultPreset);
  EXPECT_EQ(r->presetSource, "the default");
  EXPECT_TRUE(r->changedBy.empty());
  expectPresetFields(r->settings, *presetSettings(kDefaultPreset));
  EXPECT_EQ(r->settings.width, 320);
  EXPECT_EQ(r->settings.height, 200);
  EXPECT_EQ(std::string(kDefaultPreset), "hybrid-full");  // README and docs name it
}

TEST(ResolveFrame, TheScenesRenderBlockComesBeforeTheDefault) {
  SceneRenderDefaults scene;
  scene.preset = "raster";
  scene.maxDepth = 3;
  auto r = resolveScene({}, scene);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->preset, "raster");
  EXPECT_EQ(r->presetSource, "the scene's render.preset");
  EXPECT_EQ(r->settings.maxDepth, 3);
  EXPECT_EQ(r->changedBy, std::vector<std::string>{"the scene's render.maxDepth"});
  // maxDepth without a preset changes the default preset.
  SceneRenderDefaults depthOnly;
  depthOnly.maxDepth = 2;
  auto d = resolveScene({}, depthOnly);
  ASSERT_TRUE(d) << d.error().message;
  EXPECT_EQ(d->preset, kDefaultPreset);
  EXPECT_EQ(d->settings.maxDepth, 2);
}

TEST(ResolveFrame, PresetFlagReplacesTheScenesPresetAndDepthThenFlagsOverride) {
  SceneRenderDefaults scene;
  scene.preset = "raster";
  scene.maxDepth = 3;
  auto r = resolveScene({"--preset", "hybrid-fast", "--shadows", "off", "--depth", "4"}, scene);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->preset, "hybrid-fast");
  EXPECT_EQ(r->presetSource, "--preset");
  EXPECT_EQ(r->settings.shadows, EffectMode::Off);
  EXPECT_EQ(r->settings.maxDepth, 4);
  EXPECT_EQ(r->settings.rayScale, presetSettings("hybrid-fast")->rayScale);
  EXPECT_EQ(r->changedBy, (std::vector<std::string>{"--shadows", "--depth"}));
}

TEST(ResolveFrame, SppFollowsTheScenesReferencePreset) {
  SceneRenderDefaults scene;
  scene.preset = "reference";
  auto r = resolveScene({"--spp", "2"}, scene);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->settings.referenceSpp, 2);
  auto refused = resolveScene({"--spp", "2"}, SceneRenderDefaults{});
  ASSERT_FALSE(refused);
  EXPECT_TRUE(startsWith(refused.error().message, "--spp:")) << refused.error().message;
}

TEST(DescribeSettings, NamesWhatThePresetSets) {
  EXPECT_EQ(describeSettings(*presetSettings("hybrid-fast")),
            "shadows ray, reflections ray, refraction raster, depth 2, scale 1/2");
  FrameSettings reference = *presetSettings("reference");
  reference.referenceSpp = 4;
  EXPECT_EQ(describeSettings(reference),
            "shadows ray, reflections ray, refraction ray, depth 16, primary visibility by rays, 4×4 samples per pixel");
}

// --trace-pixel X,Y: a pixel of the frame, row 0 at the top; anything else one line naming the flag.
TEST(TracePixel, TakesAPixelOfTheFrameOnly) {
  auto corner = parseTracePixel("319,179", 320, 180);
  ASSERT_TRUE(corner) << corner.error().message;
  EXPECT_EQ(*corner, glm::ivec2(319, 179));
  EXPECT_EQ(*parseTracePixel("0,0", 1, 1), glm::ivec2(0, 0));
  for (const char* text : {"320,0", "0,180", "1000,1000"}) {
    auto r = parseTracePixel(text, 320, 180);
    ASSERT_FALSE(r) << text;
    EXPECT_TRUE(startsWith(r.error().message, "--trace-pixel: pixel (")) << r.error().message;
    EXPECT_NE(r.error().message.find("outside the 320x180 frame"), std::string::npos) << r.error().message;
  }
  for (const char* text : {"", "5", "5,", ",5", "-1,5", "5,-1", "5;5", "5,5,5", "5, 5", " 5,5", "+5,5", "a,b", "5x5",
                           "99999999999,5"}) {
    auto r = parseTracePixel(text, 320, 180);
    ASSERT_FALSE(r) << "'" << text << "'";
    EXPECT_TRUE(startsWith(r.error().message, "--trace-pixel: expected X,Y")) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace tandem::cli

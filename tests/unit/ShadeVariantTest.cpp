// The shade pass's variant key (gl/ShadeVariant.h): every flag is part of the key and of the defines, and
// every define it writes is one shade.frag declares a default for (so a misspelt flag cannot be silently
// ignored by the shader).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "core/Embedded.h"
#include "gl/ShadeVariant.h"

namespace tandem::gl {
namespace {

// One variant per flag, each differing from the default in that flag alone.
std::vector<ShadeVariant> eachFlagChanged() {
  std::vector<ShadeVariant> out;
  auto with = [&](auto change) {
    ShadeVariant v;
    change(v);
    out.push_back(v);
  };
  with([](ShadeVariant& v) { v.debugView = DebugView::NormalW; });
  with([](ShadeVariant& v) { v.shadowMaskPass = true; });
  with([](ShadeVariant& v) { v.shadowMask = true; });
  with([](ShadeVariant& v) { v.rayInputs = 3; });
  with([](ShadeVariant& v) { v.rayScaled = true; });
  with([](ShadeVariant& v) { v.gouraud = true; });
  with([](ShadeVariant& v) { v.toon = true; });
  with([](ShadeVariant& v) { v.uvs = true; });
  with([](ShadeVariant& v) { v.kdTextures = true; });
  with([](ShadeVariant& v) { v.colors = true; });
  with([](ShadeVariant& v) { v.normalMaps = true; });
  with([](ShadeVariant& v) { v.emissive = true; });
  with([](ShadeVariant& v) { v.alphaBlend = true; });
  with([](ShadeVariant& v) { v.lightCount = 3; });
  with([](ShadeVariant& v) { v.lightKinds = 0x21u; });
  with([](ShadeVariant& v) { v.areaLights = true; });
  with([](ShadeVariant& v) { v.uniformMaterials = 12; });
  with([](ShadeVariant& v) { v.shadowMaps = true; });
  with([](ShadeVariant& v) { v.softShadows = true; });
  with([](ShadeVariant& v) { v.probes = 2; });
  with([](ShadeVariant& v) { v.fresnelSchlick = true; });
  with([](ShadeVariant& v) { v.fresnelWeighted = false; });
  with([](ShadeVariant& v) { v.fusedOutput = true; });
  with([](ShadeVariant& v) { v.denoiseGuides = true; });
  with([](ShadeVariant& v) { v.radiosity = true; });
  with([](ShadeVariant& v) { v.exact = true; });
  with([](ShadeVariant& v) { v.procedural = true; });
  with([](ShadeVariant& v) { v.environment = true; });
  with([](ShadeVariant& v) { v.environmentAmbient = true; });
  with([](ShadeVariant& v) { v.distanceAlpha = true; });
  return out;
}

std::vector<std::string> defineNames(const ShadeVariant& v) {
  std::vector<std::string> names;
  v.forEachDefine([&](const char* name, const std::string&) { names.emplace_back(name); });
  return names;
}

TEST(ShadeVariant, EveryFlagIsPartOfTheKeyAndOfTheDefines) {
  const ShadeVariant base;
  const std::vector<ShadeVariant> changed = eachFlagChanged();
  // The list above covers every define the table writes: one changed variant per define.
  EXPECT_EQ(changed.size(), defineNames(base).size());
  std::set<ShadeVariant> keys{base};
  std::set<std::string> defines{base.defines()};
  for (const ShadeVariant& v : changed) {
    EXPECT_NE(v, base);
    keys.insert(v);
    defines.insert(v.defines());
  }
  // Each changed flag gives a key and a define text of its own: no two flags collapse into one.
  EXPECT_EQ(keys.size(), changed.size() + 1);
  EXPECT_EQ(defines.size(), changed.size() + 1);
}

TEST(ShadeVariant, DefinesAreOneLinePerFlagInTheTablesOrder) {
  ShadeVariant v;
  v.lightCount = 2;
  v.lightKinds = 0x31u;
  v.debugView = DebugView::Reflection;
  const std::string d = v.defines();
  EXPECT_EQ(d.rfind("#define TD_DEBUG_VIEW 6\n", 0), 0u);
  EXPECT_NE(d.find("#define TD_LIGHT_COUNT 2\n"), std::string::npos);
  EXPECT_NE(d.find("#define TD_LIGHT_KINDS 49u\n"), std::string::npos);  // an unsigned literal: GLSL shifts it
  EXPECT_NE(d.find("#define TD_FRESNEL_WEIGHTED 1\n"), std::string::npos);
  EXPECT_EQ(static_cast<std::size_t>(std::count(d.begin(), d.end(), '\n')), defineNames(v).size());
}

TEST(ShadeVariant, ShadeFragDeclaresADefaultForEveryDefine) {
  // The shader's #ifndef NAME defaults are the variant with every feature on (ShadePass::create compiles
  // it); a define the table writes without one would be a name the shader never reads.
  auto frag = findEmbedded("shaders/shade.frag");
  ASSERT_TRUE(frag.has_value());
  const std::string text(*frag);
  for (const std::string& name : defineNames(ShadeVariant{}))
    EXPECT_NE(text.find("#ifndef " + name + "\n"), std::string::npos) << name << " has no default in shade.frag";
}

}  // namespace
}  // namespace tandem::gl

#pragma once
// The flags one variant of the shade pass (shade.frag) is compiled for, as a typed value: the variant cache's
// key, and the one table from which the shader's TD_* defines are written. Plain data, no GL calls, so its
// rules are unit tests (tests/unit/ShadeVariantTest.cpp). ShadePass::variant fills it from the scene's
// features (GpuScene::features) and the frame's inputs.
//
// A flag added here is a member, a line in forEachDefine and the shader's #ifndef default (the unit test
// checks that every define the table writes has one in shade.frag, and that every flag changes the key).
#include <compare>
#include <cstdint>
#include <string>

#include "tandem/Settings.h"

namespace tandem::gl {

struct ShadeVariant {
  DebugView debugView = DebugView::Final;
  bool shadowMaskPass = false;  // the shadow-mask pass itself (its own outputs; no view, rays or probes)
  bool shadowMask = false;      // raster shadows gathered from the mask's grid instead of the maps
  int rayInputs = 0;            // TD_RAY_* bits the frame's plan can produce
  bool rayScaled = false;       // rayScale > 1: edge-aware upsampling
  bool gouraud = false, toon = false;
  bool uvs = false, kdTextures = false, colors = false, normalMaps = false, emissive = false;
  bool alphaBlend = false;
  int lightCount = 0;           // the direct-light loop's compile-time bound
  std::uint32_t lightKinds = 0;  // each light's type and map kind, 4 bits each (SceneFeatures::lightKinds)
  bool areaLights = false;
  int uniformMaterials = 0;     // material count in a uniform block, 0: an SSBO
  bool shadowMaps = false, softShadows = false;
  int probes = 0;               // ProbeEffect bits with a probe array, else 0
  bool fresnelSchlick = false, fresnelWeighted = true;
  bool fusedOutput = false;     // the display written as well (TD_FUSED_OUTPUT)
  bool denoiseGuides = false;   // the spatiotemporal filter's guides written as well (TD_DENOISE_GUIDES)
  bool radiosity = false, exact = false, procedural = false;
  bool environment = false;         // the environment varies with direction (a sky or an image: docs/environment.md)
  bool environmentAmbient = false;  // and lights the ambient term
  bool distanceAlpha = false;       // alpha holds the hit's distance from the camera (gl/BehindView.h's layers)

  auto operator<=>(const ShadeVariant&) const = default;

  /// Calls f(name, value) for each define, in the order the shader sees them; value is the define's text.
  template <class F>
  void forEachDefine(F&& f) const {
    auto flag = [](bool b) { return std::string(b ? "1" : "0"); };
    f("TD_DEBUG_VIEW", std::to_string(static_cast<int>(debugView)));
    f("TD_SHADOW_MASK_PASS", flag(shadowMaskPass));
    f("TD_SHADOW_MASK", flag(shadowMask));
    f("TD_RAY_INPUTS", std::to_string(rayInputs));
    f("TD_RAY_SCALED", flag(rayScaled));
    f("TD_USE_GOURAUD", flag(gouraud));
    f("TD_USE_TOON", flag(toon));
    f("TD_USE_UVS", flag(uvs));
    f("TD_USE_KD_TEXTURES", flag(kdTextures));
    f("TD_USE_COLORS", flag(colors));
    f("TD_USE_NORMAL_MAPS", flag(normalMaps));
    f("TD_USE_EMISSIVE", flag(emissive));
    f("TD_USE_ALPHA_BLEND", flag(alphaBlend));
    f("TD_LIGHT_COUNT", std::to_string(lightCount));
    f("TD_LIGHT_KINDS", std::to_string(lightKinds) + "u");
    f("TD_USE_AREA_LIGHTS", flag(areaLights));
    f("TD_UNIFORM_MATERIALS", std::to_string(uniformMaterials));
    f("TD_SHADOW_MAPS", flag(shadowMaps));
    f("TD_SOFT_SHADOWS", flag(softShadows));
    f("TD_PROBES", std::to_string(probes));
    f("TD_FRESNEL_SCHLICK", flag(fresnelSchlick));
    f("TD_FRESNEL_WEIGHTED", flag(fresnelWeighted));
    f("TD_FUSED_OUTPUT", flag(fusedOutput));
    f("TD_DENOISE_GUIDES", flag(denoiseGuides));
    f("TD_USE_RADIOSITY", flag(radiosity));
    f("TD_USE_EXACT", flag(exact));
    f("TD_USE_PROCEDURAL", flag(procedural));
    f("TD_USE_ENVIRONMENT", flag(environment));
    f("TD_USE_ENV_AMBIENT", flag(environmentAmbient));
    f("TD_DISTANCE_ALPHA", flag(distanceAlpha));
  }

  /// The #define lines the variant is compiled with (buildProgram puts them after #version).
  std::string defines() const {
    std::string out;
    forEachDefine([&](const char* name, const std::string& value) {
      out += "#define ";
      out += name;
      out += ' ';
      out += value;
      out += '\n';
    });
    return out;
  }
};

}  // namespace tandem::gl

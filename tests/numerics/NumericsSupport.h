#pragma once
// Shared helpers of the numerical-extremes tests (docs/numerics.md): whole-scene similarity transforms,
// renders through the CPU ray pass only (no GL), and the checks every extreme shares (finite buffers,
// light-mask agreement, FLIP on the tone-mapped image).
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "support/SceneTransform.h"
#include "core/Shading.h"
#include "rt/CpuComposite.h"
#include "rt/RayTracer.h"
#include "rt/RtTestScenes.h"
#include "tandem/Image.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Scene.h"
#include "tandem/SceneFile.h"
#include "tandem/Settings.h"

namespace tandem::numerics {

using namespace tandem::rt;
using namespace tandem::rt::test;

inline std::size_t pixelIndex(int x, int y, int w) {
  return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
}

/// world' = offset + scale · world, applied to everything that carries a length: instance transforms,
/// light positions, ranges and attenuation (so light reaching a scaled point is unchanged), the camera
/// and its clip distances. Computed in double so only the final rounding to float remains: that rounding
/// of the *input* is part of what the extremes test.
inline Scene whittedScene() {
  Result<Scene> s = loadDefaultScene();
  EXPECT_TRUE(s.ok());
  return s ? std::move(*s) : Scene{};
}

/// Every output of a frame: the reference image, and the hybrid ray pass on castVisibility ids with its
/// CPU composite.
struct Frame {
  ImageF reference;
  VisibilityBuffer vis;
  RayOutputs rays;
  ImageF composite;
  RayCounts referenceCounts;
};

inline FrameSettings numericsSettings(int w, int h) {
  FrameSettings s = settingsFor(w, h);
  s.shadows = s.reflections = s.refraction = EffectMode::Ray;
  return s;
}

inline Frame renderFrame(RayTracer& rt, const Scene& scene, const FrameSettings& s) {
  Frame f;
  rt.renderReference(scene, scene.camera, s, f.reference, f.referenceCounts);
  rt.castVisibility(scene.camera, s.width, s.height, f.vis);
  rt.trace(scene, scene.camera, s, f.vis, f.rays);
  compositeOnCpu(scene, scene.camera, s, f.vis, f.rays, f.composite);
  return f;
}

inline Frame renderFrame(const Scene& scene, const FrameSettings& s, int threads = 2) {
  auto rt = makeTracer(scene, threads);
  if (!rt) return {};
  return renderFrame(*rt, scene, s);
}

inline bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(glm::vec4 v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }

/// Non-finite values in every float buffer of a frame.
inline std::size_t nonFiniteCount(const Frame& f) {
  std::size_t n = 0;
  for (const glm::vec3& c : f.reference.rgb) n += !finite(c);
  for (const glm::vec3& c : f.composite.rgb) n += !finite(c);
  for (const glm::vec4& c : f.rays.reflected) n += !finite(c);
  for (const glm::vec4& c : f.rays.transmitted) n += !finite(c);
  return n;
}

/// Linear radiance → display sRGB 8-bit through the engine's tone map (what FLIP should judge).
inline Image toDisplay(const ImageF& in, int toneMap = TD_TONEMAP_ACES) {
  Image out;
  out.width = in.width;
  out.height = in.height;
  out.rgba.resize(in.rgb.size() * 4);
  for (std::size_t i = 0; i < in.rgb.size(); ++i) {
    glm::vec3 c = shading::tdSrgbEncode(shading::tdToneMap(in.rgb[i], toneMap));
    for (int k = 0; k < 3; ++k)
      out.rgba[4 * i + static_cast<std::size_t>(k)] =
          static_cast<std::uint8_t>(glm::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    out.rgba[4 * i + 3] = 255;
  }
  return out;
}

inline double flipMean(const ImageF& test, const ImageF& reference) {
  Result<FlipResult> r = flip(toDisplay(test), toDisplay(reference));
  EXPECT_TRUE(r.ok());
  return r ? r->mean : 1.0;
}

/// Light-mask agreement of two frames of the same scene at the same pixel grid (scale 1).
/// acne: a light the baseline sees is lost; leak: a light the baseline does not see is gained.
/// Only pixels inside a region of constant ids and constant baseline mask (3×3) count: a shadow or
/// silhouette edge may move by a fraction of a pixel when the scene's coordinates are rounded differently.
struct MaskDiff {
  int compared = 0;
  int acne = 0;
  int leaks = 0;
};
inline MaskDiff compareMasks(const Frame& base, const Frame& test) {
  MaskDiff d;
  const int w = base.vis.width, h = base.vis.height;
  if (base.rays.lightMask.empty() || test.rays.lightMask.empty()) return d;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      std::size_t i = pixelIndex(x, y, w);
      if (base.vis.ids[i].x == 0) continue;
      bool stable = true;
      for (int dy = -1; dy <= 1 && stable; ++dy)
        for (int dx = -1; dx <= 1 && stable; ++dx) {
          std::size_t j = pixelIndex(x + dx, y + dy, w);
          stable = base.vis.ids[j].x == base.vis.ids[i].x && test.vis.ids[j].x == base.vis.ids[i].x &&
                   base.rays.lightMask[j] == base.rays.lightMask[i];
        }
      if (!stable) continue;
      ++d.compared;
      std::uint32_t b = base.rays.lightMask[i], t = test.rays.lightMask[i];
      d.acne += (b & ~t) != 0;
      d.leaks += (t & ~b) != 0;
    }
  return d;
}

}  // namespace tandem::numerics

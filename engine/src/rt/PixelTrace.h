#pragma once
// A single-pixel re-run of the ray pass that records the pixel's ray tree (tandem/PixelTrace.h).
// It is a separate, explicit call: the passes' loops know nothing of it. It runs the recursion the passes
// are built on (Whitted::shade / secondary / radiance / lightMask) with a recorder in place of their
// NoRecorder, so every number it reports is computed by the same code: the hybrid pass's wavefront is
// bit-identical to that recursion (tests/rt WavefrontEqualsTheRecursionBitForBit), and the reference
// frame calls it directly.
#include "rt/EmbreeScene.h"
#include "rt/RayBuffers.h"
#include "rt/ShadowCertainty.h"
#include "tandem/Camera.h"
#include "tandem/PixelTrace.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::rt {

/// RayTracer::trace's work for ray-grid pixel (gx, gy) of `visibility` (which must lie on the grid of
/// settings.rayScale): the exact primary hit of the visible triangle, its shadow rays, reflection and
/// refraction, recorded. `settings` are the ones trace() was given. The result's local, reflected,
/// transmitted and lightMask are what trace() and the CPU twin of the shade pass give that pixel.
/// PixelTrace::settings are `settings` and rayPass is true; a caller that knows more of the frame (the
/// Renderer: its raster effects) replaces them and adds the notes.
PixelTrace traceHybridPixel(const Scene& scene, const EmbreeScene& embree, const Camera& camera,
                            const FrameSettings& settings, const VisibilityBuffer& visibility, int gx, int gy,
                            const ShadowCertainty* shadowMaps = nullptr, const RadiosityField* radiosity = nullptr);

/// RayTracer::renderReference's work for pixel (x, y) of a settings.width × settings.height frame: every
/// sample's camera ray, recorded; `color` is the frame's pixel.
PixelTrace traceReferencePixel(const Scene& scene, const EmbreeScene& embree, const Camera& camera,
                               const FrameSettings& settings, int x, int y, const RadiosityField* radiosity = nullptr);

}  // namespace tandem::rt

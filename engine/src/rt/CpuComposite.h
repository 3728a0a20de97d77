#pragma once
// A CPU composite of the hybrid frame on the ray grid: for each grid pixel, the local shading of its exact
// primary hit (the CPU twin of the GL shade pass, visibility from the ray pass's light mask) plus the
// reflected and transmitted radiance. Tests compare it with the reference tracer; the Renderer can use it
// to check the GL composite. Linear radiance, before exposure and tone mapping.
#include "rt/RayTracer.h"
#include "tandem/Camera.h"
#include "tandem/Image.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::rt {

/// out: rays.width × rays.height. Background pixels get Scene::background. An empty light mask means
/// every light visible (shadows off, or no shadow ray needed); shadow maps (shadows = Raster) are GL's
/// and are not modelled here.
void compositeOnCpu(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                    const VisibilityBuffer& visibility, const RayOutputs& rays, ImageF& out);

}  // namespace tandem::rt

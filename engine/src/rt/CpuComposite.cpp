#include "rt/CpuComposite.h"

#include <algorithm>
#include <cassert>

#include "core/Motion.h"
#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"

namespace tandem::rt {

void compositeOnCpu(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                    const VisibilityBuffer& visibility, const RayOutputs& rays, ImageF& out) {
  const int scale = std::max(1, settings.rayScale);
  const int width = visibility.width, height = visibility.height;
  assert(rays.width == gridSize(width, scale) && rays.height == gridSize(height, scale));
  out.width = rays.width;
  out.height = rays.height;
  out.rgb.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height), scene.background);
  // Camera-relative, as the ray pass (docs/numerics.md): positions relative to the camera stay precise
  // far from the world origin.
  const glm::vec3 anchor = camera.posW;
  const Camera cam = toRenderSpace(camera, anchor);
  FrameShading frame(scene, settings.shadingOverride, anchor);
  frame.setLightSampling(settings.lightSamples, settings.unfilteredLightSamples(), camera.sampleIndex);
  const std::size_t plane = rays.lightMask.size();
  for (int gy = 0; gy < out.height; ++gy)
    for (int gx = 0; gx < out.width; ++gx) {
      std::size_t g = static_cast<std::size_t>(gy) * static_cast<std::size_t>(out.width) + static_cast<std::size_t>(gx);
      glm::ivec2 p = fullPixelOfGridPixel(gx, gy, scale, width, height);
      glm::uvec2 id = visibility.ids[static_cast<std::size_t>(p.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(p.x)];
      Ray ray = cam.rayThroughPixel(glm::vec2(p) + 0.5f, {width, height});
      // Nothing there (or an id not in the scene, which the pass skips too): the environment.
      const bool known = id.x != 0 && id.x <= scene.instances.size();
      const Mesh* mesh = known ? &scene.meshes[scene.instances[id.x - 1].mesh] : nullptr;
      if (!mesh || (id.y == kExactTriangle ? !mesh->exact : id.y >= mesh->triangleCount())) {
        out.rgb[g] = frame.environment.radiance(ray.dir);
        continue;
      }
      std::uint32_t instance = id.x - 1;
      // A moving instance where the frame's shutter time puts it, as the rasterizer drew it.
      const Instance& inst = scene.instances[instance];
      InstanceTransform transform =
          isMoving(inst, camera.shutter)
              ? makeInstanceTransform(motionAt(motionSteps(inst, camera.shutter, anchor), camera.timeU))
              : makeInstanceTransform(inst.worldFromObject, anchor);
      transform.anchor = anchor;  // the motion steps are in render space already
      SurfaceHit hit = resolvePrimary(scene, transform, cam, id, ray);
      hit.time = camera.timeU;
      hit.lightSeed = shading::tdPixelSeed(p.x, p.y, 0u);
      std::uint32_t mask = rays.lightMask.empty() ? ~0u : rays.lightMask[g];
      AreaSampleBits area{};
      for (int a = 0; a < rays.areaLights; ++a)
        area[static_cast<std::size_t>(a)] = rays.areaSamples[static_cast<std::size_t>(a) * plane + g];
      glm::vec3 c = shadeLocal(scene, frame, transform, hit, mask, rays.areaLights > 0 ? &area : nullptr);
      if (!rays.reflected.empty()) c += glm::vec3(rays.reflected[g]);
      if (!rays.transmitted.empty()) c += glm::vec3(rays.transmitted[g]);
      out.rgb[g] = c;
    }
}

}  // namespace tandem::rt

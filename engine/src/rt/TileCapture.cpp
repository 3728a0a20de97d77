#include "rt/TileCapture.h"

#include <limits>

namespace tandem::rt {

namespace {
std::vector<CapturedRay>& raysOf(RayCaptureTile& tile, RayKind kind) { return tile.rays[static_cast<std::size_t>(kind)]; }
}  // namespace

std::size_t TileCapture::deferred(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar,
                                  std::uint8_t group) {
  std::vector<CapturedRay>& rays = raysOf(tile_, kind);
  rays.push_back(CapturedRay{originW, tNear, dirW, tFar, false, true, group});
  return rays.size() - 1;
}

void TileCapture::answer(RayKind kind, std::size_t index, bool hit, bool traced) {
  std::vector<CapturedRay>& rays = raysOf(tile_, kind);
  if (index >= rays.size()) return;
  rays[index].hit = hit;
  rays[index].traced = traced;
}

void TileCapture::rasterPrimary(glm::vec3 originW, glm::vec3 dirW) {
  answer(RayKind::Primary, deferred(RayKind::Primary, originW, dirW, 0.0f, std::numeric_limits<float>::infinity()),
         true, false);
}

void TileCapture::beginRay(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, glm::vec3,
                           float) {
  pendingIndex_ = deferred(kind, originW, dirW, tNear, tFar);
  pendingKind_ = kind;
  hasPending_ = true;
}

CapturedRay* TileCapture::pending() {
  if (!hasPending_) return nullptr;
  hasPending_ = false;
  return &raysOf(tile_, pendingKind_)[pendingIndex_];
}

void TileCapture::embreeHit(std::uint32_t, std::uint32_t, float) {
  if (CapturedRay* r = pending()) r->hit = true;
}

void TileCapture::notTraced() {
  if (CapturedRay* r = pending()) r->traced = false;
}

void TileCapture::shadowRay(std::size_t light, const ShadowRay& ray, bool occluded) {
  answer(RayKind::Shadow, deferred(RayKind::Shadow, ray.originW, ray.dirW, 0.0f, ray.tFar, static_cast<std::uint8_t>(light)),
         occluded);
}

}  // namespace tandem::rt

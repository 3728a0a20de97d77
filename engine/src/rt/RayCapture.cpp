#include "rt/RayCapture.h"

namespace tandem::rt {

namespace {
// Per thread, because tiles run in parallel and the hooks sit deep in the Whitted recursion, whose
// signatures should not change for a measurement tool. A tile runs start to end on one thread (its body
// spawns no TBB tasks), so the thread identifies the tile.
thread_local RayCaptureTile* tCurrent = nullptr;
thread_local bool tHasPending = false;
thread_local RayKind tPendingKind = RayKind::Primary;
thread_local std::size_t tPendingIndex = 0;

std::size_t idx(RayKind k) { return static_cast<std::size_t>(k); }
}  // namespace

const char* toString(RayKind kind) {
  switch (kind) {
    case RayKind::Primary: return "primary";
    case RayKind::Shadow: return "shadow";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
  }
  return "?";
}

void RayCapture::clear() {
  tiles.clear();
  width = height = 0;
  primaryTraced = false;
}

std::size_t RayCapture::count(RayKind kind) const {
  std::size_t n = 0;
  for (const RayCaptureTile& t : tiles) n += t.rays[idx(kind)].size();
  return n;
}

RayCounts RayCapture::counts() const {
  RayCounts c;
  c.primary = count(RayKind::Primary);
  c.shadow = count(RayKind::Shadow);
  c.reflection = count(RayKind::Reflection);
  c.refraction = count(RayKind::Refraction);
  return c;
}

namespace capture {

TileScope::TileScope(RayCapture* capture, std::size_t tile) : previous_(tCurrent) {
  tCurrent = capture && tile < capture->tiles.size() ? &capture->tiles[tile] : nullptr;
  tHasPending = false;
}

TileScope::~TileScope() {
  tCurrent = previous_;
  tHasPending = false;
}

bool active() { return tCurrent != nullptr; }

std::size_t recordDeferred(RayKind kind, glm::vec3 origin, glm::vec3 dir, float tnear, float tfar) {
  if (!tCurrent) return 0;
  std::vector<CapturedRay>& v = tCurrent->rays[idx(kind)];
  v.push_back(CapturedRay{origin, tnear, dir, tfar, false, true});
  return v.size() - 1;
}

std::size_t record(RayKind kind, glm::vec3 origin, glm::vec3 dir, float tnear, float tfar) {
  if (!tCurrent) return 0;
  std::vector<CapturedRay>& v = tCurrent->rays[idx(kind)];
  v.push_back(CapturedRay{origin, tnear, dir, tfar, false, true});
  tHasPending = true;
  tPendingKind = kind;
  tPendingIndex = v.size() - 1;
  return tPendingIndex;
}

void resolvePending(bool hit, bool traced) {
  if (!tCurrent || !tHasPending) return;
  CapturedRay& r = tCurrent->rays[idx(tPendingKind)][tPendingIndex];
  r.hit = hit;
  r.traced = traced;
  tHasPending = false;
}

void setHit(RayKind kind, std::size_t index, bool hit, bool traced) {
  if (!tCurrent) return;
  std::vector<CapturedRay>& v = tCurrent->rays[idx(kind)];
  if (index < v.size()) {
    v[index].hit = hit;
    v[index].traced = traced;
  }
}

}  // namespace capture
}  // namespace tandem::rt

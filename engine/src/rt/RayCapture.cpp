#include "rt/RayCapture.h"

namespace tandem::rt {

namespace {
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

const char* toString(RetraceApi api) {
  switch (api) {
    case RetraceApi::Single: return "1";
    case RetraceApi::Stream: return "1M";
    case RetraceApi::Packet: return "8";
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

}  // namespace tandem::rt

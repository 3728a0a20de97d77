#include "rt/Wavefront.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <limits>

#include "rt/RayReuse.h"
#include "rt/TileCapture.h"

namespace tandem::rt {

void ShadowBatch::clear() {
  byMap_ = kept_ = byShaft_ = 0;
  groups_.clear();
  shafts_ = nullptr;
  for (auto& rays : byLight_) rays.clear();
  for (auto& captured : capturedByLight_) captured.clear();
  areaRays_.clear();
  areaSlots_.clear();
  areaBits_.clear();
  areaWords_.clear();
  samples_.clear();
  areaCaptured_.clear();
}

template <class Capture>
std::uint32_t ShadowBatch::add(const Whitted& whitted, std::size_t lights, const ShadowPoint& hit, std::size_t slot,
                               Capture& capture, const ShadowKeep* keep, std::uint32_t* area, std::size_t areaStride,
                               std::uint32_t proof, int depth) {
  std::uint32_t visible = 0;
  SpawnOrigins origins;
  // The lights towards which the point's tile shaft is clear (prepareShafts; none without shafts).
  const std::uint32_t shaftLit = groups_.empty() ? 0u : litByShaft(hit);
  const FrameShading& frame = whitted.frame();
  const LightSampling& sampling = frame.lightAt(depth);
  for (std::size_t j = 0; j < lights; ++j) {
    if (frame.isArea(j)) {
      assert(area && "ShadowBatch::add: a frame with area lights needs their sample words");
      std::uint32_t& word = area[static_cast<std::size_t>(frame.areaSlot(j)) * areaStride];
      word = 0;
      const bool keepable = keep && ((keep->lights >> j) & 1u);
      for (int k = 0; k < sampling.count; ++k) {
        ShadowRay s = whitted.areaShadowRay(hit, j, sampling, k, origins, NoRecorder{});
        if (!s.needed) {
          if (s.visibleWithoutRay) word |= 1u << k;
          continue;
        }
        if (keepable && keep->gate->clearOfMoved(*keep->tile, j, s.originW, s.dirW, s.tFar)) {
          word |= keep->gate->keptArea(keep->grid, frame.areaSlot(j)) & (1u << k);
          ++kept_;
          continue;
        }
        areaRays_.emplace_back();
        makeEmbreeRay(areaRays_.back(), s.originW, s.dirW, 0.0f, s.tFar, hit.time);
        areaSlots_.push_back(slot);
        areaBits_.push_back(1u << j);
        areaWords_.push_back(&word);
        samples_.push_back(static_cast<std::uint8_t>(k));
        if constexpr (Capture::kRecords)
          areaCaptured_.push_back(capture.deferred(RayKind::Shadow, s.originW, s.dirW, 0.0f, s.tFar, static_cast<std::uint8_t>(j)));
      }
      if (word != 0) visible |= 1u << j;
      continue;
    }
    // The tile's shaft towards the light is clear (prepareShafts): the ray, if the point needs one, reaches
    // it, and a point that needs none is lit too (Whitted::noShadowRay), so nothing is set up.
    if (((shaftLit >> j) & 1u) != 0) {
      visible |= 1u << j;
      ++byShaft_;
      continue;
    }
    // Whitted::shadowRay in its two steps, with the kept frame's answer between them: it costs a box test
    // per moved instance near the tile, the map a texel fetch.
    ShadowRay s = whitted.shadowRayUnanswered(hit, j, origins, NoRecorder{});
    if (keep && s.needed && ((keep->lights >> j) & 1u) &&
        keep->gate->clearOfMoved(*keep->tile, j, s.originW, s.dirW, s.tFar)) {
      visible |= keep->bits & (1u << j);
      ++kept_;
      continue;
    }
    if (s.needed && ((proof >> (kProofDecidedShift + j)) & 1u)) {
      // The GL proved this ray's answer (shaders/shadow_proof.frag): the ray is not traced.
      visible |= ((proof >> j) & 1u) << j;
      ++byMap_;
      continue;
    }
    if (s.needed) whitted.answerByMap(hit, j, s, NoRecorder{});
    if (!s.needed) {
      if (s.visibleWithoutRay) visible |= 1u << j;
      if (s.byMap) ++byMap_;
      continue;
    }
    // makeEmbreeRay's checks hold already (origin and direction finite: shadowRay; tFar > 0 or +inf), so
    // the lane is written straight from them.
    byLight_[j].push_back({s.originW, s.tFar, s.dirW, embreeTime(hit.time), static_cast<std::uint32_t>(slot)});
    if constexpr (Capture::kRecords)
      capturedByLight_[j].push_back(capture.deferred(RayKind::Shadow, s.originW, s.dirW, 0.0f, s.tFar, static_cast<std::uint8_t>(j)));
  }
  return visible;
}

void ShadowBatch::decideShafts(const Whitted& whitted) {
  const FrameShading& frame = whitted.frame();
  for (ShaftGroup& g : groups_) {
    const double lift = static_cast<double>(g.lift) + 1e-30;
    for (std::size_t j = 0; j < frame.lights.size() && j < static_cast<std::size_t>(kMaxLights); ++j) {
      if (frame.isArea(j) || !frame.castsShadows(j)) continue;
      const shading::GpuLight& light = frame.lights[j];
      ShaftBox from, to;
      from.lo = glm::dvec3(g.lo) - lift;
      from.hi = glm::dvec3(g.hi) + lift;
      double magnitude = std::max(maxAbs(from.lo), maxAbs(from.hi));
      // The sine at which the rays leave the plane, bounded for the whole group (TileShafts::kMinRise; with a
      // hundredth to spare for the hits' float normals).
      const glm::dvec3 normal = shafts_->planeNormal(g.instance);
      double rise = 0.0;
      if (static_cast<int>(light.posType.w + 0.5f) == TD_LIGHT_DIRECTIONAL) {
        // Every ray has the light's direction (tdLightIncident's -dirRange, exactly): past the scene, its rays
        // are in `from` moved along it.
        const glm::dvec3 toLight = -glm::dvec3(glm::vec3(light.dirRange));
        rise = std::abs(glm::dot(normal, toLight)) / glm::length(toLight);
        const glm::dvec3 along = shafts_->beyondScene(from, magnitude) / glm::length(toLight) * toLight;
        to.lo = from.lo + along;
        to.hi = from.hi + along;
      } else {
        // A ray from p ends short of the light on the segment from p to it, up to its offset and the rounding
        // of its direction and length (a millionth of the distance, grown fourfold).
        const glm::dvec3 at(glm::vec3(light.posType));
        const double reach = glm::length(glm::max(glm::abs(at - from.lo), glm::abs(at - from.hi)));
        const double slack = 4e-6 * reach;
        from.lo -= slack;
        from.hi += slack;
        to.lo = at - (lift + slack);
        to.hi = at + (lift + slack);
        magnitude = std::max(magnitude, reach);
        // From any point of the plane the sine is the light's height over it by the distance to it.
        // (Less the points' own distance from the exact plane, which their lift bounds.)
        rise = (std::abs(glm::dot(normal, at) - shafts_->planeOffset(g.instance)) - lift) / reach;
      }
      if (rise >= 1.01 * TileShafts::kMinRise && shafts_->clearOfOthers(g.instance, from, to, magnitude)) g.lit |= 1u << j;
    }
  }
}

std::size_t ShadowBatch::findGroup(std::uint32_t instance) {
  if (lastGroup_ < groups_.size() && groups_[lastGroup_].instance == instance) return lastGroup_;
  lastGroup_ = 0;
  while (lastGroup_ < groups_.size() && groups_[lastGroup_].instance != instance) ++lastGroup_;
  return lastGroup_;
}

std::uint32_t ShadowBatch::litByShaft(const ShadowPoint& hit) {
  if (findGroup(hit.instance) == groups_.size()) return 0u;  // not a plane's point
  const ShaftGroup& g = groups_[lastGroup_];
  if (g.lit == 0) return 0u;
  // Only a point the group holds (prepareShafts saw it: in its box, its offset within its lift).
  const bool held = hit.triangle != kExactTriangle && hit.time == shafts_->time() &&
                    glm::all(glm::greaterThanEqual(hit.posW, g.lo)) && glm::all(glm::lessThanEqual(hit.posW, g.hi)) &&
                    offsetLift(hit.posW, hit.posMagnitude) <= g.lift;
  return held ? g.lit : 0u;
}

template <class Capture>
void ShadowBatch::trace(RTCScene scene, LightMask* masks, RayCounts& counts, Capture& capture) {
  counts.shadowByMap += byMap_;
  counts.shadowKept += kept_;
  byMap_ = kept_ = 0;
  counts.shadowByShaft += byShaft_;
  byShaft_ = 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  // Packets of rays towards one light, neighbouring hits first: such rays start close together and
  // converge, so Embree's packet traversal visits a node once for all of them. Measured on the Whitted
  // scene at 1280x720: these rays 23 % faster than one rtcOccluded1M call per tile (the floor, 57 -> 44 ms),
  // the whole ray pass ~8 % (docs/bench.md). The context is
  // left incoherent: with RTC_INTERSECT_CONTEXT_FLAG_COHERENT, Debian's Embree 3.13.5 never returned
  // from one tile's rtcOccluded1M (tests/rt GlassSlab after the grazing-light scenes).
  // Area lights' rays one by one: Embree's packet traversal turns to single rays once few lanes are left
  // active, so a ray's arithmetic depends on its packet's other rays, and a ray starting within an ulp of
  // another surface (a wall's foot on the floor) can get another answer when the packet changes. Reuse
  // across frames keeps per-sample answers and so changes the packets of the samples it traces; single
  // rays make each answer the ray's own, as the frame traced whole gives it (docs/reuse.md).
  for (std::size_t i = 0; i < areaRays_.size(); ++i) {
    rtcOccluded1(scene, &ctx, &areaRays_[i]);
    // Embree marks an occluded ray by tfar = -inf.
    const bool visible = areaRays_[i].tfar >= 0.0f;
    if (visible) {
      masks[areaSlots_[i]] = static_cast<LightMask>(masks[areaSlots_[i]] | areaBits_[i]);
      *areaWords_[i] |= 1u << samples_[i];
    }
    if constexpr (Capture::kRecords) capture.answer(RayKind::Shadow, areaCaptured_[i], !visible);
  }
  counts.shadow += areaRays_.size();
  RTCRay8 packet{};  // inactive lanes of a last, partial packet stay defined
  alignas(32) int valid[kPacket];
  for (std::size_t j = 0; j < byLight_.size(); ++j) {
    const std::vector<LaneRay>& rays = byLight_[j];
    const auto bit = static_cast<LightMask>(1u << j);
    for (std::size_t start = 0; start < rays.size(); start += kPacket) {
      const std::size_t lanes = std::min<std::size_t>(kPacket, rays.size() - start);
      for (std::size_t k = 0; k < static_cast<std::size_t>(kPacket); ++k) {
        valid[k] = k < lanes ? -1 : 0;
        if (k >= lanes) continue;
        const LaneRay& r = rays[start + k];
        packet.org_x[k] = r.org.x;
        packet.org_y[k] = r.org.y;
        packet.org_z[k] = r.org.z;
        packet.tnear[k] = 0.0f;
        packet.dir_x[k] = r.dir.x;
        packet.dir_y[k] = r.dir.y;
        packet.dir_z[k] = r.dir.z;
        packet.time[k] = r.time;
        packet.tfar[k] = r.tfar;
        packet.mask[k] = 0xFFFFFFFFu;
        packet.id[k] = 0;
        packet.flags[k] = 0;
      }
      rtcOccluded8(valid, scene, &ctx, &packet);
      for (std::size_t k = 0; k < lanes; ++k) {
        const bool visible = packet.tfar[k] >= 0.0f;
        if (visible) masks[rays[start + k].slot] = static_cast<LightMask>(masks[rays[start + k].slot] | bit);
        if constexpr (Capture::kRecords) capture.answer(RayKind::Shadow, capturedByLight_[j][start + k], !visible);
      }
    }
    counts.shadow += rays.size();
  }
}

Wavefront::Wavefront(const Whitted& whitted, Buffers& buffers) : whitted_(whitted), b_(buffers) {
  b_.nodes.clear();
}

template <class Capture>
void Wavefront::addPrimary(const SurfaceHit& hit, std::size_t pixel, RayCounts& counts, Capture& capture) {
  spawn(hit, 0, 1.0f, -1, pixel, counts, capture);
}

// Whitted::secondary's decisions, queuing the rays instead of recursing into them.
template <class Capture>
void Wavefront::spawn(const SurfaceHit& hit, int depth, float throughput, std::int64_t parent, std::size_t pixel,
                      RayCounts& counts, Capture& capture) {
  const TraceModes& modes = whitted_.modes();
  if (!modes.spawnsAt(depth)) return;
  const std::size_t first = b_.nodes.size();
  // A surface that spawns no ray: its weights are not worked out.
  if (spawnsNoRay(whitted_.frame().materials[hit.material].krKtIorModel, hit.coverage)) {
    if (parent >= 0) {  // a leaf of the path tree
      b_.nodes[static_cast<std::size_t>(parent)].firstChild = first;
      b_.nodes[static_cast<std::size_t>(parent)].children = 0;
    }
    return;
  }
  WhittedWeights w = whitted_.weights(hit);
  auto queue = [&](RayKind kind, glm::vec3 dir, glm::vec3 weight, float weightMax) {
    // The sides of Whitted::secondary: reflection in front of the facet, transmission behind it.
    Buffers::Node& n = b_.nodes.emplace_back();
    n.origin = spawnOrigin(hit, kind == RayKind::Refraction ? -hit.geomNormalW : hit.geomNormalW);
    n.dir = dir;
    n.time = hit.time;
    n.weight = weight;
    n.throughput = throughput * weightMax;
    n.parent = parent;
    n.pixel = pixel;
    n.refraction = kind == RayKind::Refraction;
    if constexpr (Capture::kRecords)
      n.captured = capture.deferred(kind, n.origin, dir, 0.0f, std::numeric_limits<float>::infinity());
  };
  // Glossy materials: several rays per kind at the primary hit (Whitted::secondary's, in its order).
  const float rough = whitted_.frame().roughness[hit.material];
  const int samples = whitted_.glossRays(hit.material, depth);
  if (modes.reflections && w.reflect > 0.0f && throughput * w.reflect >= modes.minContribution) {
    const glm::vec3 weight(w.reflect / static_cast<float>(samples));
    for (int k = 0; k < samples; ++k) {
      ++counts.reflection;
      queue(RayKind::Reflection,
            whitted_.glossyRayDirection(hit, w.reflectDirW, rough, kGlossReflectStream, k, hit.geomNormalW), weight,
            w.reflect);
    }
  }
  const float wT = w.transmitMax();
  if (modes.refraction && wT > 0.0f && throughput * wT >= modes.minContribution) {
    const int rays = w.passThrough ? 1 : samples;  // an uncovered BLEND part goes straight on
    const float lobe = w.passThrough ? 0.0f : rough;
    const glm::vec3 weight = w.transmit / static_cast<float>(rays);
    for (int k = 0; k < rays; ++k) {
      ++counts.refraction;
      queue(RayKind::Refraction,
            whitted_.glossyRayDirection(hit, w.refraction.dirW, lobe, kGlossRefractStream, k, -hit.geomNormalW),
            weight, wT);
    }
  }
  if (parent >= 0) {
    Buffers::Node& p = b_.nodes[static_cast<std::size_t>(parent)];
    p.firstChild = first;
    p.children = static_cast<std::uint32_t>(b_.nodes.size() - first);
  }
}

template <class Capture>
void Wavefront::run(RayCounts& counts, glm::vec4* reflected, glm::vec4* transmitted, Capture& capture) {
  const TraceModes& modes = whitted_.modes();
  const EmbreeScene& embree = whitted_.embree();
  const FrameShading& frame = whitted_.frame();
  const std::size_t lights = frame.lights.size();
  // Breadth first: the rays of depth d are nodes [begin, end); their hits append depth d + 1.
  std::size_t begin = 0;
  for (int depth = 1; begin < b_.nodes.size(); ++depth) {
    const std::size_t end = b_.nodes.size();
    b_.rays.clear();
    b_.rayNodes.clear();
    for (std::size_t i = begin; i < end; ++i) {
      Buffers::Node& n = b_.nodes[i];
      n.local = frame.environment.radiance(n.dir);  // until a hit says otherwise
      RTCRayHit rh;
      if (!makeEmbreeRay(rh.ray, n.origin, n.dir, 0.0f, std::numeric_limits<float>::infinity(), n.time)) {
        if constexpr (Capture::kRecords) capture.answer(n.refraction ? RayKind::Refraction : RayKind::Reflection, n.captured, false, false);
        continue;
      }
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      b_.rays.push_back(rh);
      b_.rayNodes.push_back(i);
    }
    if (!b_.rays.empty()) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);  // incoherent, as for shadow rays (see ShadowBatch::trace)
      rtcIntersect1M(embree.top(), &ctx, b_.rays.data(), static_cast<unsigned>(b_.rays.size()), sizeof(RTCRayHit));
    }
    b_.hits.clear();
    b_.hitNodes.clear();
    for (std::size_t k = 0; k < b_.rays.size(); ++k) {
      const RTCRayHit& rh = b_.rays[k];
      Buffers::Node& n = b_.nodes[b_.rayNodes[k]];
      bool missed = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID;
      if constexpr (Capture::kRecords) capture.answer(n.refraction ? RayKind::Refraction : RayKind::Reflection, n.captured, !missed);
      if (missed || !embree.hasTriangle(rh.hit.instID[0], rh.hit.primID)) continue;
      n.hit = true;
      b_.hits.push_back(resolveHit(whitted_.scene(), embree.transformAt(rh.hit.instID[0], n.time), rh.hit.instID[0],
                                   rh.hit.primID, Ray{n.origin, n.dir}));
      b_.hits.back().time = n.time;
      b_.hitNodes.push_back(b_.rayNodes[k]);
    }
    // Shadow rays of every hit of this depth (Whitted::shade: secondary hits use rays when asked).
    b_.masks.assign(b_.hits.size(), static_cast<LightMask>(~0u));  // all lights visible
    if (modes.secondaryShadowRays) {
      b_.shadows.clear();
      b_.shadows.prepareShafts(whitted_, b_.hits.size(), [&](std::size_t h) -> const ShadowPoint& { return b_.hits[h]; });
      b_.area.resize(b_.hits.size());  // add() writes every area word it reads
      for (std::size_t h = 0; h < b_.hits.size(); ++h)
        b_.masks[h] = static_cast<LightMask>(
            b_.shadows.add(whitted_, lights, b_.hits[h], h, capture, nullptr, b_.area[h].data(), 1, 0, depth));
      b_.shadows.trace(embree.top(), b_.masks.data(), counts, capture);
    }
    for (std::size_t h = 0; h < b_.hits.size(); ++h) {
      const SurfaceHit& hit = b_.hits[h];
      std::size_t node = b_.hitNodes[h];
      b_.nodes[node].local = shadeLocal(whitted_.scene(), frame, embree.transformAt(hit.instance, hit.time), hit, b_.masks[h],
                                        modes.secondaryShadowRays ? &b_.area[h] : nullptr, depth);
      spawn(hit, depth, b_.nodes[node].throughput, static_cast<std::int64_t>(node), b_.nodes[node].pixel, counts, capture);
    }
    begin = end;
  }
  // Bottom up: children come after their parent, so walking back finishes every node's rays before its own
  // sum, which is the recursion's expression: colour + Σ wR·S + Σ wT·T (background on a miss), each Σ from
  // zero in the order the rays were queued, as Whitted::secondary adds them.
  for (std::size_t i = b_.nodes.size(); i-- > 0;) {
    Buffers::Node& n = b_.nodes[i];
    glm::vec3 radiance = n.local;
    if (n.hit) {
      glm::vec3 s(0.0f), t(0.0f);
      for (std::size_t c = n.firstChild; c < n.firstChild + n.children; ++c)
        (b_.nodes[c].refraction ? t : s) += b_.nodes[c].weighted;
      radiance = n.local + s + t;
    }
    n.weighted = n.weight * radiance;
  }
  // The primary hits' rays, in order, into their pixels (zero until then; a = 1 where a ray was traced).
  for (const Buffers::Node& n : b_.nodes) {
    if (n.parent >= 0) continue;
    glm::vec4& out = (n.refraction ? transmitted : reflected)[n.pixel];
    out = glm::vec4(glm::vec3(out) + n.weighted, 1.0f);
  }
}

std::uint32_t ShadowBatch::add(const Whitted& whitted, std::size_t lights, const ShadowPoint& hit, std::size_t slot) {
  NoCapture none;
  return add(whitted, lights, hit, slot, none);
}
void ShadowBatch::trace(RTCScene scene, LightMask* masks, RayCounts& counts) {
  NoCapture none;
  trace(scene, masks, counts, none);
}
void Wavefront::addPrimary(const SurfaceHit& hit, std::size_t pixel, RayCounts& counts) {
  NoCapture none;
  addPrimary(hit, pixel, counts, none);
}
void Wavefront::run(RayCounts& counts, glm::vec4* reflected, glm::vec4* transmitted) {
  NoCapture none;
  run(counts, reflected, transmitted, none);
}

// The frame's instantiation and the bench's; no others.
template std::uint32_t ShadowBatch::add(const Whitted&, std::size_t, const ShadowPoint&, std::size_t, NoCapture&,
                                        const ShadowKeep*, std::uint32_t*, std::size_t, std::uint32_t, int);
template std::uint32_t ShadowBatch::add(const Whitted&, std::size_t, const ShadowPoint&, std::size_t, TileCapture&,
                                        const ShadowKeep*, std::uint32_t*, std::size_t, std::uint32_t, int);
template void ShadowBatch::trace(RTCScene, LightMask*, RayCounts&, NoCapture&);
template void ShadowBatch::trace(RTCScene, LightMask*, RayCounts&, TileCapture&);
template void Wavefront::addPrimary(const SurfaceHit&, std::size_t, RayCounts&, NoCapture&);
template void Wavefront::addPrimary(const SurfaceHit&, std::size_t, RayCounts&, TileCapture&);
template void Wavefront::run(RayCounts&, glm::vec4*, glm::vec4*, NoCapture&);
template void Wavefront::run(RayCounts&, glm::vec4*, glm::vec4*, TileCapture&);

}  // namespace tandem::rt

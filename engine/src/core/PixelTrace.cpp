// The text form of a PixelTrace (tandem/PixelTrace.h): what tandem-render --trace-pixel prints.
#include "tandem/PixelTrace.h"

#include <cmath>
#include <cstdio>

namespace tandem {

std::string_view toString(TraceRayKind kind) {
  switch (kind) {
    case TraceRayKind::Primary: return "primary";
    case TraceRayKind::Shadow: return "shadow";
    case TraceRayKind::Reflection: return "reflection";
    case TraceRayKind::Refraction: return "refraction";
  }
  return "?";
}

std::string_view toString(LightVisibility visibility) {
  switch (visibility) {
    case LightVisibility::Unoccluded: return "unoccluded";
    case LightVisibility::Occluded: return "occluded";
    case LightVisibility::CastsNoShadows: return "visible, no ray: the light casts no shadows";
    case LightVisibility::CannotReach:
      return "no ray: cannot light the point (behind the surface, outside its cone or beyond its range)";
    case LightVisibility::AtThePoint: return "visible, no ray: the light is at the point";
    case LightVisibility::NotFinite: return "visible, no ray: origin or direction not finite";
    case LightVisibility::MapSaysLit: return "visible, no ray: the hybrid shadow map proves it";
    case LightVisibility::MapSaysShadowed: return "occluded, no ray: the hybrid shadow map proves it";
    case LightVisibility::NotTraced: return "not by rays at this hit";
  }
  return "?";
}

std::string_view toString(SecondaryRay reason) {
  switch (reason) {
    case SecondaryRay::Traced: return "traced";
    case SecondaryRay::NotByRays: return "not by rays this frame";
    case SecondaryRay::DepthLimit: return "depth limit";
    case SecondaryRay::NoWeight: return "weight 0";
    case SecondaryRay::BelowMinContribution: return "throughput below minContribution";
  }
  return "?";
}

namespace {

std::string num(float v) {
  if (std::isinf(v)) return v > 0.0f ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", static_cast<double>(v));
  return buf;
}

std::string vec(glm::vec3 v) {
  std::string s = "(";  // appended, not "(" + ...: GCC 12 warns falsely (-Wrestrict) on that chain
  s += num(v.x);
  s += ", ";
  s += num(v.y);
  s += ", ";
  s += num(v.z);
  s += ")";
  return s;
}

/// A weight that is the same in all three channels reads as one number.
std::string weight(glm::vec3 w) { return w.x == w.y && w.y == w.z ? num(w.x) : vec(w); }

std::string bits(std::uint32_t mask, std::size_t lights) {
  if (lights == 0) return "none";
  std::string s = "0b";
  for (std::size_t j = lights; j-- > 0;) s += ((mask >> j) & 1u) ? '1' : '0';
  return s;
}

template <class T>
std::string nameOf(const std::vector<T>& items, std::uint32_t index, const char* what) {
  std::string s = std::string(what) + " " + std::to_string(index);
  if (index < items.size() && !items[index].name.empty()) s = items[index].name + " (" + s + ")";
  return s;
}

class Writer {
 public:
  Writer(const PixelTrace& trace, const Scene& scene) : trace_(trace), scene_(scene), lights_(scene.directLights()) {}

  std::string text() {
    header();
    for (int root : trace_.roots) ray(root, 0);
    footer();
    return out_;
  }

 private:
  void line(int indent, const std::string& s) { out_ += std::string(static_cast<std::size_t>(indent) * 2, ' ') + s + "\n"; }

  void header() {
    const PixelTrace& t = trace_;
    std::string where = "pixel (" + std::to_string(t.x) + ", " + std::to_string(t.y) + ") of " +
                        std::to_string(t.width) + "x" + std::to_string(t.height);
    if (t.reference) {
      where += ", reference frame, " + std::to_string(t.samples) + " sample(s)";
    } else {
      where += std::string(t.rayPass ? ", hybrid ray pass" : ", no ray pass (raster effects only)") + ", ray grid 1/" +
               std::to_string(t.rayScale) + " pixel (" + std::to_string(t.gridX) + ", " + std::to_string(t.gridY) +
               "): ids and camera ray of pixel (" + std::to_string(t.tracedX) + ", " + std::to_string(t.tracedY) + ")";
    }
    line(0, where);
    const FrameSettings& s = t.settings;
    line(0, "settings: shadows " + std::string(shadowModeName(s)) + ", reflections " +
                std::string(toString(s.reflections)) + ", refraction " + std::string(toString(s.refraction)) +
                ", maxDepth " + std::to_string(s.maxDepth) + ", minContribution " + num(s.minContribution) +
                ", Fresnel " + (s.fresnel == FresnelMode::Schlick ? "Schlick" : "exact") +
                (s.fresnelWeighted ? ", weighted sum (wR = kr + kt·F, wT = kt·(1 − F))" : ", classic sum (wR = kr, wT = kt)"));
  }

  void ray(int index, int indent) {
    const TraceNode& n = trace_.nodes[static_cast<std::size_t>(index)];
    std::string head = std::string(toString(n.kind)) + " ray, depth " + std::to_string(n.depth);
    if (n.kind != TraceRayKind::Primary) head += ", weight " + weight(n.weight) + ", throughput " + num(n.throughput);
    line(indent, head);
    line(indent + 2, "origin " + vec(n.originW) + "  direction " + vec(n.dirW) + "  t in [" + num(n.tNear) + ", " +
                         num(n.tFar) + "]");
    if (!n.hit) {
      line(indent + 1, "miss: environment " + vec(n.radiance));
      if (n.kind != TraceRayKind::Primary) line(indent + 1, "adds " + vec(n.contribution));
      return;
    }
    const Material* m = n.material < scene_.materials.size() ? &scene_.materials[n.material] : nullptr;
    line(indent + 1, "hit " + nameOf(scene_.instances, n.instance, "instance") + ", triangle " +
                         std::to_string(n.triangle) + ", t " + num(n.t) + ", " + (n.backFace ? "back" : "front") +
                         " face, material " + nameOf(scene_.materials, n.material, "material"));
    line(indent + 2, "position " + vec(n.positionW) + "  Ng " + vec(n.geometricNormalW) + "  N " + vec(n.shadingNormalW) +
                         "  barycentrics (" + num(1.0f - n.barycentrics.x - n.barycentrics.y) + ", " +
                         num(n.barycentrics.x) + ", " + num(n.barycentrics.y) + ")" +
                         (n.coverage < 1.0f ? "  coverage " + num(n.coverage) : std::string()));
    for (const TraceLight& l : n.lights) {
      std::string s = "light " + std::to_string(l.light);
      if (l.light < lights_.size() && !lights_[l.light]->name.empty()) s += " " + lights_[l.light]->name;
      s += ": " + std::string(toString(l.visibility));
      if (l.visibility == LightVisibility::Unoccluded || l.visibility == LightVisibility::Occluded)
        s += " (shadow ray origin " + vec(l.originW) + " direction " + vec(l.dirW) + " tFar " + num(l.tFar) + ")";
      line(indent + 1, s);
    }
    line(indent + 1, "local " + vec(n.local) + "  light mask " + bits(n.lightMask, lights_.size()));
    std::string sum = n.sumEvaluated ? "sum" : "sum (no secondary rays here)";
    if (m) sum += ": kr " + num(m->kr) + ", kt " + num(m->kt);
    sum += ", F " + num(n.fresnel) + (n.totalInternal ? " (total internal reflection)" : "") + ", wR " +
           num(n.reflectWeight) + ", wT " + weight(n.transmitWeight);
    line(indent + 1, sum);
    secondary(n, TraceRayKind::Reflection, indent + 1);
    secondary(n, TraceRayKind::Refraction, indent + 1);
    line(indent + 1, "= local " + vec(n.local) + " + wR·S " + vec(n.reflected) + " + wT·T " + vec(n.transmitted) +
                         " = " + vec(n.radiance));
    if (n.kind != TraceRayKind::Primary) line(indent + 1, "adds " + vec(n.contribution));
  }

  void secondary(const TraceNode& n, TraceRayKind kind, int indent) {
    const bool reflection = kind == TraceRayKind::Reflection;
    const std::vector<int>& children = reflection ? n.reflectionChildren : n.refractionChildren;
    for (int child : children) ray(child, indent);
    if (!children.empty()) return;
    line(indent, std::string(toString(kind)) + ": none, " + std::string(toString(reflection ? n.reflection : n.refraction)));
  }

  void footer() {
    const PixelTrace& t = trace_;
    line(0, "pixel = local " + vec(t.local) + " + reflected " + vec(t.reflected) + " + transmitted " +
                vec(t.transmitted) + (t.samples > 1 ? " (means over the samples)" : "") + " = " + vec(t.color));
    line(0, "light mask " + bits(t.lightMask, lights_.size()) + "; rays: " + std::to_string(t.rays.primary) +
                " primary, " + std::to_string(t.rays.shadow) + " shadow, " + std::to_string(t.rays.reflection) +
                " reflection, " + std::to_string(t.rays.refraction) + " refraction");
    for (const std::string& note : t.notes) line(0, "note: " + note);
  }

  const PixelTrace& trace_;
  const Scene& scene_;
  std::vector<const Light*> lights_;
  std::string out_;
};

}  // namespace

std::string toText(const PixelTrace& trace, const Scene& scene) { return Writer(trace, scene).text(); }

}  // namespace tandem

#include "core/Solids.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_inverse.hpp>

#include "core/Finite.h"

namespace tandem::solid {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<Span> unite(std::vector<Span> s);

// ---- real roots of small polynomials ----
// c[0] + c[1]·t + ... + c[n]·tⁿ.
double evaluate(const double* c, int n, double t) {
  double v = c[n];
  for (int k = n - 1; k >= 0; --k) v = v * t + c[k];
  return v;
}

/// The real roots of a quadratic, smaller first (the cancellation-free form: q = −(b + sign(b)·√disc)/2).
int quadraticRoots(double a, double b, double c, double& r0, double& r1) {
  if (a == 0.0) {
    if (b == 0.0) return 0;
    r0 = r1 = -c / b;
    return 1;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return 0;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  r0 = q / a;
  r1 = q != 0.0 ? c / q : r0;
  if (r0 > r1) std::swap(r0, r1);
  return 2;
}

/// A root of a polynomial with a sign change on [lo, hi]: bisection, with Newton steps where they stay inside
/// the bracket, to the last bit.
double bracketedRoot(const double* c, int n, double lo, double hi) {
  double flo = evaluate(c, n, lo);
  std::array<double, 8> d{};
  for (int k = 1; k <= n; ++k) d[static_cast<std::size_t>(k - 1)] = k * c[k];
  double t = 0.5 * (lo + hi);
  for (int i = 0; i < 200; ++i) {
    const double f = evaluate(c, n, t);
    if (f == 0.0) return t;
    if ((f < 0.0) == (flo < 0.0)) {
      lo = t;
      flo = f;
    } else {
      hi = t;
    }
    const double slope = evaluate(d.data(), n - 1, t);
    double next = slope != 0.0 ? t - f / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == t || hi - lo <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(lo), std::abs(hi)))
      return next;
    t = next;
  }
  return t;
}

/// The real roots of a polynomial of degree n <= 4 in [lo, hi], ascending: each monotone piece between the
/// roots of its derivative holds at most one, found by bracketing (robust where closed forms lose digits).
/// A root of even multiplicity (a grazing touch) is found only where the polynomial reaches exactly 0.
void realRoots(const double* c, int n, double lo, double hi, std::vector<double>& out) {
  out.clear();
  while (n > 0 && c[n] == 0.0) --n;
  if (n == 0) return;
  if (n <= 2) {
    double r0 = 0.0, r1 = 0.0;
    const int count = quadraticRoots(n == 2 ? c[2] : 0.0, c[1], c[0], r0, r1);
    if (count >= 1) out.push_back(r0);
    if (count == 2 && r1 != r0) out.push_back(r1);
    std::erase_if(out, [&](double r) { return !(r >= lo && r <= hi); });
    return;
  }
  std::array<double, 8> d{};
  for (int k = 1; k <= n; ++k) d[static_cast<std::size_t>(k - 1)] = k * c[k];
  std::vector<double> critical;
  realRoots(d.data(), n - 1, lo, hi, critical);
  std::vector<double> ends;
  ends.push_back(lo);
  for (double x : critical)
    if (x > ends.back() && x < hi) ends.push_back(x);
  ends.push_back(hi);
  for (std::size_t k = 0; k + 1 < ends.size(); ++k) {
    const double a = ends[k], b = ends[k + 1];
    const double fa = evaluate(c, n, a), fb = evaluate(c, n, b);
    if (fa == 0.0) {
      if (out.empty() || out.back() != a) out.push_back(a);
      continue;
    }
    if (fb == 0.0) continue;  // the next piece's start
    if ((fa < 0.0) != (fb < 0.0)) out.push_back(bracketedRoot(c, n, a, b));
  }
  if (evaluate(c, n, hi) == 0.0 && (out.empty() || out.back() != hi)) out.push_back(hi);
}

// ---- spans ----
void intersectSpan(Span& s, double t0, double t1) {
  s.t0 = std::max(s.t0, t0);
  s.t1 = std::min(s.t1, t1);
}

/// The t where the line is in the slab lo <= o + t·d <= hi (all of it, or none when d = 0).
bool slab(double o, double d, double lo, double hi, double& t0, double& t1) {
  if (d == 0.0) {
    t0 = -kInf;
    t1 = kInf;
    return o >= lo && o <= hi;
  }
  t0 = (lo - o) / d;
  t1 = (hi - o) / d;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

/// Hits of a convex primitive from one span [t0, t1] (either end may be infinite: no crossing there).
Hits convexHits(const Primitive& p, const Ray& ray, double t0, double t1) {
  Hits h;
  if (!(t0 <= t1)) return h;
  h.spans.push_back({t0, t1});
  if (std::isfinite(t0)) h.crossings.push_back({t0, normalAt(p, ray.origin + t0 * ray.dir), 0});
  if (std::isfinite(t1)) h.crossings.push_back({t1, normalAt(p, ray.origin + t1 * ray.dir), 0});
  return h;
}

/// The ray moved to start where it passes closest to the origin (t = tc there): the primitives' equations then
/// involve small numbers, whatever the distance the ray came from.
Ray nearOrigin(const Ray& ray, double& tc) {
  const double dd = glm::dot(ray.dir, ray.dir);
  tc = dd > 0.0 ? -glm::dot(ray.origin, ray.dir) / dd : 0.0;
  return {ray.origin + tc * ray.dir, ray.dir};
}

Hits sphereHits(const Primitive& p, const Ray& full) {
  double tc = 0.0;
  const Ray ray = nearOrigin(full, tc);
  const double r = p.size.x, dd = glm::dot(ray.dir, ray.dir);
  // The closest point is ray.origin itself: the chord's half-length follows without cancellation.
  const double h2 = r * r - glm::dot(ray.origin, ray.origin);
  if (!(h2 >= 0.0) || !(dd > 0.0)) return {};
  const double half = std::sqrt(h2 / dd);
  return convexHits(p, full, tc - half, tc + half);
}

Hits boxHits(const Primitive& p, const Ray& ray) {
  double t0 = -kInf, t1 = kInf;
  for (int a = 0; a < 3; ++a) {
    double s0 = 0.0, s1 = 0.0;
    if (!slab(ray.origin[a], ray.dir[a], -p.size[a], p.size[a], s0, s1)) return {};
    t0 = std::max(t0, s0);
    t1 = std::min(t1, s1);
  }
  return convexHits(p, ray, t0, t1);
}

/// Cylinder and cone: the quadric's span(s) x² + z² <= (a + b·y)² intersected with the slab |y| <= h.
Hits taperedHits(const Primitive& p, const Ray& full) {
  double tc = 0.0;
  const Ray ray = nearOrigin(full, tc);
  const bool cone = p.shape == Shape::Cone;
  const double h = cone ? p.size.z : p.size.y;
  const double a = cone ? 0.5 * (p.size.x + p.size.y) : p.size.x;
  const double b = cone ? (p.size.y - p.size.x) / (2.0 * h) : 0.0;
  const glm::dvec3 o = ray.origin, d = ray.dir;
  double s0 = 0.0, s1 = 0.0;
  if (!slab(o.y, d.y, -h, h, s0, s1)) return {};
  const double rho = a + b * o.y, drho = b * d.y;
  const double qa = d.x * d.x + d.z * d.z - drho * drho;
  const double qb = 2.0 * (o.x * d.x + o.z * d.z - rho * drho);
  const double qc = o.x * o.x + o.z * o.z - rho * rho;
  // Where the quadric's value is <= 0, as up to two pieces.
  std::vector<Span> inside;
  double r0 = 0.0, r1 = 0.0;
  const int roots = quadraticRoots(qa, qb, qc, r0, r1);
  if (qa > 0.0) {
    if (roots == 2) inside.push_back({r0, r1});
  } else if (qa < 0.0) {
    if (roots == 2) {
      inside.push_back({-kInf, r0});
      inside.push_back({r1, kInf});
    } else {
      inside.push_back({-kInf, kInf});
    }
  } else if (qb != 0.0) {  // linear: one side of its root
    const double r = -qc / qb;
    inside.push_back(qb > 0.0 ? Span{-kInf, r} : Span{r, kInf});
  } else if (qc <= 0.0) {  // parallel to the side, inside it
    inside.push_back({-kInf, kInf});
  }
  // Within the slab the solid is convex (ρ >= 0 there: the cone's other nappe lies beyond its apex, outside
  // the slab), so the pieces join into one span: a ray down the axis meets the apex as a double root.
  std::vector<Span> pieces;
  for (Span s : inside) {
    intersectSpan(s, s0, s1);
    if (s.t0 <= s.t1) pieces.push_back(s);
  }
  Hits out;
  for (const Span& s : unite(pieces)) {
    Hits piece = convexHits(p, full, s.t0 + tc, s.t1 + tc);
    out.spans.insert(out.spans.end(), piece.spans.begin(), piece.spans.end());
    out.crossings.insert(out.crossings.end(), piece.crossings.begin(), piece.crossings.end());
  }
  return out;
}

Hits torusHits(const Primitive& p, const Ray& full) {
  double tc = 0.0;
  const Ray ray = nearOrigin(full, tc);
  const double R = p.size.x, r = p.size.y;
  const glm::dvec3 o = ray.origin, d = ray.dir;
  const double dd = glm::dot(d, d);
  const double reach = (R + r) * (R + r) - glm::dot(o, o);
  if (!(reach >= 0.0) || !(dd > 0.0)) return {};
  const double span = std::sqrt(reach / dd) * (1.0 + 1e-9) + 1e-300;
  // (|p|² + R² − r²)² − 4R²(x² + z²) along the line, a quartic in t.
  const double a = dd, b = 2.0 * glm::dot(o, d), k = glm::dot(o, o) + R * R - r * r;
  const double ad = d.x * d.x + d.z * d.z, bd = 2.0 * (o.x * d.x + o.z * d.z), cd = o.x * o.x + o.z * o.z;
  const double c[5] = {k * k - 4.0 * R * R * cd, 2.0 * b * k - 4.0 * R * R * bd, b * b + 2.0 * a * k - 4.0 * R * R * ad,
                       2.0 * a * b, a * a};
  std::vector<double> roots;
  realRoots(c, 4, -span, span, roots);
  // Consecutive roots bound the inside pieces: the quartic is negative inside.
  Hits out;
  for (std::size_t i = 0; i + 1 < roots.size();) {
    const double t0 = roots[i], t1 = roots[i + 1];
    if (!(evaluate(c, 4, 0.5 * (t0 + t1)) <= 0.0)) {
      ++i;  // not an inside piece (a touch counted as a root): pair from the next root instead
      continue;
    }
    Hits piece = convexHits(p, full, t0 + tc, t1 + tc);
    out.spans.insert(out.spans.end(), piece.spans.begin(), piece.spans.end());
    out.crossings.insert(out.crossings.end(), piece.crossings.begin(), piece.crossings.end());
    i += 2;
  }
  return out;
}

Hits planeHits(const Primitive& p, const Ray& ray) {
  Hits h;
  if (ray.dir.y == 0.0) {
    if (ray.origin.y <= 0.0) h.spans.push_back({-kInf, kInf});
    return h;
  }
  const double t = -ray.origin.y / ray.dir.y;
  h.spans.push_back(ray.dir.y > 0.0 ? Span{-kInf, t} : Span{t, kInf});
  h.crossings.push_back({t, normalAt(p, ray.origin + t * ray.dir), 0});
  return h;
}

// ---- set operations on spans ----
std::vector<Span> unite(std::vector<Span> s) {
  std::sort(s.begin(), s.end(), [](const Span& a, const Span& b) { return a.t0 < b.t0; });
  std::vector<Span> out;
  for (const Span& x : s) {
    if (!out.empty() && x.t0 <= out.back().t1) out.back().t1 = std::max(out.back().t1, x.t1);
    else out.push_back(x);
  }
  return out;
}

std::vector<Span> intersectSpans(const std::vector<Span>& a, const std::vector<Span>& b) {
  std::vector<Span> out;
  for (const Span& x : a)
    for (const Span& y : b) {
      const Span s{std::max(x.t0, y.t0), std::min(x.t1, y.t1)};
      if (s.t0 <= s.t1) out.push_back(s);
    }
  return unite(out);
}

std::vector<Span> subtract(const std::vector<Span>& a, const std::vector<Span>& b) {
  std::vector<Span> out = a;
  for (const Span& y : b) {
    std::vector<Span> next;
    for (const Span& x : out) {
      if (y.t1 <= x.t0 || y.t0 >= x.t1) {
        next.push_back(x);
        continue;
      }
      if (x.t0 < y.t0) next.push_back({x.t0, y.t0});
      if (y.t1 < x.t1) next.push_back({y.t1, x.t1});
    }
    out = std::move(next);
  }
  return out;
}

/// Whether t lies in one of the spans: with its ends (closed) or strictly inside, `tolerance` either way.
bool within(const std::vector<Span>& spans, double t, double tolerance, bool closed) {
  for (const Span& s : spans) {
    if (closed ? (t >= s.t0 - tolerance && t <= s.t1 + tolerance) : (t > s.t0 + tolerance && t < s.t1 - tolerance))
      return true;
  }
  return false;
}

struct Walker {
  const Solid& solid;
  double scale;  // the root ray's coordinate scale in t units: |origin| / |dir|
  double tolerance(double t) const { return kCoincident * (scale + std::abs(t)); }

  Hits node(std::uint32_t index, const Ray& parentRay) const {
    const Node& n = solid.nodes[index];
    // Most nodes sit where their parent is (every shape of a lone exact sphere or box): no transform to undo.
    const bool placed = n.parentFromNode != glm::dmat4(1.0);
    const glm::dmat4 nodeFromParent = placed ? glm::inverse(n.parentFromNode) : glm::dmat4(1.0);
    const Ray ray = placed ? Ray{glm::dvec3(nodeFromParent * glm::dvec4(parentRay.origin, 1.0)),
                                 glm::dmat3(nodeFromParent) * parentRay.dir}
                           : parentRay;
    Hits h;
    if (n.op == Op::Leaf) {
      h = intersect(n.primitive, ray);
      for (Crossing& c : h.crossings) c.leaf = index;
    } else {
      std::vector<Hits> kids;
      kids.reserve(n.children.size());
      for (std::uint32_t child : n.children) kids.push_back(node(child, ray));
      h = combine(n.op, kids);
    }
    if (!placed) return h;
    // Normals back to the parent's space (the inverse transpose of the placement).
    const glm::dmat3 normalToParent = glm::transpose(glm::dmat3(nodeFromParent));
    for (Crossing& c : h.crossings) {
      const glm::dvec3 v = normalToParent * c.normal;
      const double len = glm::length(v);
      if (len > 0.0) c.normal = v / len;
    }
    return h;
  }

  Hits combine(Op op, const std::vector<Hits>& kids) const {
    Hits out;
    if (kids.empty()) return out;
    auto keep = [&](const Crossing& c) { out.crossings.push_back(c); };
    switch (op) {
      case Op::Leaf:
        break;
      case Op::Union:
      case Op::Merge: {
        std::vector<Span> all;
        for (const Hits& k : kids) all.insert(all.end(), k.spans.begin(), k.spans.end());
        out.spans = unite(all);
        for (std::size_t i = 0; i < kids.size(); ++i)
          for (const Crossing& c : kids[i].crossings) {
            bool inOther = false;
            if (op == Op::Merge)
              for (std::size_t j = 0; j < kids.size() && !inOther; ++j)
                inOther = j != i && within(kids[j].spans, c.t, tolerance(c.t), true);
            if (!inOther) keep(c);
          }
        break;
      }
      case Op::Intersection: {
        out.spans = kids[0].spans;
        for (std::size_t j = 1; j < kids.size(); ++j) out.spans = intersectSpans(out.spans, kids[j].spans);
        for (std::size_t i = 0; i < kids.size(); ++i)
          for (const Crossing& c : kids[i].crossings) {
            bool inAll = true;
            for (std::size_t j = 0; j < kids.size() && inAll; ++j)
              inAll = j == i || within(kids[j].spans, c.t, tolerance(c.t), true);
            if (inAll) keep(c);
          }
        break;
      }
      case Op::Difference: {
        std::vector<Span> rest;
        for (std::size_t j = 1; j < kids.size(); ++j) rest.insert(rest.end(), kids[j].spans.begin(), kids[j].spans.end());
        rest = unite(rest);
        out.spans = subtract(kids[0].spans, rest);
        // The first operand's surfaces outside the rest (on a subtracted boundary counts as inside it)...
        for (const Crossing& c : kids[0].crossings)
          if (!within(rest, c.t, tolerance(c.t), true)) keep(c);
        // ... and the rest's surfaces strictly inside the first, turned inside out.
        for (std::size_t j = 1; j < kids.size(); ++j)
          for (Crossing c : kids[j].crossings)
            if (within(kids[0].spans, c.t, tolerance(c.t), false)) {
              c.normal = -c.normal;
              keep(c);
            }
        break;
      }
    }
    std::sort(out.crossings.begin(), out.crossings.end(), [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
    return out;
  }
};

bool containsNode(const Solid& solid, std::uint32_t index, const glm::dvec3& parentPoint) {
  const Node& n = solid.nodes[index];
  const glm::dvec3 p(glm::inverse(n.parentFromNode) * glm::dvec4(parentPoint, 1.0));
  switch (n.op) {
    case Op::Leaf:
      return contains(n.primitive, p);
    case Op::Union:
    case Op::Merge:
      return std::any_of(n.children.begin(), n.children.end(), [&](std::uint32_t c) { return containsNode(solid, c, p); });
    case Op::Intersection:
      return !n.children.empty() &&
             std::all_of(n.children.begin(), n.children.end(), [&](std::uint32_t c) { return containsNode(solid, c, p); });
    case Op::Difference:
      if (n.children.empty() || !containsNode(solid, n.children[0], p)) return false;
      return std::none_of(n.children.begin() + 1, n.children.end(), [&](std::uint32_t c) { return containsNode(solid, c, p); });
  }
  return false;
}

Bounds primitiveBounds(const Primitive& p) {
  constexpr double kFar = 1e30;
  switch (p.shape) {
    case Shape::Sphere:
      return {glm::dvec3(-p.size.x), glm::dvec3(p.size.x)};
    case Shape::Box:
      return {-p.size, p.size};
    case Shape::Cylinder:
      return {{-p.size.x, -p.size.y, -p.size.x}, {p.size.x, p.size.y, p.size.x}};
    case Shape::Cone: {
      const double r = std::max(p.size.x, p.size.y);
      return {{-r, -p.size.z, -r}, {r, p.size.z, r}};
    }
    case Shape::Torus: {
      const double out = p.size.x + p.size.y;
      return {{-out, -p.size.y, -out}, {out, p.size.y, out}};
    }
    case Shape::Plane:
      return {{-kFar, -kFar, -kFar}, {kFar, 0.0, kFar}};
  }
  return {};
}

Bounds subtreeBounds(const Solid& solid, std::uint32_t index) {
  const Node& n = solid.nodes[index];
  Bounds b;
  if (n.op == Op::Leaf) {
    b = primitiveBounds(n.primitive);
  } else if (n.op == Op::Difference) {
    b = subtreeBounds(solid, n.children.front());
  } else {
    bool first = true;
    for (std::uint32_t c : n.children) {
      const Bounds k = subtreeBounds(solid, c);
      if (first) b = k;
      else if (n.op == Op::Intersection) b = {glm::max(b.lo, k.lo), glm::min(b.hi, k.hi)};
      else b = {glm::min(b.lo, k.lo), glm::max(b.hi, k.hi)};
      first = false;
    }
  }
  // The 8 corners placed in the parent's space.
  Bounds out{glm::dvec3(kInf), glm::dvec3(-kInf)};
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
    const glm::dvec3 p(n.parentFromNode * glm::dvec4(corner, 1.0));
    out.lo = glm::min(out.lo, p);
    out.hi = glm::max(out.hi, p);
  }
  return out;
}

}  // namespace

Hits intersect(const Primitive& primitive, const Ray& ray) {
  switch (primitive.shape) {
    case Shape::Sphere: return sphereHits(primitive, ray);
    case Shape::Box: return boxHits(primitive, ray);
    case Shape::Cylinder:
    case Shape::Cone: return taperedHits(primitive, ray);
    case Shape::Torus: return torusHits(primitive, ray);
    case Shape::Plane: return planeHits(primitive, ray);
  }
  return {};
}

bool contains(const Primitive& p, const glm::dvec3& q) {
  switch (p.shape) {
    case Shape::Sphere:
      return glm::dot(q, q) <= p.size.x * p.size.x;
    case Shape::Box:
      return std::abs(q.x) <= p.size.x && std::abs(q.y) <= p.size.y && std::abs(q.z) <= p.size.z;
    case Shape::Cylinder:
      return std::abs(q.y) <= p.size.y && q.x * q.x + q.z * q.z <= p.size.x * p.size.x;
    case Shape::Cone: {
      const double h = p.size.z;
      if (std::abs(q.y) > h) return false;
      const double rho = p.size.x + (p.size.y - p.size.x) * (q.y + h) / (2.0 * h);
      return q.x * q.x + q.z * q.z <= rho * rho;
    }
    case Shape::Torus: {
      const double ring = std::sqrt(q.x * q.x + q.z * q.z) - p.size.x;
      return ring * ring + q.y * q.y <= p.size.y * p.size.y;
    }
    case Shape::Plane:
      return q.y <= 0.0;
  }
  return false;
}

glm::dvec3 normalAt(const Primitive& p, const glm::dvec3& q) {
  auto unit = [](glm::dvec3 v, glm::dvec3 fallback) {
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? v / len : fallback;
  };
  switch (p.shape) {
    case Shape::Sphere:
      return unit(q, {0.0, 1.0, 0.0});
    case Shape::Box: {
      // The face whose plane the point is nearest (relative to the box's size along that axis).
      int axis = 0;
      double best = kInf;
      for (int a = 0; a < 3; ++a) {
        const double gap = std::abs(std::abs(q[a]) - p.size[a]) / p.size[a];
        if (gap < best) {
          best = gap;
          axis = a;
        }
      }
      glm::dvec3 n(0.0);
      n[axis] = q[axis] < 0.0 ? -1.0 : 1.0;
      return n;
    }
    case Shape::Cylinder:
    case Shape::Cone: {
      const bool cone = p.shape == Shape::Cone;
      const double h = cone ? p.size.z : p.size.y;
      const double a = cone ? 0.5 * (p.size.x + p.size.y) : p.size.x;
      const double b = cone ? (p.size.y - p.size.x) / (2.0 * h) : 0.0;
      const double rho = a + b * q.y;
      const double radial = std::sqrt(q.x * q.x + q.z * q.z);
      // Side or cap: whichever surface the point is nearer, relative to the solid's size.
      const double size = std::max(h, std::max(p.size.x, cone ? p.size.y : 0.0));
      const double capGap = std::abs(std::abs(q.y) - h) / size;
      const double sideGap = std::abs(radial - rho) / size;
      if (capGap <= sideGap) return {0.0, q.y < 0.0 ? -1.0 : 1.0, 0.0};
      return unit({q.x, -b * rho, q.z}, {0.0, q.y < 0.0 ? -1.0 : 1.0, 0.0});
    }
    case Shape::Torus: {
      const double radial = std::sqrt(q.x * q.x + q.z * q.z);
      if (!(radial > 0.0)) return {0.0, q.y < 0.0 ? -1.0 : 1.0, 0.0};
      const glm::dvec3 centre(q.x / radial * p.size.x, 0.0, q.z / radial * p.size.x);
      return unit(q - centre, {0.0, 1.0, 0.0});
    }
    case Shape::Plane:
      return {0.0, 1.0, 0.0};
  }
  return {0.0, 1.0, 0.0};
}

std::string validate(const Solid& solid) {
  if (solid.nodes.empty()) return "no nodes";
  if (solid.nodes.size() > kMaxCsgNodes)
    return std::to_string(solid.nodes.size()) + " nodes, more than " + std::to_string(kMaxCsgNodes);
  if (solid.root >= solid.nodes.size()) return "root " + std::to_string(solid.root) + " out of range";
  for (std::size_t i = 0; i < solid.nodes.size(); ++i) {
    const Node& n = solid.nodes[i];
    const std::string where = "node " + std::to_string(i) + ": ";
    if (!allFinite(n.parentFromNode) || !std::isfinite(glm::determinant(n.parentFromNode)) ||
        std::abs(glm::determinant(glm::dmat3(n.parentFromNode))) < 1e-300)
      return where + "its transform is not finite and invertible";
    if (n.op == Op::Leaf) {
      const glm::dvec3 s = n.primitive.size;
      if (!std::isfinite(s.x) || !std::isfinite(s.y) || !std::isfinite(s.z)) return where + "a size is not finite";
      const Shape shape = n.primitive.shape;
      const bool ok = shape == Shape::Sphere     ? s.x > 0.0
                      : shape == Shape::Box      ? s.x > 0.0 && s.y > 0.0 && s.z > 0.0
                      : shape == Shape::Cylinder ? s.x > 0.0 && s.y > 0.0
                      : shape == Shape::Cone     ? s.x >= 0.0 && s.y >= 0.0 && s.x + s.y > 0.0 && s.z > 0.0
                      : shape == Shape::Torus    ? s.x > 0.0 && s.y > 0.0 && s.y < s.x
                                                 : true;
      if (!ok) return where + "its size must be positive (a cone's radii may not both be 0, a torus's tube must be thinner than its ring)";
      if (!n.children.empty()) return where + "a primitive has no operands";
    } else {
      if (n.children.empty()) return where + "an operation needs at least one operand";
      for (std::uint32_t c : n.children)
        if (c >= solid.nodes.size() || c == i) return where + "operand " + std::to_string(c) + " out of range";
    }
  }
  // Depth and cycles: a walk from the root that never goes deeper than the limit.
  std::vector<std::pair<std::uint32_t, int>> stack{{solid.root, 1}};
  std::size_t visited = 0;
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    if (depth > kMaxCsgDepth)
      return "node " + std::to_string(index) + ": deeper than " + std::to_string(kMaxCsgDepth) + " (or a cycle)";
    if (++visited > kMaxCsgNodes * 4) return "the tree visits nodes more than " + std::to_string(kMaxCsgNodes * 4) + " times";
    for (std::uint32_t c : solid.nodes[index].children) stack.push_back({c, depth + 1});
  }
  return {};
}

Hits intersect(const Solid& solid, const Ray& ray) {
  const double dir = glm::length(ray.dir);
  const Walker walker{solid, dir > 0.0 ? glm::length(ray.origin) / dir : 0.0};
  // The root's own placement maps the solid's space to itself: the walk starts in the root's parent space.
  return walker.node(solid.root, ray);
}

bool contains(const Solid& solid, const glm::dvec3& p) { return containsNode(solid, solid.root, p); }

bool firstHit(const Hits& hits, double tNear, double tFar, Crossing& out) {
  for (const Crossing& c : hits.crossings)
    if (c.t > tNear && c.t < tFar) {
      out = c;
      return true;
    }
  return false;
}

Bounds bounds(const Solid& solid) { return subtreeBounds(solid, solid.root); }
Bounds nodeBounds(const Solid& solid, std::uint32_t index) { return subtreeBounds(solid, index); }

}  // namespace tandem::solid

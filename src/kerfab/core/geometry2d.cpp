#include "kerfab/core/geometry2d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace kerfab {

double polygon_area(const Polygon2& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

namespace {
/// Winding number of \p poly around \p p.
int winding(const Vec2& p, const Polygon2& poly) {
  int w = 0;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) w += winding_step(poly[j], poly[i], p);
  return w;
}
}  // namespace

bool inside(const Vec2& p, const std::vector<Polygon2>& polygons) {
  int w = 0;
  for (const auto& poly : polygons) w += winding(p, poly);
  return w != 0;
}

bool inside(const Vec2& p, const Polygon2& polygon) { return winding(p, polygon) != 0; }

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const double t =
      e.squaredNorm() > 0 ? std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * e)).norm();
}

double distance_to_boundary(const Vec2& p, const Polygon2& polygon) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < polygon.size(); ++i)
    d = std::min(d, distance_to_segment(p, polygon[i], polygon[(i + 1) % polygon.size()]));
  return d;
}

void make_counter_clockwise(Polygon2& polygon) {
  if (polygon_area(polygon) < 0) std::reverse(polygon.begin(), polygon.end());
}

Polygon2 clip_half_plane(const Polygon2& convex, const Vec2& at, const Vec2& m) {
  Polygon2 out;
  for (std::size_t i = 0; i < convex.size(); ++i) {
    const Vec2 &p = convex[i], &q = convex[(i + 1) % convex.size()];
    const double dp = (p - at).dot(m), dq = (q - at).dot(m);
    if (dp <= 0) out.push_back(p);
    if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  return out;
}

Polygon2 largest_polygon(const std::vector<Polygon2>& polygons) {
  const Polygon2* best = nullptr;
  for (const auto& c : polygons)
    if (polygon_area(c) > 0 && (!best || polygon_area(c) > polygon_area(*best))) best = &c;
  return best ? *best : Polygon2{};
}

StripFrame::StripFrame(const std::vector<Vec2>& points, int faces)
    : x(points), n(faces), s(faces + 1, 0.0) {
  for (int i = 0; i < n; ++i) s[i + 1] = s[i] + (mid(i + 1) - mid(i)).norm();
}

Polygon2 without_needles(Polygon2 ring, double width) {
  auto needle = [width](const Vec2& a, const Vec2& b, const Vec2& c) {
    const Vec2 u = b - a, w = c - b, v = c - a;
    if (u.dot(w) >= 0) return false;  // turns by a right angle or less
    const double longest = std::sqrt(std::max({u.squaredNorm(), w.squaredNorm(), v.squaredNorm()}));
    return std::abs(cross2(u, v)) < width * longest;
  };
  // A stack walk: a needle's tip goes, then the vertex before it is looked at again as a tip.
  Polygon2 kept;
  kept.reserve(ring.size());
  for (int pass = 0; pass < 2 && ring.size() >= 3; ++pass) {  // the second sees across the seam
    kept.clear();
    for (const Vec2& p : ring) {
      kept.push_back(p);
      while (kept.size() >= 3 && needle(kept[kept.size() - 3], kept[kept.size() - 2], kept.back()))
        kept.erase(kept.end() - 2);
    }
    bool more = true;
    while (more && kept.size() >= 3) {
      more = false;
      if (needle(kept[kept.size() - 2], kept.back(), kept.front())) kept.pop_back(), more = true;
      if (kept.size() >= 3 && needle(kept.back(), kept[0], kept[1]))
        kept.erase(kept.begin()), more = true;
    }
    const bool same = kept.size() == ring.size();
    ring.swap(kept);
    if (same) break;
  }
  if (ring.size() < 3) ring.clear();
  return ring;
}

int StripFrame::face_at(double at) const {
  return std::clamp(static_cast<int>(std::upper_bound(s.begin(), s.end(), at) - s.begin()) - 1, 0,
                    n - 1);
}

std::array<Vec2, 2> StripFrame::section(double at) const {
  const int f = face_at(at);
  const double len = s[f + 1] - s[f];
  const double u = len > 0 ? std::clamp((at - s[f]) / len, 0.0, 1.0) : 0.5;
  return {(1 - u) * x[2 * f] + u * x[2 * (f + 1)], (1 - u) * x[2 * f + 1] + u * x[2 * (f + 1) + 1]};
}

Vec2 StripFrame::along(double at) const {
  const int f = face_at(at);
  const Vec2 d = mid(std::min(f + 1, n)) - mid(f);
  return d.norm() > 0 ? Vec2(d.normalized()) : Vec2(1, 0);
}

bool holds_point_deeper_than(const Polygon2& outline, double depth) {
  const std::size_t n = outline.size();
  if (n < 3) return false;
  const double turn = polygon_area(outline) > 0 ? 1.0 : -1.0;  // left of the edges: inside
  std::vector<std::size_t> edges(n);
  std::iota(edges.begin(), edges.end(), std::size_t{0});
  auto length = [&](std::size_t i) { return (outline[(i + 1) % n] - outline[i]).squaredNorm(); };
  const std::size_t tried = std::min<std::size_t>(n, 8);
  std::partial_sort(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(tried), edges.end(),
                    [&](std::size_t a, std::size_t b) { return length(a) > length(b); });
  for (std::size_t k = 0; k < tried; ++k) {
    const Vec2 a = outline[edges[k]], b = outline[(edges[k] + 1) % n];
    if (!((b - a).norm() > 0)) continue;
    const Vec2 along = (b - a).normalized(), in = turn * Vec2(-along.y(), along.x());
    for (double t : {1.5, 2.0, 3.0, 5.0}) {
      const Vec2 p = 0.5 * (a + b) + t * depth * in;
      bool deep = inside(p, outline);
      for (std::size_t i = 0; i < n && deep; ++i)
        deep = distance_to_segment(p, outline[i], outline[(i + 1) % n]) > depth;
      if (deep) return true;
    }
  }
  return false;
}

}  // namespace kerfab

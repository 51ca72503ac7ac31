#include "kerfab/joints/plates.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace kerfab::border {

Plates::Plates(const Strips& strips, const Flattening& flat, double thickness)
    : frames_(strips.patches.size()), boxes_(strips.patches.size()), thickness_(thickness) {
  for (std::size_t p = 0; p < strips.patches.size(); ++p) {
    const auto locals = strips.patches[p].local_vertices();
    const auto& points = flat.patches[p].points;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& q : strips.patches[p].local_quads()) {
      // 3D = origin + x e1 + y e2 fitted to the four corners (least squares).
      Eigen::Matrix<double, 4, 3> a;
      Eigen::Matrix<double, 4, 3> b;
      Frame f;
      f.centre2 = Vec2::Zero();
      f.centre3 = Vec3::Zero();
      f.flat_lo = Vec2::Constant(std::numeric_limits<double>::infinity());
      f.flat_hi = -f.flat_lo;
      for (int k = 0; k < 4; ++k) {
        const Vec2 x = points[q[k]];
        const Vec3 y = strips.vertices[locals[q[k]]];
        a.row(k) << x.x(), x.y(), 1.0;
        b.row(k) = y.transpose();
        f.centre2 += 0.25 * x;
        f.centre3 += 0.25 * y;
        f.flat.push_back(x);
        f.flat_lo = f.flat_lo.cwiseMin(x), f.flat_hi = f.flat_hi.cwiseMax(x);
        lo = lo.cwiseMin(y), hi = hi.cwiseMax(y);
      }
      const Eigen::Matrix3d sol = a.colPivHouseholderQr().solve(b);
      f.e1 = sol.row(0).transpose();
      f.e2 = sol.row(1).transpose();
      f.origin = sol.row(2).transpose();
      for (int k = 0; k < 4; ++k)
        f.radius = std::max(f.radius, (strips.vertices[locals[q[k]]] - f.centre3).norm());
      const Vec3 n = f.e1.cross(f.e2);
      if (!(n.norm() > 1e-12)) continue;  // a collapsed sub-quad carries no frame
      f.n = n.normalized();
      Eigen::Matrix3d m;
      m << f.e1, f.e2, f.n;
      f.inverse = m.inverse();
      frames_[p].push_back(std::move(f));
    }
    boxes_[p] = {lo - Vec3::Constant(thickness), hi + Vec3::Constant(thickness)};
  }
}

std::pair<Vec3, Vec3> Plates::place(int p, const Vec2& v) const {
  const Frame* best = nullptr;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Frame& f : frames_[p]) {
    if (f.holds(v)) {
      best = &f;
      break;
    }
    const double d = (f.centre2 - v).squaredNorm();
    if (d < nearest) nearest = d, best = &f;
  }
  const Vec3 nan = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  if (!best) return {nan, nan};
  return {best->origin + v.x() * best->e1 + v.y() * best->e2, best->n};
}

Plates::Window Plates::window(int p, const Vec3& lo, const Vec3& hi) const {
  Window w;
  w.part = p;
  for (std::size_t i = 0; i < frames_[p].size(); ++i) {
    const Frame& f = frames_[p][i];
    const Vec3 grow = Vec3::Constant(f.radius + thickness_);
    if (((lo - grow).array() <= f.centre3.array()).all() &&
        (f.centre3.array() <= (hi + grow).array()).all()) {
      w.frames.push_back(static_cast<int>(i));
      w.centres.push_back(f.centre3);
    }
  }
  return w;
}

Vec3 Plates::local(const Window& w, const Vec3& q) const {
  // The nearest sub-quads by centre; of those, the first whose flat quad holds the point's flat
  // coordinates in its own frame (a bent part's frames differ by the bend between sub-quads).
  std::array<std::pair<double, const Frame*>, 4> nearest;
  nearest.fill({std::numeric_limits<double>::infinity(), nullptr});
  for (std::size_t k = 0; k < w.centres.size(); ++k) {
    const double d = (w.centres[k] - q).squaredNorm();
    if (d >= nearest.back().first) continue;
    nearest.back() = {d, &frames_[w.part][w.frames[k]]};
    std::sort(nearest.begin(), nearest.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
  }
  Vec3 first = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  for (const auto& [d, f] : nearest) {
    if (!f) break;
    const Vec3 l = f->inverse * (q - f->origin);
    if (f->holds(Vec2(l.x(), l.y()))) return l;
    if (!first.allFinite()) first = l;
  }
  return first;
}

std::vector<int> Plates::near(const Vec3& lo, const Vec3& hi) const {
  std::vector<int> out;
  for (std::size_t p = 0; p < boxes_.size(); ++p)
    if ((boxes_[p][0].array() <= hi.array()).all() && (lo.array() <= boxes_[p][1].array()).all())
      out.push_back(static_cast<int>(p));
  return out;
}

double Plates::deepest_in(const Window& w, const std::vector<Vec3>& qs,
                          const Polygon2& outline) const {
  constexpr double kReach = 1.0;  // distances to the outline beyond this do not matter
  double deepest = -std::numeric_limits<double>::infinity();
  // The points within the plate's thickness, in its flat frame.
  std::vector<std::pair<Vec2, double>> in_plate;  // (x, y), distance to the nearer face
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& q : qs) {
    const Vec3 l = local(w, q);
    if (!l.allFinite()) continue;
    const double face = 0.5 * thickness_ - std::abs(l.z());
    if (face <= 0) {
      deepest = std::max(deepest, face);
      continue;
    }
    in_plate.push_back({Vec2(l.x(), l.y()), face});
    lo = lo.cwiseMin(in_plate.back().first), hi = hi.cwiseMax(in_plate.back().first);
  }
  if (in_plate.empty() || outline.size() < 3) return deepest;
  // The outline's edges near the points; a point is inside if the reference point (the box's
  // centre) is, with an even number of those edges crossing the segment between them, or
  // outside with an odd number (the segment stays in the box, so only these edges can cross it).
  lo -= Vec2::Constant(kReach), hi += Vec2::Constant(kReach);
  std::vector<std::array<Vec2, 2>> edges;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Vec2 a = outline[i], b = outline[(i + 1) % outline.size()];
    if (std::max(a.x(), b.x()) < lo.x() || std::min(a.x(), b.x()) > hi.x() ||
        std::max(a.y(), b.y()) < lo.y() || std::min(a.y(), b.y()) > hi.y())
      continue;
    edges.push_back({a, b});
  }
  const Vec2 ref = 0.5 * (lo + hi);
  const bool ref_inside = inside(ref, outline);
  for (const auto& [v, face] : in_plate) {
    bool in = ref_inside;
    double d = kReach;
    for (const auto& [a, b] : edges) {
      d = std::min(d, distance_to_segment(v, a, b));
      // Half-open in the direction across the segment ref -> v, so a vertex on it counts once.
      const double sa = cross2(v - ref, a - ref), sb = cross2(v - ref, b - ref);
      if ((sa > 0) == (sb > 0)) continue;
      const double ta = cross2(b - a, ref - a), tb = cross2(b - a, v - a);
      if ((ta > 0) != (tb > 0)) in = !in;
    }
    deepest = std::max(deepest, in ? std::min(face, d) : -d);
  }
  return deepest;
}

}  // namespace kerfab::border

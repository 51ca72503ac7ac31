#pragma once
// Point probes on polygons for the tests, written apart from kerfab's own geometry so that a
// test checks the code with something that shares nothing with it.
#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <vector>

namespace kerfab::test {

/// Whether \p p lies inside \p poly by the even-odd rule.
inline bool inside_even_odd(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
        p.x() < (poly[j].x() - poly[i].x()) * (p.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) +
                    poly[i].x())
      in = !in;
  return in;
}

/// Distance from \p p to the nearest point of \p poly's outline.
inline double distance_to_outline(const Eigen::Vector2d& p,
                                  const std::vector<Eigen::Vector2d>& poly) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], e = poly[(i + 1) % poly.size()] - a;
    const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    d = std::min(d, (a + t * e - p).norm());
  }
  return d;
}

}  // namespace kerfab::test

#include "kerfab/joints/tooth_offsets.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kerfab {

ToothOffsets tooth_offsets(double fold, double thickness, double protrusion, double max_tip) {
  // Cross-section perpendicular to the border, border point at the origin. Part A lies along
  // -x: {x <= e_A, |y| <= h/2}. Part B is A turned by the fold: in-plane direction
  // b = (cos f, sin f), normal n = (-sin f, cos f), B = {p.b >= -e_B, |p.n| <= h/2}.
  const double f = std::abs(fold), h = thickness, c = std::cos(f), s = std::sin(f);
  ToothOffsets o;
  // (2) A's tooth corners (tip, -h/2) and (tip, +h/2) may leave B's slab, beyond the mitre,
  // by at most the protrusion: tip*s + h/2 c - h/2 <= P and tip*s - h/2 c - h/2 <= P.
  o.tip = std::min(protrusion + 0.5 * h * (1 - c), protrusion + 0.5 * h * (1 + c)) / s;
  o.tip = std::min(o.tip, max_tip);
  // (1) B's slotted edge p.b = -slot must stay behind every point of A inside B's slab:
  // slot = -max{p.b : x <= tip, |y| <= h/2, |p.n| <= h/2}, a linear maximum over the vertices
  // of a convex polygon.
  double best = -std::numeric_limits<double>::infinity();
  // Vertices where A's faces y = +-h/2 meet B's faces p.n = +-h/2 (those with x <= tip).
  for (double t : {-1.0, 1.0})
    for (double u : {-1.0, 1.0}) {
      const double x = 0.5 * h * (t * c - u) / s;
      if (x <= o.tip) best = std::max(best, 0.5 * h * (t - u * c) / s);
    }
  // The highest point of A's tooth end x = tip that lies in B's slab (p.b grows with y).
  double y_top = 0.5 * h;
  if (std::abs(c) > 1e-15) {
    const double y1 = (o.tip * s + 0.5 * h) / c, y2 = (o.tip * s - 0.5 * h) / c;
    y_top = std::min(y_top, std::max(y1, y2));
    const double y_bottom = std::max(-0.5 * h, std::min(y1, y2));
    if (y_top >= y_bottom) best = std::max(best, o.tip * c + y_top * s);
  } else if (o.tip <= 0.5 * h) {
    best = std::max(best, o.tip * c + y_top * s);
  }
  o.slot = -best;
  return o;
}

}  // namespace kerfab

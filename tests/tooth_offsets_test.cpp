#include "kerfab/joints/tooth_offsets.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "polygon_probe.h"

namespace kerfab {
namespace {

using P2 = Eigen::Vector2d;
using Polygon = std::vector<P2>;
constexpr double kPi = M_PI;

double cross(const P2& a, const P2& b) { return a.x() * b.y() - a.y() * b.x(); }

double area(const Polygon& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * a;
}

// Sutherland-Hodgman: convex subject clipped by a convex, counter-clockwise clip polygon.
Polygon clip(const Polygon& subject, const Polygon& clipper) {
  Polygon out = subject;
  for (std::size_t i = 0; i < clipper.size() && !out.empty(); ++i) {
    const P2 a = clipper[i], b = clipper[(i + 1) % clipper.size()];
    auto inside = [&](const P2& p) { return cross(b - a, p - a) >= 0; };
    Polygon in = out;
    out.clear();
    for (std::size_t j = 0; j < in.size(); ++j) {
      const P2 p = in[j], q = in[(j + 1) % in.size()];
      const double dp = cross(b - a, p - a), dq = cross(b - a, q - a);
      if (inside(p)) out.push_back(p);
      if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
    }
  }
  return out;
}

// The two parts' cross-sections for fold f, thickness h: part A along -x with its contour at
// x = e_a, part B turned by f with its contour at p.b = -e_b; and the mitred shell.
struct Section {
  double f, h, length;
  P2 b() const { return {std::cos(f), std::sin(f)}; }
  P2 n() const { return {-std::sin(f), std::cos(f)}; }
  Polygon part_a(double e_a) const {
    return {{-length, -h / 2}, {e_a, -h / 2}, {e_a, h / 2}, {-length, h / 2}};
  }
  Polygon part_b(double e_b) const {
    auto at = [&](double u, double v) -> P2 { return u * b() + v * n(); };
    return {at(-e_b, -h / 2), at(length, -h / 2), at(length, h / 2), at(-e_b, h / 2)};
  }
  Polygon shell() const {
    const double k = h / 2 * std::tan(f / 2);
    const P2 outer(k, -h / 2), inner(-k, h / 2);  // where the offsets meet (the mitre)
    return {{-length, -h / 2},    outer, outer + length * b(),
            inner + length * b(), inner, {-length, h / 2}};
  }
  // Largest distance by which part A's tooth (x in [0, tip]) leaves the shell.
  double protrusion(double tip) const {
    const Polygon s = shell();
    double worst = 0;
    for (int i = 0; i <= 200; ++i)
      for (double y : {-h / 2, h / 2, -h / 2 + h * i / 200.0}) {
        const P2 p(std::min(tip, tip * i / 100.0), y);
        if (test::inside_even_odd(p, s)) continue;
        worst = std::max(worst, test::distance_to_outline(p, s));
      }
    return worst;
  }
  double overlap(double tip, double slot) const {
    return std::abs(area(clip(part_a(tip), part_b(slot))));
  }
};

TEST(ToothOffsets, CrossSectionProofForEveryFoldAndThickness) {
  for (double h : {1.0, 3.0, 6.0})
    for (double allowed : {0.0, 0.2})
      for (int deg = 1; deg <= 179; ++deg) {
        SCOPED_TRACE("h " + std::to_string(h) + " fold " + std::to_string(deg) + " protrusion " +
                     std::to_string(allowed));
        const double f = deg * kPi / 180;
        const Section sec{f, h, 200 * h};
        for (double sign : {1.0, -1.0}) {  // convex and concave folds: the same offsets
          const ToothOffsets o = tooth_offsets(sign * f, h, allowed);
          EXPECT_GE(o.tip, 0.0);
          EXPECT_LT(o.slot, 0.0);
          const double eps = 1e-9 * h * h;
          // (1) tooth of A against slotted edge of B (and by symmetry B's tooth against A).
          EXPECT_LE(sec.overlap(o.tip, o.slot), eps);
          // (2) the tooth stays in the mitred shell (up to the allowed protrusion).
          EXPECT_LE(sec.protrusion(o.tip), allowed + 1e-9 * h);
          // (3) one percent more tip protrudes; one percent less cut-back overlaps.
          const double tip_more = o.tip * 1.01 + 1e-9;
          EXPECT_TRUE(sec.protrusion(tip_more) > allowed + 1e-12 * h ||
                      sec.overlap(tip_more, o.slot) > eps);
          EXPECT_GT(sec.overlap(o.tip, o.slot * 0.99), eps);
        }
      }
}

TEST(ToothOffsets, ClosedFormsWithoutProtrusion) {
  const double h = 3;
  for (int deg = 1; deg <= 179; ++deg) {
    const double f = deg * kPi / 180, t = std::tan(f / 2);
    const ToothOffsets o = tooth_offsets(f, h);
    if (deg <= 90) {
      EXPECT_NEAR(o.tip, h / 2 * t, 1e-12);
      EXPECT_NEAR(o.slot, -h / 2 * t * (1 + 2 * std::cos(f)), 1e-12);
    }
    if (deg >= 90) {
      EXPECT_NEAR(o.tip, h / 2 / t, 1e-12);
      EXPECT_NEAR(o.slot, -h / 2 * t, 1e-12);
    }
  }
  // Box corner: the tooth reaches through the other plate, glued depth h.
  const ToothOffsets box = tooth_offsets(kPi / 2, h);
  EXPECT_NEAR(box.tip, h / 2, 1e-12);
  EXPECT_NEAR(box.slot, -h / 2, 1e-12);
}

// The paper's Eq. 3-4 (o_b tip, o_a slot) under both readings of its angle psi.
ToothOffsets paper_offsets(double psi, double h) {
  if (psi > kPi / 2) {
    const double oa = -h / (2 * std::tan(0.5 * (kPi - psi)));
    return {oa + h / std::sin(psi), oa};
  }
  const double ob = h / (2 * std::tan(0.5 * psi));
  return {ob, ob - h * std::sin(psi)};
}

TEST(ToothOffsets, ThePrintedFormulaFailsForPartOfTheRangeEitherWay) {
  const double h = 3;
  // psi = fold: at 30 degrees the tooth sticks far out of the shell.
  const double f30 = kPi / 6;
  const Section s30{f30, h, 600};
  EXPECT_GT(s30.protrusion(paper_offsets(f30, h).tip), 0.5);
  // psi = pi - fold (angle between the parts): at 120 degrees the tooth protrudes ...
  const double f120 = 2 * kPi / 3;
  const Section s120{f120, h, 600};
  EXPECT_GT(s120.protrusion(paper_offsets(kPi - f120, h).tip), 0.3);
  // ... and at 60 degrees the slot is cut deeper than needed (0.866 h instead of 0.577 h).
  const double f60 = kPi / 3;
  EXPECT_LT(paper_offsets(kPi - f60, h).slot, tooth_offsets(f60, h).slot - 0.25 * h);
  // Where that reading agrees with ours: tip for folds up to 90 degrees.
  EXPECT_NEAR(paper_offsets(kPi - f60, h).tip, tooth_offsets(f60, h).tip, 1e-12);
}

}  // namespace
}  // namespace kerfab

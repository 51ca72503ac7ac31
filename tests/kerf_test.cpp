#include "kerfab/kerf/kerf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fixtures.h"
#include "kerfab/core/errors.h"
#include "shapes.h"

namespace kerfab {
namespace {

constexpr double kPi = M_PI;

struct Built {
  Strips strips;
  Flattening flat;
  Joints joints;
};

Built build(const PolyMesh& quads, const TriangleMesh& target_mesh, const StripsOptions& so = {},
            const BendingOptions& bo = {}) {
  const TargetSurface target(target_mesh);
  Built b;
  b.strips = build_strips(quads, choose_bending_edges(quads, target, bo), target, so);
  b.flat = flatten_patches(b.strips, {});
  b.joints = make_joints(b.strips, b.flat, {}, {}, {});
  return b;
}

TEST(Kerf, BeamCountSolvesTheTorsionRelation) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int printed_wrong = 0;
  for (int i = 0; i < 2000; ++i) {
    const double angle = 1e-4 + unit(rng), width = 0.1 + 20 * unit(rng);
    const double length = 1 + 100 * unit(rng), h = 0.5 + 6 * unit(rng);
    const double g = std::pow(10.0, 1 + 3 * unit(rng));  // G / tau from 10 to 10^4
    const double n = beams_needed(angle, width, length, h, g);
    const double a = std::pow(angle * g / length, 2);
    // Eq. 9-11: n^2 = A r^2 with r = sqrt(h^2 + (w/n)^2) / 2.
    EXPECT_NEAR(n * n, a * (h * h / 4 + width * width / (4 * n * n)), 1e-9 * n * n);
    // The printed Eq. 7 (minus under the root) is NaN or misses the relation.
    const double printed =
        std::sqrt(a * h * h / 8 + std::sqrt(a * a * h * h * h * h / 64 - a * width * width / 4));
    if (!std::isfinite(printed) ||
        std::abs(printed * printed - a * (h * h / 4 + width * width / (4 * printed * printed))) >
            1e-6 * printed * printed)
      ++printed_wrong;
  }
  EXPECT_GT(printed_wrong, 1900);  // only where A h^4 >> w^2 does it come close
  // Small A: the printed radicand is negative.
  {
    const double a = 1e-4, h = 3, w = 5;
    EXPECT_TRUE(std::isnan(std::sqrt(a * a * h * h * h * h / 64 - a * w * w / 4)));
    EXPECT_GT(beams_needed(std::sqrt(a) / 100, w, 1, h, 100), 0.0);
  }
  EXPECT_EQ(beams_needed(0.0, 5, 20, 3, 100), 0.0);  // no twist, no beams
}

// Continuum closed form for a ring of radius R and height H: over an arc W the normals turn by
// W/R, beams are H long, segment width W/2, so n_e = W c with
// c = sqrt(g^2 h^2 / 8 + sqrt(g^4 h^4 / 64 + g^2 / 16)), g = (G / tau_eff) / (R H); the ring
// needs 2 pi R c beams in all.
double ring_beams(double r, double height, double h, double shear_over_yield) {
  const double g = shear_over_yield / (r * height);
  return 2 * kPi * r *
         std::sqrt(g * g * h * h / 8 + std::sqrt(std::pow(g * h, 4) / 64 + g * g / 16));
}

TEST(Kerf, RingCutCountMatchesTheClosedForm) {
  for (double r : {40.0, 80.0})
    for (double height : {30.0, 60.0})
      for (double h : {2.0, 3.0, 6.0}) {
        SCOPED_TRACE("R " + std::to_string(r) + " H " + std::to_string(height) + " h " +
                     std::to_string(h));
        const auto shape = test::open_cylinder(r, height, 24, 1, 48);
        const Built b = build(shape.quads, shape.target);
        ASSERT_EQ(b.strips.patches.size(), 1u);
        Material m;
        m.thickness = h;
        const KerfResult k = place_kerf_cuts(b.strips, b.flat, b.joints, m, {}, {});
        const double g = m.shear_modulus / (m.yield_strength / m.safety);
        const double beams = ring_beams(r, height, h, g);
        EXPECT_NEAR(k.cuts, std::ceil(beams) - 1, 1.0) << "beams " << beams;
      }
}

TEST(Kerf, FlatPartsAndPaperGetNoCuts) {
  const auto plane = test::quad_plane(120, 4, 1);
  const Built flat = build(plane.quads, plane.target);
  EXPECT_EQ(place_kerf_cuts(flat.strips, flat.flat, flat.joints, {}, {}, {}).cuts, 0);
  const auto ring = test::open_cylinder(40, 30, 24, 1, 16);
  const Built b = build(ring.quads, ring.target);
  EXPECT_EQ(place_kerf_cuts(b.strips, b.flat, b.joints, material_preset("paper"), {}, {}).cuts, 0);
  EXPECT_GT(place_kerf_cuts(b.strips, b.flat, b.joints, {}, {}, {}).cuts, 20);
}

TEST(Kerf, DensityRisesWithCurvature) {
  // Elliptic tube, semi-axes 80 and 30 mm: curvature 0.089/mm at the ends of the long axis,
  // 0.0047/mm at the ends of the short one.
  auto ellipse = [](double u, double v) {
    return Vec3(80 * std::cos(2 * kPi * u), 30 * std::sin(2 * kPi * u), 40 * v);
  };
  const PolyMesh quads = test::grid_mesh(48, 1, true, false, ellipse);
  const Built b = build(quads, triangulate(test::grid_mesh(48 * 16, 16, true, false, ellipse)));
  ASSERT_EQ(b.strips.patches.size(), 1u);
  const KerfResult k = place_kerf_cuts(b.strips, b.flat, b.joints, {}, {}, {});
  const Patch& patch = b.strips.patches[0];
  // Cuts per mm of the sub-quads near |x| = 80 (tight) and near |y| = 30 (flat).
  double tight = 0, flat = 0;
  const auto& density = k.patches[0].face_density;
  for (std::size_t f = 0; f < density.size(); ++f) {
    const auto& q = b.strips.faces[patch.faces[f]];
    const Vec3 centre = 0.25 * (b.strips.vertices[q[0]] + b.strips.vertices[q[1]] +
                                b.strips.vertices[q[2]] + b.strips.vertices[q[3]]);
    if (std::abs(centre.x()) > 75) tight = std::max(tight, density[f]);
    if (std::abs(centre.y()) > 28 && std::abs(centre.x()) < 20) flat = std::max(flat, density[f]);
  }
  EXPECT_GT(tight, 2 * flat);
  EXPECT_GT(tight, 0);
}

TEST(Kerf, TightBendsAreCriticalAndCutsStayInsideTheirPart) {
  const auto shape = test::open_cylinder(12, 10, 24, 1, 16);
  const Built b = build(shape.quads, shape.target);
  KerfOptions o;
  const KerfResult k = place_kerf_cuts(b.strips, b.flat, b.joints, {}, {}, o);
  ASSERT_GT(k.cuts, 0);
  EXPECT_GT(k.critical.size(), 0u);  // R 12, H 10 in 3 mm MDF: ~95 beams, 0.8 mm apart
  for (const auto& c : k.critical) EXPECT_LT(c.spacing, o.min_cut_spacing);
  EXPECT_LT(k.patches[0].min_spacing, o.min_cut_spacing);
  // Every cut end lies inside the part, a margin away from its outline, and off its teeth.
  const Polygon2 body = flat_outline(b.strips, b.flat, 0);
  const auto shrunk =
      polygon_offset(polygon_intersection(b.joints.parts[0].designed, body), -o.margin + 1e-3);
  ASSERT_EQ(shrunk.size(), 1u);
  for (const KerfCut& c : k.patches[0].cuts)
    for (const Vec2& end : {c.a, c.b}) {
      double area = 0;
      for (const auto& poly :
           polygon_intersection(shrunk.front(), {end + Vec2(-1e-3, -1e-3), end + Vec2(1e-3, -1e-3),
                                                 end + Vec2(1e-3, 1e-3), end + Vec2(-1e-3, 1e-3)}))
        area += std::abs(polygon_area(poly));
      EXPECT_NEAR(area, 4e-6, 1e-9) << "cut end outside the part's margin";
    }
}

TEST(Kerf, RejectsBadMaterial) {
  EXPECT_THROW(material_preset("balsa"), InvalidInput);
  const auto ring = test::open_cylinder(40, 30, 12, 1, 4);
  const Built b = build(ring.quads, ring.target);
  Material m;
  m.yield_strength = 0;
  EXPECT_THROW(place_kerf_cuts(b.strips, b.flat, b.joints, m, {}, {}), InvalidInput);
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

bool segment_hits_polygon(const Vec2& a, const Vec2& b, const Polygon2& poly) {
  // Inside test of the end points, then proper crossings with the polygon's edges.
  auto cross = [](const Vec2& o, const Vec2& p, const Vec2& q) {
    return (p - o).x() * (q - o).y() - (p - o).y() * (q - o).x();
  };
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 &c = poly[i], &d = poly[(i + 1) % poly.size()];
    if (cross(a, b, c) * cross(a, b, d) < 0 && cross(c, d, a) * cross(c, d, b) < 0) return true;
  }
  double area = 0;
  for (const auto& p : polygon_intersection(poly, {a + Vec2(-1e-3, -1e-3), a + Vec2(1e-3, -1e-3),
                                                   a + Vec2(1e-3, 1e-3), a + Vec2(-1e-3, 1e-3)}))
    area += std::abs(polygon_area(p));
  return area > 0;
}

TEST(Kerf, SpotAdaptiveNeedsFarLessCuttingThanAConstantDensity) {
  const PreparedInput in = test::load(test::spot());
  const Strips s =
      build_strips(in.quads, choose_bending_edges(in.quads, in.surface, {}), in.surface, {});
  const Flattening f = flatten_patches(s, {});
  const Joints j = make_joints(s, f, {}, {}, {});
  const KerfResult adaptive = place_kerf_cuts(s, f, j, {}, {}, {});
  ASSERT_GT(adaptive.max_cuts_per_quad, 0);
  KerfOptions constant;
  constant.constant_cuts_per_quad = adaptive.max_cuts_per_quad;  // enough for the tightest quad
  const KerfResult uniform = place_kerf_cuts(s, f, j, {}, {}, constant);
  EXPECT_LT(adaptive.cut_length, 0.5 * uniform.cut_length);
  // No cut runs through a tooth.
  for (std::size_t p = 0; p < s.patches.size(); ++p)
    for (const KerfCut& c : adaptive.patches[p].cuts)
      for (const JointSpan& sp : j.parts[p].spans)
        if (sp.tooth) {
          EXPECT_FALSE(segment_hits_polygon(c.a, c.b, sp.region)) << "patch " << p;
        }
}

}  // namespace
}  // namespace kerfab

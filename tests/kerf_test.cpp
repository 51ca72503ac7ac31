#include "kerfab/kerf/kerf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
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

// Physics applied to the cuts as placed, sharing nothing with the code: each cut's middle is
// mapped from the flattened part back onto the 3D strip (same barycentric coordinates in the
// same sub-quad triangle), the analytic surface normal there gives the twist between two cuts,
// the 2D distance between the cut lines the beam's width, the analytic strip width its length.
struct Beam {
  double width = 0, twist = 0, length = 0;
  double stress(const Material& m) const {
    return m.shear_modulus * twist * 0.5 * std::sqrt(m.thickness * m.thickness + width * width) /
           length;
  }
};

struct Surface {
  std::function<Vec3(const Vec3&)> normal;  // analytic unit normal at a point on the surface
  double strip_width = 0;                   // the rulings' length [mm]
};

Vec3 to_3d(const Strips& s, const Flattening& f, int p, const Vec2& x) {
  const Patch& patch = s.patches[p];
  const auto& pts = f.patches[p].points;
  const auto lv = patch.local_vertices();
  auto p3 = [&](int local) { return s.vertices[lv[local]]; };
  double best = 1e300;
  Vec3 out = Vec3::Zero();
  for (const auto& q : patch.local_quads())
    for (const std::array<int, 3> t : {std::array<int, 3>{q[0], q[1], q[2]}, {q[0], q[2], q[3]}}) {
      const Vec2 a = pts[t[0]], b = pts[t[1]], c = pts[t[2]];
      const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      if (std::abs(det) < 1e-12) continue;
      const double u = ((x - a).x() * (c - a).y() - (x - a).y() * (c - a).x()) / det;
      const double v = ((b - a).x() * (x - a).y() - (b - a).y() * (x - a).x()) / det;
      const double outside = std::max({0.0, -u, -v, u + v - 1});
      if (outside < best) {
        best = outside;
        out = p3(t[0]) + u * (p3(t[1]) - p3(t[0])) + v * (p3(t[2]) - p3(t[0]));
      }
    }
  return out;
}

double line_distance(const Vec2& p, const KerfCut& c) {
  const Vec2 d = (c.b - c.a).normalized();
  return std::abs((p - c.a).x() * d.y() - (p - c.a).y() * d.x());
}

/// The beams between consecutive cuts of patch 0, in order along the strip.
std::vector<Beam> measured_beams(const Strips& s, const Flattening& f,
                                 const std::vector<KerfCut>& cuts, const Surface& surface) {
  std::vector<Beam> beams;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const Vec2 m0 = 0.5 * (cuts[i].a + cuts[i].b), m1 = 0.5 * (cuts[i + 1].a + cuts[i + 1].b);
    const Vec3 n0 = surface.normal(to_3d(s, f, 0, m0)), n1 = surface.normal(to_3d(s, f, 0, m1));
    beams.push_back({0.5 * (line_distance(m1, cuts[i]) + line_distance(m0, cuts[i + 1])),
                     std::atan2(n0.cross(n1).norm(), n0.dot(n1)), surface.strip_width});
  }
  return beams;
}

double largest_stress(const std::vector<Beam>& beams, const Material& m) {
  double worst = 0;
  for (const Beam& b : beams) worst = std::max(worst, b.stress(m));
  return worst;
}

struct PhysicsCase {
  std::string name;
  PolyMesh quads;
  TriangleMesh target;
  Surface surface;
};

std::vector<PhysicsCase> physics_cases() {
  std::vector<PhysicsCase> cases;
  for (double r : {40.0, 60.0, 90.0})
    for (double height : {25.0, 40.0}) {
      const auto ring = test::open_cylinder(r, height, 24, 1, 32);
      cases.push_back(
          {"ring R" + std::to_string(int(r)) + " H" + std::to_string(int(height)),
           ring.quads,
           ring.target,
           {[](const Vec3& p) { return Vec3(Vec3(p.x(), p.y(), 0).normalized()); }, height}});
    }
  {  // Frustum: radius 60 at z = 0 to 35 at z = 40.
    auto cone = [](double u, double v) {
      const double r = 60 - 25 * v;
      return Vec3(r * std::cos(2 * kPi * u), r * std::sin(2 * kPi * u), 40 * v);
    };
    cases.push_back({"cone",
                     test::grid_mesh(24, 1, true, false, cone),
                     triangulate(test::grid_mesh(24 * 32, 16, true, false, cone)),
                     {[](const Vec3& p) {
                        const double rho = std::hypot(p.x(), p.y());
                        return Vec3(Vec3(p.x() / rho, p.y() / rho, 25.0 / 40.0).normalized());
                      },
                      std::hypot(40.0, 25.0)}});
  }
  {  // Elliptic tube, semi-axes 80 and 30 mm, 40 mm high.
    auto ellipse = [](double u, double v) {
      return Vec3(80 * std::cos(2 * kPi * u), 30 * std::sin(2 * kPi * u), 40 * v);
    };
    cases.push_back(
        {"elliptic tube",
         test::grid_mesh(48, 1, true, false, ellipse),
         triangulate(test::grid_mesh(48 * 16, 16, true, false, ellipse)),
         {[](const Vec3& p) { return Vec3(Vec3(p.x() / 6400, p.y() / 900, 0).normalized()); },
          40.0}});
  }
  return cases;
}

TEST(Kerf, EveryPlacedBeamStaysWithinTheYieldStressAndNoneIsWasted) {
  const Material mdf;
  const double allowed = mdf.yield_strength / mdf.safety;
  for (const PhysicsCase& c : physics_cases()) {
    SCOPED_TRACE(c.name);
    const Built b = build(c.quads, c.target);
    ASSERT_EQ(b.strips.patches.size(), 1u);
    const KerfResult k = place_kerf_cuts(b.strips, b.flat, b.joints, mdf, {}, {});
    EXPECT_TRUE(k.critical.empty());
    const auto& cuts = k.patches[0].cuts;
    ASSERT_GT(cuts.size(), 10u);
    const std::vector<Beam> beams = measured_beams(b.strips, b.flat, cuts, c.surface);
    EXPECT_LE(largest_stress(beams, mdf), allowed);
    // Not wasteful: without every 20th cut some beam breaks ...
    std::vector<KerfCut> fewer;
    for (std::size_t i = 0; i < cuts.size(); ++i)
      if (i % 20 != 10) fewer.push_back(cuts[i]);
    EXPECT_GT(largest_stress(measured_beams(b.strips, b.flat, fewer, c.surface), mdf), allowed);
    // ... and so does any even spread of 5 % fewer cuts over the same stretch.
    const std::size_t n = cuts.size(), m = n - std::max<std::size_t>(1, n / 20);
    std::vector<KerfCut> spread;
    for (std::size_t i = 0; i < m; ++i) {
      const double t = static_cast<double>(i) * (n - 1) / (m - 1);
      const std::size_t j = std::min(static_cast<std::size_t>(t), n - 2);
      const double u = t - j;
      spread.push_back(
          {(1 - u) * cuts[j].a + u * cuts[j + 1].a, (1 - u) * cuts[j].b + u * cuts[j + 1].b, 0, 0});
    }
    EXPECT_GT(largest_stress(measured_beams(b.strips, b.flat, spread, c.surface), mdf), allowed);
  }
}

// The issue's reference: a ring of radius 60 mm and height 40 mm in 3 mm MDF (G / tau_eff =
// 100) needs 57 beams around (57 x 6.61 mm twisting 0.110 rad each reach tau_eff). The strip is
// open at its joint: its beams are the stretches between cuts and the two end pieces.
TEST(Kerf, RingOfRadius60AndHeight40NeedsFiftySevenBeams) {
  const auto ring = test::open_cylinder(60, 40, 24, 1, 32);
  const Built b = build(ring.quads, ring.target);
  ASSERT_EQ(b.strips.patches.size(), 1u);
  const KerfResult k = place_kerf_cuts(b.strips, b.flat, b.joints, {}, {}, {});
  EXPECT_NEAR(k.cuts + 1, 57, 1);
}

// Paper Sec. 3.5: merging sideways makes the beams longer, so fewer cuts do. Two rings of 20 mm
// merged cut like one ring of 40 mm.
TEST(Kerf, MergingTwoRingsCutsLikeOneRingOfTheirHeight) {
  const auto one = test::open_cylinder(60, 40, 24, 1, 16);
  const auto two = test::open_cylinder(60, 40, 24, 2, 16);
  StripsOptions merge;
  for (auto e : two.quads.edges()) {
    const auto h = two.quads.halfedge_handle(e, 0);
    const auto a = two.quads.from_vertex_handle(h), b = two.quads.to_vertex_handle(h);
    if (std::abs(two.quads.point(a)[2] - 20) < 1e-9 && std::abs(two.quads.point(b)[2] - 20) < 1e-9)
      merge.merge_edges.push_back({a.idx(), b.idx()});
  }
  const Built single = build(one.quads, one.target);
  const Built apart = build(two.quads, two.target);
  const Built merged = build(two.quads, two.target, merge);
  ASSERT_EQ(single.strips.patches.size(), 1u);
  ASSERT_EQ(apart.strips.patches.size(), 2u);
  ASSERT_EQ(merged.strips.patches.size(), 1u);
  const int cuts_single =
      place_kerf_cuts(single.strips, single.flat, single.joints, {}, {}, {}).cuts;
  const int cuts_apart = place_kerf_cuts(apart.strips, apart.flat, apart.joints, {}, {}, {}).cuts;
  const int cuts_merged =
      place_kerf_cuts(merged.strips, merged.flat, merged.joints, {}, {}, {}).cuts;
  EXPECT_NEAR(cuts_merged, cuts_single, 1);
  EXPECT_GT(cuts_apart, 2 * cuts_merged);  // two rows of half-length beams need more each
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
  // R 12, H 10 in 3 mm MDF: the beams would have to be about 0.5 mm wide. The cuts keep the
  // laser's minimum spacing, and the stretch is reported as critical with what it would need.
  EXPECT_GT(k.critical.size(), 0u);
  for (const auto& c : k.critical) {
    EXPECT_LT(c.spacing, o.min_cut_spacing);
    EXPECT_GT(c.stress_ratio, 1.0);
    EXPECT_EQ(c.cause, CriticalCause::kTooDense);
  }
  EXPECT_GE(k.patches[0].min_spacing, o.min_cut_spacing - 1e-9);
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
  // Measured: 32.1 m against 57.8 m (12 cuts per quad; both capped at the minimum spacing).
  EXPECT_LT(adaptive.cut_length, 0.6 * uniform.cut_length);
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

namespace kerfab {
namespace {

void expect_same_cuts(const KerfResult& a, const KerfResult& b) {
  EXPECT_EQ(a.cuts, b.cuts);
  EXPECT_EQ(a.cut_length, b.cut_length);
  EXPECT_EQ(a.quad_cuts, b.quad_cuts);
  EXPECT_EQ(a.tightest_bend, b.tightest_bend);
  EXPECT_EQ(a.cutting.minutes, b.cutting.minutes);
  ASSERT_EQ(a.critical.size(), b.critical.size());
  for (std::size_t i = 0; i < a.critical.size(); ++i) {
    const CriticalRegion &x = a.critical[i], &y = b.critical[i];
    EXPECT_EQ(x.patch, y.patch) << "region " << i;
    EXPECT_EQ(x.start, y.start);
    EXPECT_EQ(x.end, y.end);
    EXPECT_EQ(x.spacing, y.spacing);
    EXPECT_EQ(x.cuts, y.cuts);
    EXPECT_EQ(x.stress_ratio, y.stress_ratio);
    EXPECT_EQ(x.cause, y.cause);
    EXPECT_EQ(x.quads, y.quads);
    EXPECT_TRUE(x.centre == y.centre);
  }
  ASSERT_EQ(a.patches.size(), b.patches.size());
  for (std::size_t p = 0; p < a.patches.size(); ++p) {
    const PatchKerf &x = a.patches[p], &y = b.patches[p];
    EXPECT_EQ(x.twist, y.twist) << "patch " << p;
    EXPECT_EQ(x.positions, y.positions);
    EXPECT_EQ(x.min_spacing, y.min_spacing);
    EXPECT_EQ(x.stress_ratio, y.stress_ratio);
    EXPECT_EQ(x.tightest_bend, y.tightest_bend);
    EXPECT_EQ(x.face_density, y.face_density);
    EXPECT_EQ(x.face_critical, y.face_critical);
    ASSERT_EQ(x.cuts.size(), y.cuts.size()) << "patch " << p;
    for (std::size_t k = 0; k < x.cuts.size(); ++k) {
      EXPECT_TRUE(x.cuts[k].a == y.cuts[k].a && x.cuts[k].b == y.cuts[k].b);
      EXPECT_EQ(x.cuts[k].position, y.cuts[k].position);
      EXPECT_EQ(x.cuts[k].face, y.cuts[k].face);
    }
  }
}

// A KerfMemo changes nothing. On Spot's strips (with critical regions), place_kerf_cuts gives
// the same cuts, regions and totals without a memo, with an empty one (every patch placed),
// with the same memo again (every patch reused), under another material and other options with
// that memo (nothing reused that does not apply), and with a memo too small to keep anything.
TEST(Kerf, AMemoOfCutsChangesNothing) {
  const PreparedInput in = test::load(test::spot());
  const Strips s =
      build_strips(in.quads, choose_bending_edges(in.quads, in.surface, {}), in.surface, {});
  const Flattening f = flatten_patches(s, {});
  const Joints j = make_joints(s, f, {}, {}, {});
  auto place = [&](KerfMemo* memo, const Material& m = {}, const KerfOptions& o = {}) {
    return place_kerf_cuts(s, f, j, m, {}, o, memo);
  };
  const KerfResult plain = place(nullptr);
  ASSERT_GT(plain.cuts, 0);
  ASSERT_FALSE(plain.critical.empty());
  KerfMemo memo;
  expect_same_cuts(plain, place(&memo));
  EXPECT_EQ(memo.misses(), s.patches.size());
  expect_same_cuts(plain, place(&memo));
  EXPECT_EQ(memo.misses(), s.patches.size());  // the second call placed nothing
  EXPECT_EQ(memo.hits(), s.patches.size());
  const Material thin = material_preset("mdf2");
  expect_same_cuts(place(nullptr, thin), place(&memo, thin));
  KerfOptions wide;
  wide.min_cut_spacing = 1.5;
  expect_same_cuts(place(nullptr, {}, wide), place(&memo, {}, wide));
  EXPECT_EQ(memo.hits(), s.patches.size());  // neither found the mdf cuts
  KerfMemo tiny(1);
  expect_same_cuts(plain, place(&tiny));
  expect_same_cuts(plain, place(&tiny));
  EXPECT_EQ(tiny.hits(), 0u);
}

}  // namespace
}  // namespace kerfab

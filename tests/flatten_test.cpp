#include "kerfab/flatten/flatten.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "fixtures.h"
#include "kerfab/core/errors.h"
#include "kerfab/eval/surface_distance.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/pipeline/cuttable_patches.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

constexpr double kPi = M_PI;

struct Built {
  PolyMesh quads;
  TriangleMesh target;
  Strips strips;
};

// Strips on a quad mesh whose own triangulation is the target: planar quads stay planar after
// projection, so strips of a developable grid are exactly developable.
Built strips_on_own_mesh(PolyMesh quads, int k, const BendingOptions& bending_options = {}) {
  Built b;
  b.quads = std::move(quads);
  b.target = triangulate(b.quads);
  const TargetSurface target(b.target);
  const BendingResult bending = choose_bending_edges(b.quads, target, bending_options);
  StripsOptions o;
  o.rulings_per_quad = k;
  o.max_ruling_spacing = 1e9;
  b.strips = build_strips(b.quads, bending, target, o);
  return b;
}

double corner(const Vec3& p, const Vec3& n, const Vec3& q) {
  return std::atan2((n - p).cross(q - p).norm(), (n - p).dot(q - p));
}
double corner(const Vec2& p, const Vec2& n, const Vec2& q) {
  const Vec2 u = n - p, v = q - p;
  return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
}

// Every edge and diagonal length and every corner angle of every patch equals its 3D value.
void expect_isometric(const Strips& s, const Flattening& f, double tol) {
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    const Patch& patch = s.patches[p];
    const auto& x = f.patches[p].points;
    const auto lv = patch.local_vertices();
    auto p3 = [&](int local) { return s.vertices[lv[local]]; };
    EXPECT_TRUE(f.patches[p].converged);
    for (const auto& q : patch.local_quads()) {
      for (int a = 0; a < 4; ++a) {
        for (int b = a + 1; b < 4; ++b) {
          const double l3 = (p3(q[b]) - p3(q[a])).norm(), l2 = (x[q[b]] - x[q[a]]).norm();
          EXPECT_NEAR(l2, l3, tol * l3) << "patch " << p;
        }
        EXPECT_NEAR(corner(x[q[a]], x[q[(a + 1) % 4]], x[q[(a + 3) % 4]]),
                    corner(p3(q[a]), p3(q[(a + 1) % 4]), p3(q[(a + 3) % 4])), tol)
            << "patch " << p;
      }
    }
  }
}

TEST(Flatten, CylinderRingsUnrollIsometrically) {
  const auto shape = test::open_cylinder(40, 30, 16, 2, 1);
  const Built b = strips_on_own_mesh(shape.quads, 3);
  ASSERT_EQ(b.strips.patches.size(), 2u);
  const Flattening f = flatten_patches(b.strips, {});
  expect_isometric(b.strips, f, 1e-6);
  EXPECT_EQ(f.inverted_quads, 0);
  EXPECT_EQ(f.non_simple_outlines, 0);
  // A ring unrolls to a rectangle as long as the polygon's perimeter.
  const double perimeter = 16 * 2 * 40 * std::sin(kPi / 16);
  for (const auto& pf : f.patches) EXPECT_NEAR(pf.area_2d, perimeter * 15, 1e-6 * perimeter * 15);
  // The two rings share one border, equally long on both sides; each ring also meets itself
  // where its loop was cut (a 15 mm ruling).
  ASSERT_EQ(f.borders.size(), 3u);
  int rings_border = 0, loop_borders = 0;
  for (const SharedBorder& sb : f.borders) {
    const bool self = sb.patches[0] == sb.patches[1];
    const double expected = self ? 15.0 : perimeter;
    (self ? loop_borders : rings_border) += 1;
    EXPECT_NEAR(sb.length_3d, expected, 1e-9 * expected);
    EXPECT_NEAR(sb.length_2d[0], expected, 1e-6 * expected);
    EXPECT_NEAR(sb.length_2d[1], expected, 1e-6 * expected);
  }
  EXPECT_EQ(rings_border, 1);
  EXPECT_EQ(loop_borders, 2);
  EXPECT_LT(f.max_mating_mismatch_rel, 1e-6);
  // The 3D strips need no deformation to match the flat metric.
  EXPECT_LT(surface_distance(patch_triangles(b.strips, f, false),
                             patch_triangles(b.strips, f, true), {.sample_spacing = 2})
                .hausdorff,
            1e-6);
}

// Leaving a part out (the resolve stage's `omit`): of three stacked rings, the middle one. Its
// sub-quads go, the others are renumbered and keep their flattening, and the two borders it had
// with the outer rings are free edges: only the rings' own loop borders are left. A set that
// holds only some of a patch's quads leaves nothing out.
TEST(Flatten, LeavingAPartOutFreesItsNeighboursBorders) {
  const auto shape = test::open_cylinder(40, 45, 16, 3, 1);
  const Built b = strips_on_own_mesh(shape.quads, 3);
  ASSERT_EQ(b.strips.patches.size(), 3u);
  CuttablePatches c{b.strips, flatten_patches(b.strips, {})};
  ASSERT_EQ(c.flattening.borders.size(), 5u);  // two between rings, three loop cuts
  int middle = -1;                             // the ring with two neighbours
  for (int p = 0; p < 3; ++p) {
    int others = 0;
    for (const SharedBorder& sb : c.flattening.borders)
      others += sb.patches[0] != sb.patches[1] && (sb.patches[0] == p || sb.patches[1] == p);
    if (others == 2) middle = p;
  }
  ASSERT_NE(middle, -1);
  const auto quads = c.strips.patches[middle].all_quads();
  CuttablePatches some = c;
  EXPECT_TRUE(omit_patches(some, {quads.begin(), quads.end() - 1}).empty());
  EXPECT_EQ(some.strips.patches.size(), 3u);
  const std::size_t faces = c.strips.faces.size();
  std::vector<double> areas;
  for (int p = 0; p < 3; ++p)
    if (p != middle) areas.push_back(c.flattening.patches[p].area_2d);
  EXPECT_EQ(omit_patches(c, {quads.begin(), quads.end()}), std::vector<int>{middle});
  ASSERT_EQ(c.strips.patches.size(), 2u);
  ASSERT_EQ(c.flattening.patches.size(), 2u);
  EXPECT_EQ(c.strips.faces.size(), faces * 2 / 3);
  EXPECT_EQ(c.strips.face_quad.size(), c.strips.faces.size());
  for (int p : c.strips.face_patch) EXPECT_TRUE(p == 0 || p == 1) << p;
  for (int q : quads) EXPECT_EQ(c.strips.quad_patch[q], -1);
  for (int p = 0; p < 2; ++p) {
    EXPECT_EQ(c.flattening.patches[p].area_2d, areas[p]);
    for (int f : c.strips.patches[p].all_faces()) EXPECT_EQ(c.strips.face_patch[f], p);
  }
  ASSERT_EQ(c.flattening.borders.size(), 2u);
  for (const SharedBorder& sb : c.flattening.borders) {
    EXPECT_EQ(sb.patches[0], sb.patches[1]);
    EXPECT_NEAR(sb.length_3d, 15.0, 1e-9);
  }
  // The surface left is the two outer rings: two thirds of the cylinder's.
  double area = 0;
  const TriangleMesh t = triangulate(c.strips);
  for (const auto& tri : t.triangles)
    area += 0.5 * (t.vertices[tri[1]] - t.vertices[tri[0]])
                      .cross(t.vertices[tri[2]] - t.vertices[tri[0]])
                      .norm();
  const double perimeter = 16 * 2 * 40 * std::sin(kPi / 16);
  EXPECT_NEAR(area, perimeter * 30, 1e-6 * perimeter * 30);
}

TEST(Flatten, ConeStripsUnrollIsometrically) {
  // Frustum of a cone: radius 60 at z = 0 to 25 at z = 70; rings are developable.
  auto cone = [](double u, double v) {
    const double r = 60 - 35 * v;
    return Vec3(r * std::cos(2 * kPi * u), r * std::sin(2 * kPi * u), 70 * v);
  };
  const Built b = strips_on_own_mesh(test::grid_mesh(20, 3, true, false, cone), 4);
  const Flattening f = flatten_patches(b.strips, {});
  expect_isometric(b.strips, f, 1e-6);
  EXPECT_EQ(f.inverted_quads, 0);
  EXPECT_LT(f.max_mating_mismatch_rel, 1e-6);
}

TEST(Flatten, PlanarPatchIsReproducedUpToARigidMotion) {
  const auto shape = test::quad_plane(120, 5, 1);
  const Built b = strips_on_own_mesh(shape.quads, 3);
  const Flattening f = flatten_patches(b.strips, {});
  for (std::size_t p = 0; p < b.strips.patches.size(); ++p) {
    const Patch& patch = b.strips.patches[p];
    const auto& x = f.patches[p].points;
    // Best rotation + translation (no reflection) from the plane's (x, y) onto the flattening.
    std::vector<Vec2> y;
    for (const auto& r : patch.rulings)
      for (int rail = 0; rail < 2; ++rail) y.push_back(b.strips.vertices[r[rail]].head<2>());
    Vec2 cx = Vec2::Zero(), cy = Vec2::Zero();
    for (std::size_t i = 0; i < x.size(); ++i) cx += x[i], cy += y[i];
    cx /= x.size(), cy /= y.size();
    double s_cos = 0, s_sin = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Vec2 a = y[i] - cy, c = x[i] - cx;
      s_cos += a.dot(c);
      s_sin += a.x() * c.y() - a.y() * c.x();
    }
    const double angle = std::atan2(s_sin, s_cos);
    const Eigen::Rotation2Dd rot(angle);
    for (std::size_t i = 0; i < x.size(); ++i)
      EXPECT_LT((rot * (y[i] - cy) + cx - x[i]).norm(), 1e-9 * 120) << "patch " << p;
  }
}

TEST(Flatten, SphereStripsConvergeWithBoundedError) {
  const auto shape = test::sphere(50, 4);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  const Strips s = build_strips(shape.quads, bending, target, {});
  const Flattening f = flatten_patches(s, {});
  EXPECT_EQ(f.unconverged, 0);
  EXPECT_EQ(f.inverted_quads, 0);
  EXPECT_EQ(f.non_simple_outlines, 0);
  // Doubly curved: angles must give, a little; border lengths stay almost exact.
  EXPECT_GT(f.max_angle_error, 1e-4);
  EXPECT_LT(f.max_angle_error, 5 * kPi / 180);
  EXPECT_LT(f.max_border_length_error_rel, 1e-3);
  EXPECT_LT(f.max_mating_mismatch_rel, 1e-3);
  for (const auto& pf : f.patches) {
    EXPECT_LE(pf.energy, pf.initial_energy);
    EXPECT_NEAR(pf.area_2d, pf.area_3d, 0.01 * pf.area_3d);
  }
  // A heavier border-length weight trades angle error for border accuracy.
  FlattenOptions angles_first;
  angles_first.lambda = 0.1;
  const Flattening g = flatten_patches(s, angles_first);
  EXPECT_GT(g.max_border_length_error_rel, f.max_border_length_error_rel);
}

// The evaluation's deformation (deformed_3d: how far the 3D strips move to take their flat
// lengths) on doubly curved strips, which must move: every rail segment and ruling of it ends
// within a hundred-millionth of its patch's longest edge of its flat length (where the steps
// stop), from errors over ten thousand times larger, and no vertex moves far (under 5 mm).
TEST(Flatten, DeformedStripsTakeTheirFlatLengths) {
  const auto shape = test::sphere(50, 4);
  const TargetSurface target(shape.target);
  const Strips s =
      build_strips(shape.quads, choose_bending_edges(shape.quads, target, {}), target, {});
  const Flattening f = flatten_patches(s, {});
  ASSERT_EQ(f.patches.size(), s.patches.size());
  double worst_before = 0, moved = 0;
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    const auto& x = f.patches[p].points;
    const auto& y = f.patches[p].deformed_3d;
    const auto lv = s.patches[p].local_vertices();
    ASSERT_EQ(y.size(), x.size());
    double longest = 0, worst = 0;
    for (const auto& q : s.patches[p].local_quads())
      for (int a = 0; a < 4; ++a) longest = std::max(longest, (x[q[(a + 1) % 4]] - x[q[a]]).norm());
    for (const auto& q : s.patches[p].local_quads())
      for (int a = 0; a < 4; ++a) {
        const int i = q[a], j = q[(a + 1) % 4];
        const double flat = (x[j] - x[i]).norm();
        worst = std::max(worst, std::abs((y[j] - y[i]).norm() - flat));
        worst_before =
            std::max(worst_before,
                     std::abs((s.vertices[lv[j]] - s.vertices[lv[i]]).norm() - flat) / longest);
      }
    EXPECT_LE(worst, 1e-8 * longest) << "patch " << p;
    for (std::size_t v = 0; v < y.size(); ++v)
      moved = std::max(moved, (y[v] - s.vertices[lv[v]]).norm());
  }
  EXPECT_GT(worst_before, 1e-4);  // the strips had to move
  EXPECT_GT(moved, 1e-3);
  EXPECT_LT(moved, 5.0);  // mm, on a sphere of radius 50
}

TEST(Flatten, DeterministicAcrossThreadCounts) {
  const auto shape = test::torus(60, 20, 16, 8);
  const TargetSurface target(shape.target);
  const Strips s =
      build_strips(shape.quads, choose_bending_edges(shape.quads, target, {}), target, {});
  FlattenOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const Flattening a = flatten_patches(s, one), b = flatten_patches(s, two);
  ASSERT_EQ(a.patches.size(), b.patches.size());
  for (std::size_t p = 0; p < a.patches.size(); ++p)
    for (std::size_t i = 0; i < a.patches[p].points.size(); ++i)
      EXPECT_EQ(a.patches[p].points[i], b.patches[p].points[i]);
  FlattenOptions bad;
  bad.lambda = 1.5;
  EXPECT_THROW(flatten_patches(s, bad), InvalidInput);
}

TEST(Flatten, RealMeshesFitTogether) {
  for (const test::RealModel& model : {test::spot(), test::fandisk()}) {
    SCOPED_TRACE(model.target);
    const PreparedInput p = test::load(model);
    const Strips s = test::real_strips(p);
    const Flattening f = flatten_patches(s, {});
    EXPECT_EQ(f.unconverged, 0);
    EXPECT_EQ(f.inverted_quads, 0);
    EXPECT_LT(f.max_mating_mismatch_rel, 1e-3);  // mating borders within 0.1 %
    EXPECT_LT(f.max_shared_border_mismatch_rel, 1e-3);
    EXPECT_GT(f.borders.size(), s.patches.size() / 2);
    // Deforming the 3D strips to the flat rail and ruling lengths moves them by < 0.1 % of the
    // diagonal (the paper's observation).
    const double diag = bounding_box(p.surface.mesh()).diagonal();
    const SurfaceDistance moved = surface_distance(
        patch_triangles(s, f, false), patch_triangles(s, f, true), {.sample_spacing = 0.01 * diag});
    EXPECT_LT(moved.hausdorff / diag, 1e-3);
  }
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

TEST(Flatten, AHelicalBandOverlapsItselfInThePlaneAndIsReported) {
  // A band 20 mm wide around a helix of radius 50 mm, 1.25 turns, 40 mm rise per turn: no
  // contact in 3D, but unrolled it turns by about 450 degrees and must cross itself.
  auto band = [](double u, double v) {
    const double t = 2.5 * kPi * u, r = 40 + 20 * v;
    return Vec3(r * std::cos(t), r * std::sin(t), 40 * t / (2 * kPi));
  };
  const PolyMesh quads = test::grid_mesh(60, 1, false, false, band);
  // Strips along the helix: its long edges (constant radius) bend.
  auto along_helix = [](const Vec3& a, const Vec3& c) {
    return std::abs(std::hypot(a.x(), a.y()) - std::hypot(c.x(), c.y())) < 1e-6;
  };
  const BendingOptions opt = test::force_bendable(quads, along_helix);
  const Built b = strips_on_own_mesh(quads, 2, opt);
  ASSERT_EQ(b.strips.patches.size(), 1u);
  const Flattening f = flatten_patches(b.strips, {});
  EXPECT_FALSE(f.patches[0].outline_simple);
  EXPECT_EQ(f.non_simple_outlines, 1);
  EXPECT_EQ(f.inverted_quads, 0);
  // Split in the middle, each half unrolls without crossing.
  const Strips halves = split_patch(b.strips, 0, 30);
  ASSERT_EQ(halves.patches.size(), 2u);
  const Flattening g = flatten_patches(halves, {});
  EXPECT_EQ(g.non_simple_outlines, 0);
  ASSERT_EQ(g.borders.size(), 1u);  // the two halves meet along one ruling
  EXPECT_NEAR(g.borders[0].length_3d, 20, 1e-9);
  // One turn only: no crossing.
  auto one_turn = [](double u, double v) {
    const double t = 1.5 * kPi * u, r = 40 + 20 * v;
    return Vec3(r * std::cos(t), r * std::sin(t), 40 * t / (2 * kPi));
  };
  const PolyMesh short_quads = test::grid_mesh(36, 1, false, false, one_turn);
  const BendingOptions short_opt = test::force_bendable(short_quads, along_helix);
  const Built c = strips_on_own_mesh(short_quads, 2, short_opt);
  EXPECT_EQ(flatten_patches(c.strips, {}).non_simple_outlines, 0);
}

// One strip of 8 sub-quads rolled round a cylinder of radius 40 mm (developable: it unrolls to
// (arc length, height) exactly), its second rail at height \p width(s) over the first. Where
// the width is 0 the two rails' vertices are two vertices at one point.
Strips rolled_strip(const std::function<double(double)>& width) {
  constexpr int n = 8;
  constexpr double r = 40, step = 7.5;
  Strips s;
  Patch patch;
  for (int i = 0; i <= n; ++i) {
    const double arc = step * i;
    for (double y : {0.0, width(arc)})
      s.vertices.push_back(Vec3(r * std::sin(arc / r), y, r * std::cos(arc / r)));
    patch.rulings.push_back({2 * i, 2 * i + 1});
  }
  for (int i = 0; i < n; ++i) {
    s.faces.push_back({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
    s.face_patch.push_back(0);
    s.face_quad.push_back(i);
    patch.faces.push_back(i);
    patch.face_flipped.push_back(0);
    patch.rail_edges.push_back({-1, -1});
    patch.quads.push_back(i);
  }
  s.patches.push_back(patch);
  return s;
}

// A strip whose rails meet (its end or its start a point, or its waist: the rails touch there) has
// vertices the conformal start leaves free: one only in sub-quad triangles of no area, or a half
// joined to the rest at a point. The start then holds them to the strip's plane (stanford-bunny
// from its triangles failed here: "conformal map: factorisation failed"). All three flatten: every
// edge as long as in 3D, the vertices at one point still at one point. (A waist leaves its two
// halves free to turn about it: each is checked on its own.)
TEST(Flatten, AStripWhoseRailsMeetFlattensWithItsLengths) {
  for (const int shape : {0, 1, 2}) {
    SCOPED_TRACE(shape == 0   ? "rails meeting at the end"
                 : shape == 1 ? "rails touching at the waist"
                              : "rails meeting at the start");
    const Strips s = rolled_strip([shape](double arc) {
      return shape == 0   ? 10 * (1 - arc / 60)
             : shape == 1 ? 10 * std::abs(1 - arc / 30)
                          : 10 * arc / 60;
    });
    Flattening f;
    ASSERT_NO_THROW(f = flatten_patches(s, {}));
    const Patch& patch = s.patches[0];
    const std::vector<int> local = patch.local_vertices();
    const auto& x = f.patches[0].points;
    ASSERT_EQ(x.size(), local.size());
    for (const auto& q : patch.local_quads())
      for (int c = 0; c < 4; ++c) {
        const int a = q[c], b = q[(c + 1) % 4];
        const double l3 = (s.vertices[local[a]] - s.vertices[local[b]]).norm();
        EXPECT_NEAR((x[a] - x[b]).norm(), l3, 1e-3 * 7.5) << a << " - " << b;
      }
    for (const auto& q : patch.local_quads()) {  // each quad's diagonals (fixes its shape)
      const double d3 = (s.vertices[local[q[0]]] - s.vertices[local[q[2]]]).norm();
      EXPECT_NEAR((x[q[0]] - x[q[2]]).norm(), d3, 1e-2 * 7.5);
    }
  }
}

TEST(Flatten, InvertedQuadsAndCrossingOutlinesAreDetected) {
  const std::vector<Vec2> square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_EQ(count_inverted_quads(square, {{0, 1, 2, 3}}), 0);
  EXPECT_EQ(count_inverted_quads(square, {{0, 3, 2, 1}}), 1);         // clockwise: folded over
  const std::vector<Vec2> dart = {{0, 0}, {10, 0}, {3, 3}, {0, 10}};  // reflex corner
  EXPECT_EQ(count_inverted_quads(dart, {{0, 1, 2, 3}}), 1);
  const std::vector<Vec2> bowtie = {{0, 0}, {10, 0}, {0, 10}, {10, 10}};
  EXPECT_EQ(count_inverted_quads(bowtie, {{0, 1, 2, 3}}), 1);
  EXPECT_TRUE(is_simple_polygon(square, {0, 1, 2, 3}));
  EXPECT_FALSE(is_simple_polygon(bowtie, {0, 1, 2, 3}));
  const std::vector<Vec2> touching = {{0, 0}, {10, 0}, {10, 10}, {5, 0}, {0, 10}};
  EXPECT_FALSE(is_simple_polygon(touching, {0, 1, 2, 3, 4}));  // vertex on another edge
}

// A one-quad facet whose corners sit off any common plane: the flat quad keeps its four side
// lengths exactly, is strictly convex and counter-clockwise; a planar convex quad comes back
// congruent (angles and diagonals as in 3D); four lengths no quadrilateral has give nothing.
TEST(Flatten, AWarpedOneQuadFacetFlattensConvexWithItsSideLengths) {
  auto check = [](const std::array<Vec3, 4>& p) {
    const auto q = convex_quad(p);
    EXPECT_TRUE(q.has_value());
    if (!q) return std::array<Vec2, 4>{};
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(((*q)[(j + 1) % 4] - (*q)[j]).norm(), (p[(j + 1) % 4] - p[j]).norm(), 1e-9);
    const std::vector<Vec2> points(q->begin(), q->end());
    EXPECT_EQ(count_inverted_quads(points, {{0, 1, 2, 3}}), 0);
    return *q;
  };
  // Planar: a trapezoid tilted in space.
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  const std::array<Vec3, 4> trapezoid = {turn * Vec3(0, 0, 0), turn * Vec3(12, 0, 0),
                                         turn * Vec3(9, 7, 0), turn * Vec3(2, 7, 0)};
  const auto t = check(trapezoid);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR((t[(j + 2) % 4] - t[j]).norm(), (trapezoid[(j + 2) % 4] - trapezoid[j]).norm(),
                1e-9);
    EXPECT_NEAR(corner(t[j], t[(j + 1) % 4], t[(j + 3) % 4]),
                corner(trapezoid[j], trapezoid[(j + 1) % 4], trapezoid[(j + 3) % 4]), 1e-9);
  }
  // Corners moved so far by the facets around that the quad crosses itself in its own plane
  // (a bow tie: edges 1-2 and 3-0 cross); and one warped off any plane.
  check({Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(10, 10, 3), Vec3(0, 10, -3)});
  const std::array<Vec3, 4> warped = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 8),
                                      Vec3(10, 10, 8)};
  check(warped);
  // Four corners on a line (sides 10, 6, 2, 2: the longest as long as the rest): no quad.
  EXPECT_FALSE(convex_quad({Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(4, 0, 0), Vec3(2, 0, 0)})
                   .has_value());
}

// A facet over a plateau: a 3 x 3 grid of 10 mm quads on the plane z = 0 whose middle quad is
// lifted by 25 mm. Its outline is the flat 30 x 30 square (every outline corner's angle, summed
// over its quads, is 90 or 180 deg), but its quads cannot lie flat together: a corner quad's 3D
// angles sum to 300.5 deg. Cut along its outline, the facet is that square exactly, with its
// inner vertices inside and no quad turned over. A patch that is not there gives nothing.
TEST(Flatten, AFacetWhoseQuadsCannotLieFlatIsCutAlongItsOutline) {
  constexpr double h = 25;
  Strips s;
  auto id = [](int i, int j) { return 4 * j + i; };
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      s.vertices.emplace_back(10.0 * i, 10.0 * j, (i == 1 || i == 2) && (j == 1 || j == 2) ? h : 0);
  Patch facet;
  facet.flat = true;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int f = static_cast<int>(s.faces.size());
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      s.face_quad.push_back(f);
      s.face_patch.push_back(0);
      facet.quads.push_back(f);
      facet.faces.push_back(f);
      facet.flat_quads.push_back(s.faces.back());
    }
  for (int v = 0; v < 16; ++v) facet.flat_vertices.push_back(v);
  std::vector<int> ring;  // counter-clockwise around the square
  for (int i = 0; i < 3; ++i) ring.push_back(id(i, 0));
  for (int j = 0; j < 3; ++j) ring.push_back(id(3, j));
  for (int i = 3; i > 0; --i) ring.push_back(id(i, 3));
  for (int j = 3; j > 0; --j) ring.push_back(id(0, j));
  for (std::size_t k = 0; k < ring.size(); ++k) {
    OutlineEdge e;
    e.v = {ring[k], ring[(k + 1) % ring.size()]};
    e.coarse_edge = static_cast<int>(k);
    e.side = 0;
    facet.flat_outline.push_back(e);
  }
  s.patches.push_back(facet);
  // With its quads' angles, the facet flattens more than 20 deg off.
  EXPECT_GT(flatten_patches(s, {}).patches[0].max_angle_error, 20 * kPi / 180);
  const auto cut = flatten_facet_by_outline(s, 0, {});
  ASSERT_TRUE(cut.has_value());
  const PatchFlattening& p = *cut;
  EXPECT_EQ(p.inverted_quads, 0);
  EXPECT_TRUE(p.outline_simple);
  EXPECT_LT(p.max_angle_error, 1e-6);
  EXPECT_LT(p.max_border_length_error_rel, 1e-9);
  // The square: corners 30 mm apart along the sides, 30 sqrt(2) across.
  const auto& x = p.points;
  for (int k = 0; k < 4; ++k) {
    const Vec2 a = x[ring[3 * k]], b = x[ring[(3 * k + 3) % 12]], c = x[ring[(3 * k + 6) % 12]];
    EXPECT_NEAR((b - a).norm(), 30, 1e-6);
    EXPECT_NEAR((c - a).norm(), 30 * std::sqrt(2.0), 1e-6);
  }
  EXPECT_NEAR(p.area_2d, 900, 1e-6);
  EXPECT_FALSE(flatten_facet_by_outline(s, 1, {}).has_value());
  // Inner vertices strictly inside the square.
  const Vec2 o = x[ring[0]], u = (x[ring[3]] - o) / 30, w = (x[ring[9]] - o) / 30;
  for (int j = 1; j < 3; ++j)
    for (int i = 1; i < 3; ++i) {
      const Vec2 d = x[id(i, j)] - o;
      EXPECT_GT(d.dot(u), 1);
      EXPECT_LT(d.dot(u), 29);
      EXPECT_GT(d.dot(w), 1);
      EXPECT_LT(d.dot(w), 29);
    }
}

}  // namespace
}  // namespace kerfab

#include "kerfab/strips/strips.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "fixtures.h"
#include "kerfab/core/errors.h"
#include "kerfab/eval/surface_distance.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

constexpr double kPi = M_PI;

StripsOptions exact_k(int k) {
  StripsOptions o;
  o.rulings_per_quad = k;
  o.max_ruling_spacing = 1e9;  // only rulings_per_quad counts
  return o;
}

// Largest |analytic signed distance| over a dense sample of every sub-quad (bilinear patch).
double max_analytic_deviation(const Strips& s, const std::function<double(const Vec3&)>& sdf) {
  double worst = 0;
  for (const auto& q : s.faces)
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 16; ++j) {
        const double u = i / 16.0, v = j / 16.0;
        const Vec3 p = (1 - u) * (1 - v) * s.vertices[q[0]] + u * (1 - v) * s.vertices[q[1]] +
                       u * v * s.vertices[q[2]] + (1 - u) * v * s.vertices[q[3]];
        worst = std::max(worst, std::abs(sdf(p)));
      }
  return worst;
}

// Checks that patches partition the quads and sub-quads, and that each patch, as a mesh over
// the global vertex ids, is a topological disk (Euler characteristic 1, one boundary loop).
void expect_partition_into_disks(const PolyMesh& quads, const Strips& s) {
  std::vector<int> quad_count(quads.n_faces(), 0), face_count(s.faces.size(), 0);
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    const Patch& patch = s.patches[p];
    for (int q : patch.all_quads()) ++quad_count[q];
    for (int f : patch.all_faces()) ++face_count[f];
    ASSERT_EQ(patch.rulings.size(), patch.faces.size() + 1);
    std::set<int> verts;
    std::map<std::pair<int, int>, int> edges;
    for (int f : patch.all_faces()) {
      const auto& q = s.faces[f];
      for (int k = 0; k < 4; ++k) {
        verts.insert(q[k]);
        ++edges[{std::min(q[k], q[(k + 1) % 4]), std::max(q[k], q[(k + 1) % 4])}];
      }
    }
    const long chi = static_cast<long>(verts.size()) - static_cast<long>(edges.size()) +
                     static_cast<long>(patch.all_faces().size());
    EXPECT_EQ(chi, 1) << "patch " << p << " is not a disk";
    // Boundary edges (one face) must form a single closed loop.
    std::map<int, std::vector<int>> adj;
    int boundary_edges = 0;
    for (const auto& [e, n] : edges) {
      EXPECT_LE(n, 2) << "patch " << p << " has a non-manifold edge";
      if (n == 1) {
        adj[e.first].push_back(e.second);
        adj[e.second].push_back(e.first);
        ++boundary_edges;
      }
    }
    int walked = 0, prev = -1, cur = adj.begin()->first;
    const int start = cur;
    do {
      ASSERT_EQ(adj[cur].size(), 2u) << "patch " << p << " boundary is not a simple loop";
      const int next = adj[cur][0] != prev ? adj[cur][0] : adj[cur][1];
      prev = cur, cur = next, ++walked;
    } while (cur != start && walked <= boundary_edges);
    EXPECT_EQ(walked, boundary_edges) << "patch " << p << " has more than one boundary loop";
    // Outline edges: as many as boundary edges, each on the coarse edge it names.
    const auto outline = patch.outline();
    const auto lv = patch.local_vertices();
    EXPECT_EQ(static_cast<int>(outline.size()), boundary_edges);
    for (const OutlineEdge& e : outline) {
      ASSERT_GE(e.coarse_edge, 0);
      const auto& along = s.edge_vertices[e.coarse_edge];
      for (int local : e.v) {
        const Vec3 x = s.vertices[lv[local]];
        double nearest = std::numeric_limits<double>::infinity();
        for (int v : along) nearest = std::min(nearest, (s.vertices[v] - x).norm());
        EXPECT_LT(nearest, 1e-12) << "patch " << p << " outline side " << e.side;
      }
    }
  }
  for (std::size_t q = 0; q < quad_count.size(); ++q)
    EXPECT_EQ(quad_count[q], 1) << "quad " << q << " in " << quad_count[q] << " patches";
  for (std::size_t f = 0; f < face_count.size(); ++f)
    EXPECT_EQ(face_count[f], 1) << "sub-quad " << f;
}

double area(const TriangleMesh& m) {
  double a = 0;
  for (const auto& t : m.triangles)
    a += 0.5 *
         (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  return a;
}

// Sagitta of the widest sub-chord when a chord of central angle `delta` is split at k equal
// parameters and the points are projected radially onto the circle of radius r.
double ring_deviation(double r, double delta, int k) {
  double widest = 0;
  for (int i = 0; i < k; ++i) {
    const double b0 = std::atan((2.0 * i / k - 1) * std::tan(delta / 2));
    const double b1 = std::atan((2.0 * (i + 1) / k - 1) * std::tan(delta / 2));
    widest = std::max(widest, b1 - b0);
  }
  return r * (1 - std::cos(widest / 2));
}

TEST(Strips, CylinderRingsMatchTheAnalyticDeviationForEachRulingCount) {
  const double r = 50, height = 40;
  const int around = 12, along = 2, refine = 32;
  const auto shape = test::open_cylinder(r, height, around, along, refine);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  const double target_error = r * (1 - std::cos(kPi / (around * refine)));  // chordal
  double previous = std::numeric_limits<double>::infinity();
  for (int k : {1, 2, 3, 4, 6}) {
    const Strips s = build_strips(shape.quads, bending, target, exact_k(k));
    // Rings around the axis: one per row, each a closed loop cut open once.
    EXPECT_EQ(s.patches.size(), static_cast<std::size_t>(along));
    EXPECT_EQ(s.closed_loops, along);
    EXPECT_EQ(s.self_contacts, 2 * along);  // each cut ruling's two vertices are copied
    for (const Patch& p : s.patches) {
      EXPECT_EQ(p.quads.size(), static_cast<std::size_t>(around));
      EXPECT_EQ(p.faces.size(), static_cast<std::size_t>(around * k));
      EXPECT_TRUE(p.loop_cut);
      // Rulings parallel to the axis.
      for (const auto& ru : p.rulings) {
        const Vec3 d = (s.vertices[ru[1]] - s.vertices[ru[0]]).normalized();
        EXPECT_NEAR(std::abs(d.z()), 1.0, 1e-9);
      }
    }
    const double expected = ring_deviation(r, 2 * kPi / around, k);
    const double measured = max_analytic_deviation(s, shape.signed_distance);
    EXPECT_NEAR(measured, expected, target_error + 1e-9) << "k = " << k;
    EXPECT_LT(measured, previous);
    previous = measured;
    const SurfaceDistance d =
        surface_distance(triangulate(s), shape.target, {.sample_spacing = 0.2});
    EXPECT_NEAR(d.hausdorff, expected, target_error + 1e-3) << "k = " << k;
    expect_partition_into_disks(shape.quads, s);
  }
}

TEST(Strips, CylinderAxialStripsAreStraightWithDeviationIndependentOfRulings) {
  const double r = 50, height = 60;
  const int around = 12, along = 3;
  const auto shape = test::open_cylinder(r, height, around, along, 16);
  const TargetSurface target(shape.target);
  // Force every edge along the axis bendable: strips then run along the axis.
  const BendingOptions opt = test::force_bendable(shape.quads, [](const Vec3& a, const Vec3& b) {
    return std::abs((b - a).normalized().z()) > 0.99;
  });
  const BendingResult bending = choose_bending_edges(shape.quads, target, opt);
  const double expected = r * (1 - std::cos(kPi / around));  // sagitta of a coarse chord
  for (int k : {1, 3, 5}) {
    const Strips s = build_strips(shape.quads, bending, target, exact_k(k));
    EXPECT_EQ(s.patches.size(), static_cast<std::size_t>(around));
    EXPECT_EQ(s.closed_loops, 0);
    for (const Patch& p : s.patches) {
      EXPECT_EQ(p.quads.size(), static_cast<std::size_t>(along));
      // Both rails are one straight line along the axis.
      for (int rail = 0; rail < 2; ++rail) {
        const Vec3 a = s.vertices[p.rulings.front()[rail]], b = s.vertices[p.rulings.back()[rail]];
        for (const auto& ru : p.rulings) {
          const Vec3 v = s.vertices[ru[rail]];
          EXPECT_LT((v - a).cross(b - a).norm() / (b - a).squaredNorm(), 1e-9);
        }
      }
    }
    EXPECT_NEAR(max_analytic_deviation(s, shape.signed_distance), expected, 1e-9) << "k = " << k;
    expect_partition_into_disks(shape.quads, s);
  }
}

TEST(Strips, TJunctionVerticesStayOnTheirStraightEdge) {
  const auto shape = test::sphere(50, 4);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  const Strips s = build_strips(shape.quads, bending, target, exact_k(4));
  EXPECT_GT(s.t_junctions, 0);  // the cube sphere's corners force direction changes
  int checked = 0;
  for (auto e : shape.quads.edges()) {
    const auto& pts = s.edge_vertices[e.idx()];
    if (bending.bendable[e.idx()] || pts.size() <= 2) continue;
    const Vec3 a = s.vertices[pts.front()], b = s.vertices[pts.back()];
    for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
      const Vec3 v = s.vertices[pts[i]];
      EXPECT_LT((v - a).cross(b - a).norm() / (b - a).squaredNorm(), 1e-9);
      EXPECT_NEAR((v - a).dot(b - a) / (b - a).squaredNorm(),
                  static_cast<double>(i) / (pts.size() - 1), 1e-9);
      EXPECT_TRUE(s.vertex_on_straight_edge[pts[i]]);
      ++checked;
    }
  }
  EXPECT_GE(checked, s.t_junctions);
  // Projected vertices lie on the sphere (to the target's chordal error).
  for (std::size_t v = 0; v < s.vertices.size(); ++v)
    if (!s.vertex_on_straight_edge[v]) {
      EXPECT_LT(std::abs(shape.signed_distance(s.vertices[v])), 0.05);
    }
}

TEST(Strips, EveryTestShapeSplitsIntoDisksThatCoverItOnce) {
  std::vector<test::Shape> shapes;
  shapes.push_back(test::quad_plane(100, 6));
  shapes.push_back(test::open_cylinder(30, 80, 10, 4));
  shapes.push_back(test::closed_cylinder(30, 60, 4));
  shapes.push_back(test::sphere(40, 4));
  shapes.push_back(test::torus(60, 20, 16, 8));
  for (const auto& shape : shapes) {
    SCOPED_TRACE(shape.name);
    const TargetSurface target(shape.target);
    const BendingResult bending = choose_bending_edges(shape.quads, target, {});
    const Strips s = build_strips(shape.quads, bending, target, {});
    expect_partition_into_disks(shape.quads, s);
    // Overlapping strips would add area: the strip mesh's area is the surface's, to 3%.
    EXPECT_NEAR(area(triangulate(s)) / area(shape.target), 1.0, 0.03);
    EXPECT_LT(s.patches.size(), shape.quads.n_faces());
  }
}

TEST(Strips, SplittingAPatchKeepsAPartitionIntoDisks) {
  const auto shape = test::open_cylinder(40, 30, 16, 2);
  const TargetSurface target(shape.target);
  const Strips s =
      build_strips(shape.quads, choose_bending_edges(shape.quads, target, {}), target, exact_k(3));
  const Strips t = split_patch(s, 1, 5);
  ASSERT_EQ(t.patches.size(), 3u);
  EXPECT_EQ(t.patches[1].quads.size(), 5u);
  EXPECT_EQ(t.patches[2].quads.size(), 11u);
  EXPECT_EQ(t.patches[1].faces.size(), 15u);
  // The new border ruling is shared: last of the first part, first of the second.
  EXPECT_EQ(t.patches[1].rulings.back(), t.patches[2].rulings.front());
  EXPECT_EQ(t.patches[1].end_edges[1], t.patches[2].end_edges[0]);
  EXPECT_GE(t.patches[2].end_edges[0], 0);
  for (int q : t.patches[2].quads) EXPECT_EQ(t.quad_patch[q], 2);
  expect_partition_into_disks(shape.quads, t);
  EXPECT_THROW(split_patch(s, 1, 0), InvalidInput);
  EXPECT_THROW(split_patch(s, 5, 1), InvalidInput);
}

TEST(Strips, TorusRingsAreCutOpen) {
  const auto shape = test::torus(60, 20, 16, 8);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  const Strips s = build_strips(shape.quads, bending, target, {});
  // Every strip of a torus grid is a closed ring: each is cut once.
  EXPECT_EQ(s.closed_loops, s.chains);
  EXPECT_EQ(s.patches.size(), static_cast<std::size_t>(s.chains));
  for (const Patch& p : s.patches) EXPECT_TRUE(p.loop_cut);
}

TEST(Strips, SplitAngleBoundsTheFoldInsideAPatch) {
  // A 100 x 100 mm sheet folded by 90 degrees along v = 0.5, strips forced across the fold.
  auto fold = [](double u, double v) {
    return v <= 0.5 ? Vec3(100 * u, 100 * v, 0) : Vec3(100 * u, 50, 100 * (v - 0.5));
  };
  const PolyMesh quads = test::grid_mesh(6, 6, false, false, fold);
  const TargetSurface target(triangulate(test::grid_mesh(24, 24, false, false, fold)));
  // Edges of constant u bendable: rulings cross the fold.
  const BendingOptions opt = test::force_bendable(
      quads, [](const Vec3& a, const Vec3& b) { return std::abs(b.x() - a.x()) < 1e-9; });
  const BendingResult bending = choose_bending_edges(quads, target, opt);
  StripsOptions loose;
  loose.split_angle = kPi;
  const Strips whole = build_strips(quads, bending, target, loose);
  EXPECT_EQ(whole.split_borders, 0);
  EXPECT_EQ(whole.patches.size(), 6u);
  EXPECT_NEAR(whole.max_fold, kPi / 2, 1e-9);
  const Strips split = build_strips(quads, bending, target, {});  // 60 degrees
  EXPECT_EQ(split.split_borders, 6);
  EXPECT_EQ(split.patches.size(), 12u);
  EXPECT_NEAR(split.max_fold, 0, 1e-9);  // what is left of each strip is flat
  expect_partition_into_disks(quads, split);
  StripsOptions steep;
  steep.split_angle = 91 * kPi / 180;
  EXPECT_EQ(build_strips(quads, bending, target, steep).split_borders, 0);
}

TEST(Strips, FeatureProjectionPutsRimVerticesOnTheRim) {
  const double r = 30, height = 60;
  const auto shape = test::closed_cylinder(r, height, 4, 16);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  auto rim_error = [&](const Strips& s) {
    double worst = 0;
    for (auto e : shape.quads.edges()) {
      const auto h = shape.quads.halfedge_handle(e, 0);
      const Vec3 a = to_eigen(shape.quads.point(shape.quads.from_vertex_handle(h)));
      const Vec3 b = to_eigen(shape.quads.point(shape.quads.to_vertex_handle(h)));
      const bool on_rim = std::abs(std::abs(a.z()) - height / 2) < 1e-9 &&
                          std::abs(std::abs(b.z()) - height / 2) < 1e-9 &&
                          std::abs(std::hypot(a.x(), a.y()) - r) < 1e-9 &&
                          std::abs(std::hypot(b.x(), b.y()) - r) < 1e-9;
      if (!on_rim) continue;
      for (int v : s.edge_vertices[e.idx()]) {
        if (s.vertex_on_straight_edge[v]) continue;  // T-junctions stay on the straight edge
        const Vec3 p = s.vertices[v];
        worst =
            std::max(worst, std::hypot(std::hypot(p.x(), p.y()) - r, std::abs(p.z()) - height / 2));
      }
    }
    return worst;
  };
  StripsOptions plain = exact_k(4);
  StripsOptions features = plain;
  features.features = 30 * kPi / 180;
  const Strips a = build_strips(shape.quads, bending, target, plain);
  const Strips b = build_strips(shape.quads, bending, target, features);
  const double target_error = r * (1 - std::cos(kPi / (2 * 4 * 16)));  // rim polygon sagitta
  EXPECT_GT(b.feature_vertices, 0);
  EXPECT_LE(rim_error(b), target_error + 1e-9);
  EXPECT_GT(rim_error(a), 5 * target_error);  // normal projection leaves the rim
}

TEST(Strips, MaxRulingSpacingRaisesTheCountAndSharedEdgesAgree) {
  const auto shape = test::sphere(80, 3);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  StripsOptions o;
  o.rulings_per_quad = 1;
  o.max_ruling_spacing = 5;
  const Strips s = build_strips(shape.quads, bending, target, o);
  // Every bending edge is split finely enough; a shared edge has one set of vertices.
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const auto& q = s.faces[f];
    const int axis = s.quads[s.face_quad[f]].axis;
    (void)axis;
    EXPECT_LE((s.vertices[q[1]] - s.vertices[q[0]]).norm(), 5.0 * 1.05);
    EXPECT_LE((s.vertices[q[2]] - s.vertices[q[3]]).norm(), 5.0 * 1.05);
  }
  for (auto e : shape.quads.edges()) {
    if (!bending.bendable[e.idx()]) continue;
    const auto h = shape.quads.halfedge_handle(e, 0);
    const double len = (shape.quads.point(shape.quads.to_vertex_handle(h)) -
                        shape.quads.point(shape.quads.from_vertex_handle(h)))
                           .norm();
    EXPECT_GE(static_cast<double>(s.edge_vertices[e.idx()].size() - 1), len / 5 - 1e-9);
  }
}

TEST(Strips, DeterministicAndRejectsBadOptions) {
  const auto shape = test::sphere(40, 3);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  const Strips a = build_strips(shape.quads, bending, target, {});
  const Strips b = build_strips(shape.quads, bending, target, {});
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t v = 0; v < a.vertices.size(); ++v) EXPECT_EQ(a.vertices[v], b.vertices[v]);
  EXPECT_EQ(a.faces, b.faces);
  StripsOptions bad;
  bad.rulings_per_quad = 0;
  EXPECT_THROW(build_strips(shape.quads, bending, target, bad), InvalidInput);
  bad = {};
  bad.max_ruling_spacing = std::nan("");
  EXPECT_THROW(build_strips(shape.quads, bending, target, bad), InvalidInput);
  bad = {};
  bad.split_angle = 0;
  EXPECT_THROW(build_strips(shape.quads, bending, target, bad), InvalidInput);
}

TEST(Strips, RealMeshesMeetThePaperQuality) {
  for (const test::RealModel& model : {test::spot(), test::fandisk()}) {
    SCOPED_TRACE(model.target);
    const PreparedInput p = test::load(model);
    const Strips s = test::real_strips(p);
    expect_partition_into_disks(p.quads, s);
    const double diag = bounding_box(p.surface.mesh()).diagonal();
    const SurfaceDistance d =
        surface_distance(triangulate(s), p.surface.mesh(), {.sample_spacing = 0.004 * diag});
    EXPECT_LT(d.hausdorff / diag, 0.02);
    EXPECT_LT(d.mean / diag, 0.002);
    EXPECT_LT(s.patches.size(), p.quads.n_faces() / 5);
  }
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

TEST(Strips, QuadRowsAndTheNaiveRowLayoutOnGrids) {
  const auto plane = test::quad_plane(100, 6);
  EXPECT_EQ(quad_rows(plane.quads), 12);
  auto naive = [](const test::Shape& shape) {
    const TargetSurface target(shape.target);
    return build_strips(shape.quads, naive_row_bending(shape.quads), target, {}).patches.size();
  };
  EXPECT_EQ(naive(plane), 6u);  // one family of rows covers the plane
  const auto torus = test::torus(60, 20, 16, 8);
  EXPECT_EQ(quad_rows(torus.quads), 24);
  EXPECT_EQ(naive(torus),
            8u);  // the 8 rings of 16 quads, each cut open once the 8 rows of 16 quads, taken first
  const auto sphere = test::sphere(50, 4);  // 3 x 4 rings of 16 quads around the cube
  EXPECT_EQ(quad_rows(sphere.quads), 12);
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

// The coarse edges of a quad mesh whose two ends satisfy \p pick, as vertex index pairs.
std::vector<std::array<int, 2>> edges_where(
    const PolyMesh& m, const std::function<bool(const Vec3&, const Vec3&)>& pick) {
  std::vector<std::array<int, 2>> out;
  for (auto e : m.edges()) {
    const auto h = m.halfedge_handle(e, 0);
    const auto a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
    if (pick(to_eigen(m.point(a)), to_eigen(m.point(b)))) out.push_back({a.idx(), b.idx()});
  }
  return out;
}

// Paper Sec. 3.5: two ring strips of a cylinder merged sideways become one ring of twice the
// height, with its inner rail on the straight rulings.
TEST(Strips, MergingTwoRingsSidewaysGivesOneTwoRowRingWithStraightRulings) {
  const auto shape = test::open_cylinder(60, 40, 24, 2, 16);
  const TargetSurface target(shape.target);
  const BendingResult bending = choose_bending_edges(shape.quads, target, {});
  const Strips apart = build_strips(shape.quads, bending, target, {});
  ASSERT_EQ(apart.patches.size(), 2u);
  StripsOptions o;
  o.merge_edges = edges_where(shape.quads, [](const Vec3& a, const Vec3& b) {
    return std::abs(a.z() - 20) < 1e-9 && std::abs(b.z() - 20) < 1e-9;
  });
  ASSERT_EQ(o.merge_edges.size(), 24u);
  const Strips merged = build_strips(shape.quads, bending, target, o);
  ASSERT_EQ(merged.patches.size(), 1u);
  const Patch& p = merged.patches[0];
  EXPECT_EQ(p.rows(), 2);
  EXPECT_EQ(p.all_quads().size(), 48u);
  EXPECT_TRUE(p.loop_cut);
  expect_partition_into_disks(shape.quads, merged);
  // Every inner vertex on its ruling's straight segment, halfway up (equal rows).
  for (std::size_t i = 0; i < p.rulings.size(); ++i) {
    const Vec3 a = merged.vertices[p.rulings[i][0]], b = merged.vertices[p.rulings[i][1]];
    const Vec3 m = merged.vertices[p.more_rows[0].rail[i]];
    EXPECT_LT((m - a).cross(b - a).norm() / (b - a).norm(), 1e-9);
    EXPECT_NEAR((m - a).norm(), 20.0, 1e-6);
    EXPECT_NEAR((b - a).norm(), 40.0, 1e-6);
  }
}

TEST(Strips, MergeAndSplitGuidanceIsCheckedAndRefusedWithReasons) {
  const auto ring = test::open_cylinder(40, 30, 12, 2, 8);
  const TargetSurface target(ring.target);
  const BendingResult bending = choose_bending_edges(ring.quads, target, {});
  // An axial edge is a ruling of both its quads: the strips across it are not side by side.
  StripsOptions o;
  o.merge_edges = {edges_where(ring.quads, [](const Vec3& a, const Vec3& b) {
                     return std::abs(a.z() - b.z()) > 1;
                   }).front()};
  try {
    build_strips(ring.quads, bending, target, o);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("not aligned"), std::string::npos) << e.what();
  }
  o.merge_edges = {{0, 9999}};
  EXPECT_THROW(build_strips(ring.quads, bending, target, o), InvalidInput);
  // Splits: two axial edges of the lower ring cut it into two patches (no loop cut needed).
  o = {};
  o.split_edges = edges_where(ring.quads, [](const Vec3& a, const Vec3& b) {
    return std::abs(a.z() - b.z()) > 1 && std::min(a.z(), b.z()) < 1 && std::abs(a.y()) < 1e-9;
  });
  ASSERT_EQ(o.split_edges.size(), 2u);
  const Strips split = build_strips(ring.quads, bending, target, o);
  EXPECT_EQ(split.patches.size(), 3u);
  // A split inside a merged patch contradicts the merge.
  o.merge_edges = edges_where(ring.quads, [](const Vec3& a, const Vec3& b) {
    return std::abs(a.z() - 15) < 1e-9 && std::abs(b.z() - 15) < 1e-9;
  });
  o.split_edges = {o.merge_edges.front()};
  EXPECT_THROW(build_strips(ring.quads, bending, target, o), InvalidInput);
}

// The resolve stage's merges are wishes: one that no longer applies once a facet is made beside
// it (the resolve stage once lost every facet of a round, and then 67 of Spot's regions, to
// one such merge) is skipped, while the same edge given by a user is still refused.
TEST(Strips, SoftMergeEdgesThatNoLongerApplyAreSkipped) {
  const auto ring = test::open_cylinder(40, 30, 12, 2, 8);
  const TargetSurface target(ring.target);
  const BendingResult bending = choose_bending_edges(ring.quads, target, {});
  const auto middle = edges_where(ring.quads, [](const Vec3& a, const Vec3& b) {
    return std::abs(a.z() - 15) < 1e-9 && std::abs(b.z() - 15) < 1e-9;
  });
  ASSERT_EQ(middle.size(), 12u);
  // The quads of the upper ring beside the first six merge edges become one facet.
  std::set<int> above;
  for (int k = 0; k < 6; ++k) {
    const auto h = ring.quads.find_halfedge(ring.quads.vertex_handle(middle[k][0]),
                                            ring.quads.vertex_handle(middle[k][1]));
    for (auto hh : {h, ring.quads.opposite_halfedge_handle(h)}) {
      const auto f = ring.quads.face_handle(hh);
      if (f.is_valid() && ring.quads.calc_face_centroid(f)[2] > 15) above.insert(f.idx());
    }
  }
  ASSERT_EQ(above.size(), 6u);
  StripsOptions hard;
  hard.facets = {std::vector<int>(above.begin(), above.end())};
  hard.merge_edges = middle;
  try {
    build_strips(ring.quads, bending, target, hard);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("facet"), std::string::npos) << e.what();
  }
  StripsOptions soft = hard;
  soft.soft_merge_edges = soft.merge_edges;
  soft.merge_edges.clear();
  const Strips s = build_strips(ring.quads, bending, target, soft);
  // The facet, and the rings: the six merges beside the facet skipped, the other six kept (the
  // lower ring merged sideways with what is left of the upper one).
  int facets = 0, merged = 0;
  std::vector<int> held(ring.quads.n_faces(), 0);
  for (const Patch& p : s.patches) {
    for (int q : p.all_quads()) ++held[q];
    facets += p.flat ? 1 : 0;
    merged += p.rows() == 2 ? 1 : 0;
  }
  EXPECT_EQ(facets, 1);
  EXPECT_EQ(merged, 1);
  EXPECT_EQ(s.patches.size(), 3u);  // the facet, the merged run, the rest of the lower ring
  for (int n : held) EXPECT_EQ(n, 1);
}

// A merged patch must not contain a singularity of the quad mesh: on a cube sphere, two merge
// edges meeting at a cube corner (valence 3) are refused with the vertex named.
TEST(Strips, MergeThroughASingularityIsRefused) {
  const auto sphere = test::sphere(60, 3);
  const TargetSurface target(sphere.target);
  const BendingResult bending = choose_bending_edges(sphere.quads, target, {});
  int corner = -1;
  for (auto v : sphere.quads.vertices())
    if (sphere.quads.valence(v) == 3) corner = v.idx();
  ASSERT_GE(corner, 0);
  StripsOptions o;
  for (auto h : sphere.quads.voh_range(sphere.quads.vertex_handle(corner)))
    o.merge_edges.push_back({corner, sphere.quads.to_vertex_handle(h).idx()});
  try {
    build_strips(sphere.quads, bending, target, o);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("singularity"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace kerfab

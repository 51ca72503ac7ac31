// Coarsening of a given quad mesh (quads/coarsen.h): rows too narrow for their bend collapse, the
// rows beside them grow until the material can bend them, fidelity and topology kept.
#include "kerfab/quads/coarsen.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "kerfab/core/errors.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/kerf/kerf.h"
#include "kerfab/pipeline/resolve.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

/// Width a strip needs to bend at curvature kappa in \p m (docs/kerf-cuts.md: beams 1.5 x the
/// minimum cut spacing wide hold while g d sqrt(h^2 + d^2) <= 2 l / kappa), written out here
/// from the torsion relation, not taken from the code [mm].
double needed_width(const Material& m, double kappa, double spacing = 0.9) {
  const double g = m.shear_modulus / (m.yield_strength / m.safety), d = 1.5 * spacing;
  return 0.5 * g * d * std::sqrt(m.thickness * m.thickness + d * d) * kappa;
}

struct Topo {
  int euler = 0, borders = 0, faces = 0;
};
Topo topo(const PolyMesh& m) {
  int used = 0;
  for (auto v : m.vertices()) used += m.is_isolated(v) ? 0 : 1;
  return {used - static_cast<int>(m.n_edges()) + static_cast<int>(m.n_faces()),
          boundary_loop_count(m), static_cast<int>(m.n_faces())};
}

/// Every face a strictly convex quad, facing the way the target does there.
void expect_convex_quads_on(const PolyMesh& m, const TargetSurface& target) {
  ASSERT_TRUE(is_all_quads(m));
  for (auto f : m.faces()) {
    const auto v = quad_vertices(m, f);
    std::array<Vec3, 4> p;
    for (int k = 0; k < 4; ++k) p[k] = to_eigen(m.point(m.vertex_handle(v[k])));
    const Vec3 n = (p[2] - p[0]).cross(p[3] - p[1]).normalized();
    for (int k = 0; k < 4; ++k) {
      const Vec3 a = p[(k + 3) % 4] - p[k], b = p[(k + 1) % 4] - p[k];
      EXPECT_GT(b.cross(a).dot(n), 0) << "face " << f.idx() << " corner " << k;
    }
    const Vec3 c = 0.25 * (p[0] + p[1] + p[2] + p[3]);
    EXPECT_GT(n.dot(target.closest(c).normal), 0) << "face " << f.idx();
  }
  for (auto v : m.vertices()) {
    if (m.is_isolated(v)) continue;
    EXPECT_LT(target.closest(to_eigen(m.point(v))).distance, 1e-6) << "vertex " << v.idx();
  }
}

// A ring of rows 2 mm tall (R 30 mm): 3 mm MDF needs strips of 7.4 mm for its beams to hold
// around it, and 10.8 mm for one cut to fit across a strip at all (a 2 mm cut, a 2 mm bridge,
// 1 mm margins, 1.5 mm slots on both borders, and a cut spacing each side). The rows collapse
// until every ring strip is that wide; the rows along the axis do not bend and keep their
// width; the rings stay exact (straight rulings along the axis).
TEST(Coarsen, ThinRingsGrowUntilTheyCanBend) {
  const auto ring = test::open_cylinder(30, 60, 48, 30, 4);
  const TargetSurface target(ring.target);
  const Material mdf = material_preset("mdf");
  ASSERT_NEAR(needed_width(mdf, 1.0 / 30), 7.40, 0.01);
  const double need = 2 + 2 + 2 * 1 + 2 * 1.5 + 2 * 0.9;
  const CoarsenResult c = coarsen_quads(ring.quads, target, mdf, {});
  EXPECT_EQ(c.quads_before, 48 * 30);
  EXPECT_GT(c.rows_collapsed, 0);
  EXPECT_GT(c.narrow_before, 0.45);  // the ring rows' cross edges, half of all
  EXPECT_EQ(c.narrow_after, 0.0);
  const Topo before = topo(ring.quads), after = topo(c.quads);
  EXPECT_EQ(after.euler, before.euler);
  EXPECT_EQ(after.borders, 2);
  expect_convex_quads_on(c.quads, target);
  // Axial edges (the rings' cross edges) at least as long as the bend needs; the edges around
  // (2 pi 30 / 48 = 3.9 mm) unchanged; and every ring is whole: rows = faces / 48.
  for (auto e : c.quads.edges()) {
    const auto h = c.quads.halfedge_handle(e, 0);
    const Vec3 a = to_eigen(c.quads.point(c.quads.from_vertex_handle(h)));
    const Vec3 b = to_eigen(c.quads.point(c.quads.to_vertex_handle(h)));
    if (std::abs(a.z() - b.z()) <= 1e-6) {
      EXPECT_NEAR((a - b).norm(), 2 * 30 * std::sin(M_PI / 48), 1e-6);
      continue;
    }
    EXPECT_GE(std::abs(a.z() - b.z()), need - 1e-6);
    EXPECT_LT(std::abs(a.x() - b.x()) + std::abs(a.y() - b.y()), 1e-6);  // still axial
  }
  EXPECT_EQ(after.faces % 48, 0);
  EXPECT_LE(after.faces / 48, static_cast<int>(60 / need));
  EXPECT_GE(after.faces / 48, static_cast<int>(60 / (2 * need)));
}

// The physics it is for: the kerf cuts the same ring needs, as placed by the kerf stage, need
// cuts closer than the laser can make on the rows as given (30 critical stretches, whole rings)
// and none on the coarsened mesh but where a ring's two ends meet at its loop cut (the end
// pieces there, between the joint's slots, are the resolve stage's to mend).
TEST(Coarsen, TheCoarsenedRingNeedsNoCriticalRegionButAtItsLoopCut) {
  const auto ring = test::open_cylinder(30, 60, 48, 30, 4);
  const TargetSurface target(ring.target);
  const Material mdf = material_preset("mdf");
  auto critical = [&](const PolyMesh& quads) {
    InputOptions io;
    PreparedInput in = prepare_input(test::poly_mesh(ring.target), quads, io);
    PartsOptions o;
    o.material = mdf;
    o.usable.sheet_width = o.usable.sheet_height = 2000;
    const PartsBuild b = build_parts(in, o, {});
    std::vector<std::pair<double, double>> out;  // each stretch's distance from the nearer end
    for (const CriticalRegion& c : b.kerf.critical) {
      const double length = 2 * M_PI * 30;  // the ring's strips run all around
      out.push_back({c.start, length - c.end});
    }
    return out;
  };
  const auto before = critical(ring.quads);
  EXPECT_GE(before.size(), 25u);
  int whole = 0;
  for (const auto& [from_start, to_end] : before) whole += from_start < 1 && to_end < 1 ? 1 : 0;
  EXPECT_GE(whole, 20);
  const auto after = critical(coarsen_quads(ring.quads, target, mdf, {}).quads);
  EXPECT_LE(after.size(), 4u);
  for (const auto& [from_start, to_end] : after)
    EXPECT_LT(std::min(from_start, to_end), 6.0) << from_start << " " << to_end;
}

// Nothing to do: paper needs no kerf cuts; rows already wide enough stay; and a ring too small
// for any strip (R 4.5 mm, 15 mm tall: its bend needs strips of 49 mm) keeps its two rows, as
// one row would be just as narrow and its facets narrower.
TEST(Coarsen, NothingChangesWhereItWouldNotHelp) {
  const auto ring = test::open_cylinder(30, 60, 48, 30, 4);
  const TargetSurface target(ring.target);
  const CoarsenResult paper = coarsen_quads(ring.quads, target, material_preset("paper"), {});
  EXPECT_EQ(paper.rows_collapsed, 0);
  EXPECT_EQ(paper.quads_after, 48 * 30);
  const auto wide = test::open_cylinder(30, 60, 48, 5, 4);  // rows of 12 mm
  const TargetSurface wide_target(wide.target);
  const CoarsenResult w = coarsen_quads(wide.quads, wide_target, material_preset("mdf"), {});
  EXPECT_EQ(w.rows_collapsed, 0);
  EXPECT_EQ(w.narrow_before, 0.0);
  const auto tiny = test::open_cylinder(4.5, 15, 12, 2, 8);
  const TargetSurface tiny_target(tiny.target);
  const CoarsenResult t = coarsen_quads(tiny.quads, tiny_target, material_preset("mdf"), {});
  EXPECT_EQ(t.rows_collapsed, 0);
  EXPECT_EQ(t.quads_after, 24);
  EXPECT_GT(t.rows_refused, 0);
  CoarsenOptions off;
  off.enabled = false;
  EXPECT_EQ(coarsen_quads(ring.quads, target, material_preset("mdf"), off).rows_collapsed, 0);
  CoarsenOptions bad;
  bad.tolerance = 0;
  EXPECT_THROW(coarsen_quads(ring.quads, target, material_preset("mdf"), bad), InvalidInput);
}

// A sphere curves both ways: rows may widen only while a straight ruling across them stays
// within the tolerance (sag kappa l^2 / 8). Every quad's edges then stay within the widest
// faithful ruling, and the quads stay on the sphere.
TEST(Coarsen, RowsOnASphereStayFaithful) {
  const auto ball = test::sphere(50, 24, 2);
  const TargetSurface target(ball.target);
  const CoarsenOptions o;
  const double diagonal = bounding_box(ball.target).diagonal();
  const double faithful = std::sqrt(8 * o.tolerance * diagonal * 50);  // 16.6 mm
  const CoarsenResult c = coarsen_quads(ball.quads, target, material_preset("mdf"), o);
  EXPECT_GT(c.rows_collapsed, 0);
  EXPECT_LT(c.narrow_after, c.narrow_before);
  EXPECT_EQ(topo(c.quads).euler, 2);
  expect_convex_quads_on(c.quads, target);
  for (auto e : c.quads.edges()) {
    const auto h = c.quads.halfedge_handle(e, 0);
    const Vec3 a = to_eigen(c.quads.point(c.quads.from_vertex_handle(h)));
    const Vec3 b = to_eigen(c.quads.point(c.quads.to_vertex_handle(h)));
    EXPECT_LE((a - b).norm(), faithful) << e.idx();
  }
}

// Sharp features stay where they are: on a closed cylinder (sharp rims between the side and
// the caps), every vertex on a rim keeps its place, and no rim edge disappears into a row.
TEST(Coarsen, SharpFeaturesStayInPlace) {
  const auto can = test::closed_cylinder(30, 60, 24, 2);
  const TargetSurface target(can.target);
  const CoarsenResult c = coarsen_quads(can.quads, target, material_preset("mdf"), {});
  EXPECT_GT(c.rows_collapsed, 0);
  std::set<std::array<long, 3>> rim_before, rim_after;
  auto key = [](const OpenMesh::Vec3d& p) {
    return std::array<long, 3>{std::lround(p[0] * 1e4), std::lround(p[1] * 1e4),
                               std::lround(p[2] * 1e4)};
  };
  for (const PolyMesh* m : {&can.quads, &c.quads})
    for (auto v : m->vertices())
      if (!m->is_isolated(v) && std::abs(std::abs(m->point(v)[2]) - 30) < 1e-9 &&
          std::abs(std::hypot(m->point(v)[0], m->point(v)[1]) - 30) < 1e-9)
        (m == &can.quads ? rim_before : rim_after).insert(key(m->point(v)));
  EXPECT_FALSE(rim_after.empty());
  for (const auto& k : rim_after) EXPECT_TRUE(rim_before.count(k));
  // The rims are still closed loops of quad edges: every rim vertex has two rim edges.
  std::map<std::array<long, 3>, int> rim_edges;
  for (auto e : c.quads.edges()) {
    const auto h = c.quads.halfedge_handle(e, 0);
    const auto a = c.quads.point(c.quads.from_vertex_handle(h)),
               b = c.quads.point(c.quads.to_vertex_handle(h));
    if (rim_after.count(key(a)) && rim_after.count(key(b)) && std::abs(a[2] - b[2]) < 1e-9) {
      ++rim_edges[key(a)];
      ++rim_edges[key(b)];
    }
  }
  for (const auto& k : rim_after) EXPECT_EQ(rim_edges[k], 2);
  expect_convex_quads_on(c.quads, target);
  EXPECT_EQ(topo(c.quads).euler, 2);
}

// A real quad mesh two Catmull-Clark levels finer than Spot's cage, at 250 mm: rows collapse
// where Spot's legs, neck and body need wider strips, its topology stays, and the same input
// gives the same mesh.
TEST(Coarsen, SpotsFineQuadMeshKeepsItsTopology) {
  const PolyMesh quads = read_mesh(test::real_mesh("spot_quadrangulated.obj"));
  InputOptions io;
  io.size = 250;
  const PreparedInput in = prepare_input(quads, quads, io);
  const CoarsenResult c = coarsen_quads(in.quads, in.surface, material_preset("mdf"), {});
  EXPECT_EQ(c.quads_before, 2928);
  EXPECT_LT(c.quads_after, 0.8 * c.quads_before);
  EXPECT_LT(c.narrow_after, c.narrow_before - 0.02);
  EXPECT_EQ(topo(c.quads).euler, 2);
  EXPECT_EQ(topo(c.quads).borders, 0);
  expect_convex_quads_on(c.quads, in.surface);
  const CoarsenResult again = coarsen_quads(in.quads, in.surface, material_preset("mdf"), {});
  ASSERT_EQ(again.quads.n_vertices(), c.quads.n_vertices());
  for (auto v : c.quads.vertices()) EXPECT_EQ(again.quads.point(v), c.quads.point(v));
}

/// Interior vertex valence -> count.
std::map<int, int> valences(const PolyMesh& m) {
  std::map<int, int> out;
  for (auto v : m.vertices())
    if (!m.is_isolated(v)) ++out[static_cast<int>(m.valence(v)) + (m.is_boundary(v) ? 100 : 0)];
  return out;
}

/// Checks that \p coarse is \p fine one level of subdivision back: every corner one of fine's
/// vertices, every edge a path of two fine edges through a vertex of valence 4 (3 on the
/// border: the edge point), every quad's diagonal corners on fine quads that share an inner
/// vertex of valence 4 (the face point), and subdividing it again gives fine's counts and
/// valences.
void expect_one_level_back(const PolyMesh& coarse, const PolyMesh& fine) {
  std::map<std::array<double, 3>, OpenMesh::VertexHandle> at;
  for (auto v : fine.vertices()) at[{fine.point(v)[0], fine.point(v)[1], fine.point(v)[2]}] = v;
  auto in_fine = [&](OpenMesh::VertexHandle v) {
    const auto it = at.find({coarse.point(v)[0], coarse.point(v)[1], coarse.point(v)[2]});
    EXPECT_NE(it, at.end()) << "corner " << v.idx() << " is no vertex of the finer mesh";
    return it == at.end() ? OpenMesh::VertexHandle() : it->second;
  };
  auto between = [&](OpenMesh::VertexHandle a, OpenMesh::VertexHandle b) {  // common neighbours
    std::set<int> na, both;
    for (auto w : fine.vv_range(a)) na.insert(w.idx());
    for (auto w : fine.vv_range(b))
      if (na.count(w.idx())) both.insert(w.idx());
    return both;
  };
  for (auto e : coarse.edges()) {
    const auto h = coarse.halfedge_handle(e, 0);
    const auto a = in_fine(coarse.from_vertex_handle(h)), b = in_fine(coarse.to_vertex_handle(h));
    if (!a.is_valid() || !b.is_valid()) continue;
    bool edge_point = false;
    for (int m : between(a, b)) {
      const auto v = fine.vertex_handle(m);
      edge_point = edge_point || fine.valence(v) == (fine.is_boundary(v) ? 3u : 4u);
    }
    EXPECT_TRUE(edge_point) << "edge " << e.idx();
  }
  for (auto f : coarse.faces()) {
    const auto c = quad_vertices(coarse, f);
    const auto a = in_fine(coarse.vertex_handle(c[0])), b = in_fine(coarse.vertex_handle(c[2]));
    if (!a.is_valid() || !b.is_valid()) continue;
    auto on_faces_at = [&](OpenMesh::VertexHandle x) {  // corners of the fine quads at x
      std::set<int> out;
      for (auto g : fine.vf_range(x))
        for (auto w : g.vertices()) out.insert(w.idx());
      return out;
    };
    const std::set<int> at_a = on_faces_at(a);
    bool face_point = false;  // a corner of a fine quad at both diagonal corners
    for (int m : on_faces_at(b)) {
      const auto v = fine.vertex_handle(m);
      face_point = face_point || (at_a.count(m) && !fine.is_boundary(v) && fine.valence(v) == 4u);
    }
    EXPECT_TRUE(face_point) << "face " << f.idx();
  }
  const PolyMesh again = catmull_clark(coarse, 1);
  EXPECT_EQ(again.n_faces(), fine.n_faces());
  EXPECT_EQ(again.n_vertices(), fine.n_vertices());
  EXPECT_EQ(valences(again), valences(fine));
}

// Issue 18: a mesh some Catmull-Clark levels finer than its cage is taken back level by level:
// each level is the one before it (its corners the old vertices, its edges and quads through
// the edge and face points), down to the cage, which is no subdivision; a cube grid with an odd
// count per side is none either. Closed (a cube) and open (a square).
TEST(Coarsen, SubdivisionLevelsAreTakenBackExactly) {
  const PolyMesh cube = test::cube_grid_mesh(1, [](const Vec3& p) { return Vec3(50 * p); });
  const PolyMesh square = test::quad_plane(100, 1).quads;
  for (const PolyMesh* cage : {&cube, &square}) {
    PolyMesh fine = catmull_clark(*cage, 3);
    for (int level = 3; level > 0; --level) {
      const auto back = take_back_subdivision(fine);
      ASSERT_TRUE(back) << level;
      EXPECT_EQ(back->n_faces(), catmull_clark(*cage, level - 1).n_faces());
      EXPECT_EQ(topo(*back).euler, topo(*cage).euler);
      EXPECT_EQ(topo(*back).borders, topo(*cage).borders);
      expect_one_level_back(*back, fine);
      fine = *back;
    }
    EXPECT_EQ(fine.n_faces(), cage->n_faces());
    EXPECT_FALSE(take_back_subdivision(fine));
  }
  EXPECT_FALSE(take_back_subdivision(test::cube_grid_mesh(3, [](const Vec3& p) { return p; })));
  // Spot's cage has triangles: its first subdivision is as far back as quads go.
  const PolyMesh spot = catmull_clark(read_mesh(test::real_mesh("spot_control_mesh.obj")), 2);
  const auto once = take_back_subdivision(spot);
  ASSERT_TRUE(once);
  EXPECT_EQ(once->n_faces(), 732u);
  EXPECT_FALSE(take_back_subdivision(*once));
}

// Spot's cage with three Catmull-Clark steps (11,712 quads) at 500 mm: its rows wind round the
// model and cross themselves, so few of them can be collapsed one by one; levels of it are taken
// back instead, as long as every quad stays convex on the target and the middles of its edges
// and quads stay within the tolerance of it (a straight ruling across a row twice as wide).
TEST(Coarsen, ASubdividedCageIsTakenBackWhileItKeepsFaith) {
  InputOptions io;
  io.size = 500;
  io.subdivide = 3;
  const PreparedInput in = prepare_input(read_mesh(test::real_mesh("spot_triangulated.obj")),
                                         read_mesh(test::real_mesh("spot_control_mesh.obj")), io);
  const CoarsenOptions o;
  const CoarsenResult c = coarsen_quads(in.quads, in.surface, material_preset("mdf"), o);
  EXPECT_EQ(c.quads_before, 11712);
  EXPECT_GE(c.levels_taken_back, 1);
  EXPECT_LE(c.quads_after, 2928);
  EXPECT_LT(c.narrow_after, 0.35);
  EXPECT_LT(c.narrow_after, c.narrow_before - 0.3);
  EXPECT_EQ(topo(c.quads).euler, 2);
  EXPECT_EQ(topo(c.quads).borders, 0);
  expect_convex_quads_on(c.quads, in.surface);
  // The levels taken back keep faith: the middles of their edges and quads lie within the
  // tolerance of the target (the rows collapsed after them follow their own rule).
  const double tolerance = o.tolerance * bounding_box(in.surface.mesh()).diagonal();
  PolyMesh level = in.quads;
  for (int k = 0; k < c.levels_taken_back; ++k) {
    const auto back = take_back_subdivision(level);
    ASSERT_TRUE(back);
    level = *back;
  }
  EXPECT_EQ(level.n_faces(), 11712u >> (2 * c.levels_taken_back));
  for (auto v : level.vertices())
    level.set_point(v, to_openmesh(in.surface.closest(to_eigen(level.point(v))).point));
  for (auto e : level.edges()) {
    const auto h = level.halfedge_handle(e, 0);
    const Vec3 mid = 0.5 * (to_eigen(level.point(level.from_vertex_handle(h))) +
                            to_eigen(level.point(level.to_vertex_handle(h))));
    EXPECT_LE(in.surface.closest(mid).distance, tolerance) << "edge " << e.idx();
  }
  for (auto f : level.faces()) {
    Vec3 centre = Vec3::Zero();
    for (auto v : f.vertices()) centre += 0.25 * to_eigen(level.point(v));
    EXPECT_LE(in.surface.closest(centre).distance, tolerance) << "face " << f.idx();
  }
  // Too tight a tolerance for the cage's levels: none is taken back.
  CoarsenOptions tight;
  tight.tolerance = 1e-4;
  EXPECT_EQ(coarsen_quads(in.quads, in.surface, material_preset("mdf"), tight).levels_taken_back,
            0);
}

}  // namespace
}  // namespace kerfab

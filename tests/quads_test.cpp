// Quad meshing of triangle targets (src/kerfab/quads): alignment, topology and soundness,
// checked on generated shapes with exact answers and on real meshes.
#include "kerfab/quads/quads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "cli_util.h"
#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/errors.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/quads/fields.h"
#include "kerfab/quads/sweep.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

constexpr double kPi = 3.14159265358979323846;

QuadMeshResult mesh_of(const TriangleMesh& target, QuadMeshOptions o = {}) {
  const TargetSurface surface(target);
  return make_quad_mesh(surface, Material{}, o);
}

/// The triangles of \p file, scaled so that their largest side is 250 mm (as `--size 250`).
TriangleMesh at_250_mm(const std::filesystem::path& file) {
  TriangleMesh t = triangulate(read_mesh(file));
  const double side = bounding_box(t).largest_side();
  for (auto& v : t.vertices) v *= 250.0 / side;
  return t;
}

int euler(const PolyMesh& m) {
  return static_cast<int>(m.n_vertices()) - static_cast<int>(m.n_edges()) +
         static_cast<int>(m.n_faces());
}

/// Every face a convex quad whose corners turn the same way (measured here, not by the stage).
void expect_sound_quads(const PolyMesh& q) {
  ASSERT_TRUE(is_all_quads(q));
  for (auto f : q.faces()) {
    const auto v = quad_vertices(q, f);
    Vec3 sum = Vec3::Zero();
    std::array<Vec3, 4> n;
    for (int c = 0; c < 4; ++c) {
      const Vec3 p = to_eigen(q.point(OpenMesh::VertexHandle(v[c])));
      const Vec3 a = to_eigen(q.point(OpenMesh::VertexHandle(v[(c + 1) % 4]))) - p;
      const Vec3 b = to_eigen(q.point(OpenMesh::VertexHandle(v[(c + 3) % 4]))) - p;
      n[c] = a.cross(b);
      sum += n[c];
    }
    for (int c = 0; c < 4; ++c)
      ASSERT_GT(n[c].dot(sum), 0) << "face " << f.idx() << " corner " << c;
  }
  // Manifold: every edge has one or two faces, every vertex one fan.
  for (auto v : q.vertices()) EXPECT_TRUE(q.is_manifold(v)) << "vertex " << v.idx();
}

/// The largest angle between a quad edge and the nearer of two directions given at its middle
/// [rad].
template <typename Directions>
double worst_edge_angle(const PolyMesh& q, Directions directions) {
  double worst = 0;
  for (auto e : q.edges()) {
    const auto h = q.halfedge_handle(e, 0);
    const Vec3 a = to_eigen(q.point(q.from_vertex_handle(h)));
    const Vec3 b = to_eigen(q.point(q.to_vertex_handle(h)));
    const Vec3 d = (b - a).normalized();
    const auto [u, v] = directions(Vec3(0.5 * (a + b)));
    const double off_u = std::acos(std::min(1.0, std::abs(d.dot(u))));
    const double off_v = std::acos(std::min(1.0, std::abs(d.dot(v))));
    worst = std::max(worst, std::min(off_u, off_v));
  }
  return worst;
}

/// Mean |corner - 90 deg| over the corners of \p q [deg] and the share of corners outside
/// 45-135 deg, measured here from the points.
std::pair<double, double> corner_skew(const PolyMesh& q) {
  double sum = 0;
  int n = 0, skewed = 0;
  for (auto f : q.faces()) {
    std::vector<Vec3> p;
    for (auto v : q.fv_range(f)) p.push_back(to_eigen(q.point(v)));
    for (std::size_t c = 0; c < p.size(); ++c) {
      const Vec3 a = p[(c + 1) % p.size()] - p[c], b = p[(c + p.size() - 1) % p.size()] - p[c];
      const double angle =
          std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI;
      sum += std::abs(angle - 90);
      skewed += std::abs(angle - 90) > 45 ? 1 : 0;
      ++n;
    }
  }
  return {sum / n, static_cast<double>(skewed) / n};
}

// An open cylinder (its target's vertices in rings, so a loft: swept), and the same with the
// vertices between its rims moved up or down by up to 10 micrometres (its rings broken: no
// loft, the lattice, its cross field along the principal directions).
TEST(Quads, CylinderEdgesRunAlongTheAxisAndAroundIt) {
  const auto s = test::open_cylinder(50, 100, 24, 8);
  TriangleMesh jittered = s.target;
  for (std::size_t i = 0; i < jittered.vertices.size(); ++i) {
    Vec3& p = jittered.vertices[i];
    if (p.z() > 1e-9 && p.z() < 100 - 1e-9)
      p.z() += 0.005 * static_cast<double>(i * 7919 % 5) - 0.01;
  }
  for (const bool loft : {true, false}) {
    SCOPED_TRACE(loft ? "in rings" : "jittered");
    const QuadMeshResult r = mesh_of(loft ? s.target : jittered, {.quad_size = 10});
    expect_sound_quads(r.quads);
    EXPECT_EQ(euler(r.quads), 0);
    EXPECT_EQ(boundary_loop_count(r.quads), 2);
    if (loft)
      EXPECT_EQ(r.method.rfind("loft", 0), 0u) << r.method;
    else
      EXPECT_EQ(r.method, "lattice");
    EXPECT_EQ(r.irregular_vertices, 0);
    // Each edge runs along the axis (z) or around it (perpendicular to z and to the radius).
    const double worst = worst_edge_angle(r.quads, [](const Vec3& mid) {
      return std::pair{Vec3(Vec3::UnitZ()),
                       Vec3(Vec3::UnitZ().cross(Vec3(mid.x(), mid.y(), 0)).normalized())};
    });
    EXPECT_LT(worst, 5 * kPi / 180)
        << "worst edge direction off by " << worst * 180 / kPi << " deg";
    // Edges along and around the axis make nearly square corners: the report's skew says so.
    EXPECT_LT(r.mean_corner_deviation, 2 * kPi / 180);
    EXPECT_EQ(r.skewed_corners, 0.0);
    EXPECT_NEAR(r.mean_corner_deviation * 180 / kPi, corner_skew(r.quads).first, 1e-9);
    // The 10 mm size: circumference 314 mm in about 31 quads, 100 mm height in about 10.
    EXPECT_NEAR(static_cast<double>(r.quads.n_faces()), 31.4 * 10, 31.4 * 10 * 0.15);
    // All vertices on the cylinder (the target is its 192-gon: chordal error 0.067 mm); the
    // lattice's rim vertices are means of the remeshed ones (one 0.54 mm inside the jittered
    // cylinder's rim).
    for (auto v : r.quads.vertices()) {
      const Vec3 p = to_eigen(r.quads.point(v));
      EXPECT_NEAR(std::hypot(p.x(), p.y()), 50.0, loft ? 0.07 : 0.6) << p.transpose();
    }
  }
}

// An open patch keeps the corners of its border: the remesher and the lattice kept only the
// points where feature lines meet or end, and a border is one line, so the quads slid round a
// corner and cut it off (a saddle at 250 mm lost 2.6 mm at each, the shared open surface
// inspired_mesh 4.2 mm). A saddle z = (x^2 - y^2) / 200 over [-80, 80]^2 (its corners turn by
// 68 degrees), and the shared open surface from its triangles at 250 mm.
TEST(Quads, AnOpenPatchKeepsTheCornersOfItsBorder) {
  TriangleMesh saddle;
  const int n = 40;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -80 + 160.0 * i / n, y = -80 + 160.0 * j / n;
      saddle.vertices.emplace_back(x, y, (x * x - y * y) / 200);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      saddle.triangles.push_back({a, b, c});
      saddle.triangles.push_back({a, c, d});
    }
  const QuadMeshResult r = mesh_of(saddle, {.quad_size = 12});
  expect_sound_quads(r.quads);
  EXPECT_EQ(euler(r.quads), 1);
  EXPECT_EQ(boundary_loop_count(r.quads), 1);
  for (const Vec3& corner :
       {Vec3(-80, -80, 0), Vec3(80, -80, 0), Vec3(80, 80, 0), Vec3(-80, 80, 0)}) {
    double nearest = std::numeric_limits<double>::infinity();
    for (auto v : r.quads.vertices())
      nearest = std::min(nearest, (to_eigen(r.quads.point(v)) - corner).norm());
    EXPECT_LT(nearest, 1e-9) << corner.transpose();
  }
  if (!test::have_shared_meshes()) GTEST_SKIP() << "shared meshes not available";
  const TriangleMesh open = at_250_mm(test::shared_meshes() / "inspired_mesh.obj");
  const QuadMeshResult q = mesh_of(open);
  expect_sound_quads(q.quads);
  const TargetSurface quads(triangulate(q.quads));
  double farthest = 0;
  for (const Vec3& p : open.vertices) farthest = std::max(farthest, quads.closest(p).distance);
  // Its corners were 4.2 mm from the quads; now every vertex of it is within 0.4 mm.
  EXPECT_LT(farthest, 1.0);
}

TEST(Quads, ClosedShapesKeepTheirTopology) {
  const std::vector<std::pair<test::Shape, double>> shapes = {
      {test::sphere(50, 6), 12.0},
      {test::torus(60, 20, 32, 16), 2 * kPi * 20 / 12},
      {test::closed_cylinder(40, 80, 4), 10.0}};
  for (const auto& [shape, size] : shapes) {
    SCOPED_TRACE(shape.name);
    const QuadMeshResult r = mesh_of(shape.target, {.quad_size = size});
    expect_sound_quads(r.quads);
    EXPECT_EQ(euler(r.quads), shape.name == "torus" ? 0 : 2);
    EXPECT_EQ(boundary_loop_count(r.quads), 0);
    for (auto v : r.quads.vertices())
      EXPECT_LT(std::abs(shape.signed_distance(to_eigen(r.quads.point(v)))), 0.05 * size);
    // The sphere comes from the lattice, the capped cylinder (an extrusion) from its cap's
    // lattice and its wall swept, both with far fewer irregular vertices than the triangle
    // split (about half of all). The torus is not asked for that: a lattice of one spacing
    // cannot fit its inner and outer circles (80 vs 40 mm radius) without dislocations, and
    // today they push it to the safe net (docs/quad-meshing.md).
    if (shape.name == "torus") continue;
    EXPECT_EQ(r.method.rfind(shape.name == "sphere" ? "lattice" : "extrusion", 0), 0u) << r.method;
    EXPECT_LT(r.irregular_vertices, 0.2 * r.quads.n_vertices()) << r.method;
  }
}

// A fold under --quad-feature-angle (60 deg) is a feature line too where both its sides are
// planes reaching three quad sizes across it (a house's eaves, a box's bevels): a 12-sided
// prism (radius 50, facets 25.9 mm wide, folding 30 deg) has no feature but its two border
// rings at 10 mm quads (its facets are narrower than 30 mm: a coarse cylinder, whose quads
// follow the axis), and its 12 folds as well at 6 mm quads (facets wider than 18 mm: panels),
// each then lying along quad edges.
TEST(Quads, ShallowFoldsBetweenWidePlanesAreFeatures) {
  const TriangleMesh prism = test::open_cylinder(50, 100, 12, 4, 1).target;
  const double ring = 12 * 2 * 50 * std::sin(kPi / 12), folds = 12 * 100.0;
  const QuadMeshResult coarse = mesh_of(prism, {.quad_size = 10});
  expect_sound_quads(coarse.quads);
  // (The remeshed border rings come out up to 2 % shorter: their corners are cut.)
  EXPECT_GT(coarse.feature_length, 0.97 * 2 * ring);
  EXPECT_LT(coarse.feature_length, 2 * ring + 1);
  const QuadMeshResult fine = mesh_of(prism, {.quad_size = 6});
  expect_sound_quads(fine.quads);
  EXPECT_GT(fine.feature_length, 0.97 * 2 * ring + folds);
  EXPECT_LT(fine.feature_length, 2 * ring + folds + 1);
  EXPECT_GT(fine.feature_length_on_quads, 0.95 * fine.feature_length);
  // Every quad corner within 0.01 mm of a facet's plane: no quad is bent round a fold.
  for (auto f : fine.quads.faces()) {
    const auto corners = quad_vertices(fine.quads, f);
    Vec3 centre = Vec3::Zero();
    for (int c : corners) centre += to_eigen(fine.quads.point(OpenMesh::VertexHandle(c))) / 4;
    const double facet = std::round(std::atan2(centre.y(), centre.x()) / (kPi / 6) - 0.5) + 0.5;
    const Vec3 n(std::cos(facet * kPi / 6), std::sin(facet * kPi / 6), 0);
    for (int c : corners) {
      const Vec3 p = to_eigen(fine.quads.point(OpenMesh::VertexHandle(c)));
      EXPECT_LT(std::abs(p.dot(n) - 50 * std::cos(kPi / 12)), 0.01) << p.transpose();
    }
  }
}

/// A 200 mm cube with its four vertical edges chamfered by \p c [mm] (an octagonal prism, the
/// chamfers folding 45 degrees from the sides), as triangles.
TriangleMesh chamfered_cube(double c) {
  const double s = 200;
  const std::vector<std::array<double, 2>> ring = {{c, 0},     {s - c, 0}, {s, c},     {s, s - c},
                                                   {s - c, s}, {c, s},     {0, s - c}, {0, c}};
  TriangleMesh m;
  for (double z : {0.0, s})
    for (const auto& [x, y] : ring) m.vertices.push_back({x, y, z});
  m.vertices.push_back({s / 2, s / 2, 0});
  m.vertices.push_back({s / 2, s / 2, s});
  const int n = 8, bottom = 2 * n, top = 2 * n + 1;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, j + n});
    m.triangles.push_back({i, j + n, i + n});
    m.triangles.push_back({bottom, j, i});
    m.triangles.push_back({top, i + n, j + n});
  }
  return m;
}

// A chamfer is a plane too where it is a quad wide and folds close it all round: a 200 mm cube
// with 20 mm chamfers (28.3 mm wide, folding 45 deg from the sides) at 18 mm quads has its 8
// chamfer folds as feature lines beside the rims (3106 mm in all, each face then a plate); with
// 10 mm chamfers (14.1 mm wide, under a quad) only the rims (1553 mm).
TEST(Quads, ChamfersAQuadWideAreFeatures) {
  const double rims20 = 2 * (4 * 160 + 4 * 20 * std::sqrt(2.0));
  const double rims10 = 2 * (4 * 180 + 4 * 10 * std::sqrt(2.0));
  const QuadMeshResult wide = mesh_of(chamfered_cube(20), {.quad_size = 18});
  expect_sound_quads(wide.quads);
  EXPECT_NEAR(wide.feature_length, rims20 + 8 * 200, 0.01 * (rims20 + 8 * 200));
  EXPECT_GT(wide.feature_length_on_quads, 0.95 * wide.feature_length);
  const QuadMeshResult narrow = mesh_of(chamfered_cube(10), {.quad_size = 18});
  expect_sound_quads(narrow.quads);
  // (The remeshed rims come out up to 2 % shorter: their corners are cut.)
  EXPECT_GT(narrow.feature_length, 0.97 * rims10);
  EXPECT_LT(narrow.feature_length, rims10 + 1);
}

// A lattice of one spacing cannot wrap a torus's inner and outer circles (40 against 80 mm
// from the axis here) without dislocations; the global integer step (dislocations.h) pairs
// them off, so the lattice stretches instead: every vertex regular, every edge along a
// parallel or a meridian. Checked on the generated torus and on the shared one. Not yet on
// every torus: the generated one at 8 mm quads and a generated 100/25 mm one keep 6 and 11
// irregular vertices (docs/quad-meshing.md).
TEST(Quads, TorusComesOutAllRegularAlongItsCircles) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const auto generated = test::torus(60, 20, 32, 16);
  const TriangleMesh shared = at_250_mm(test::shared_meshes() / "torus.obj");
  // Name, target, quad size (0: the size rule), radius of the tube's centre line [mm].
  for (const auto& [name, target, size, tube_centre] :
       {std::tuple{"generated, quads of 10.5 mm", generated.target, 2 * kPi * 20 / 12, 60.0},
        std::tuple{"generated, size rule", generated.target, 0.0, 60.0},
        std::tuple{"torus.obj at 250 mm", shared, 0.0, 100.0}}) {
    SCOPED_TRACE(name);
    QuadMeshOptions o;
    if (size > 0) o.quad_size = size;
    const QuadMeshResult r = mesh_of(target, o);
    expect_sound_quads(r.quads);
    EXPECT_EQ(euler(r.quads), 0);
    EXPECT_GT(r.dislocations, 0);  // there were some to remove
    EXPECT_EQ(r.dislocations_left, 0);
    for (auto v : r.quads.vertices()) EXPECT_EQ(r.quads.valence(v), 4u) << "vertex " << v.idx();
    EXPECT_EQ(r.irregular_vertices, 0);
    // The axis: the bounding box's shortest side.
    const BoundingBox box = bounding_box(target);
    const Vec3 extent = box.max - box.min, centre = 0.5 * (box.max + box.min);
    Vec3 axis = Vec3::Zero();
    Eigen::Index shortest = 0;
    extent.minCoeff(&shortest);
    axis[shortest] = 1;
    // Along a parallel (around the axis) or a meridian (round the tube).
    const double worst = worst_edge_angle(r.quads, [&](const Vec3& mid) {
      Vec3 radial = mid - centre;
      radial -= axis * axis.dot(radial);
      const Vec3 around = axis.cross(radial).normalized();
      const Vec3 core = centre + radial.normalized() * tube_centre;  // the tube's centre line
      return std::pair{around, Vec3(around.cross(mid - core).normalized())};
    });
    EXPECT_LT(worst, 10 * kPi / 180) << "worst edge off its circle by " << worst * 180 / kPi;
    // Before the integer step: 21 irregular vertices on torus.obj, 25 on the generated one.
    std::printf("%s: %zu quads (%s, dislocations %d, left %d), worst edge %.1f deg off\n", name,
                r.quads.n_faces(), r.method.c_str(), r.dislocations, r.dislocations_left,
                worst * 180 / kPi);
  }
}

// A scanned surface is noisy: a UV sphere of radius 125 mm (60 x 30 facets of about 13 mm)
// with every vertex moved radially by up to 3 % of the radius at random. Its curvature is the
// noise's, and no lattice on it holds (170 triangles found no partner, the split lattices
// folded); before, the safe net split its triangles into 7667 quads, 2896 of their vertices
// irregular. A copy smoothed by Taubin's steps has a lattice: about 400 quads, few irregular
// vertices, their corners put back onto the noisy target.
TEST(Quads, ANoisyTargetIsMeshedAsItsSmoothedCopy) {
  TriangleMesh noisy;
  const int nu = 60, nv = 30;
  const double radius = 125;
  std::uint32_t state = 1;
  auto random = [&] {  // uniform in [-1, 1], the same on every machine
    state = state * 1664525u + 1013904223u;
    return 2.0 * (state >> 8) / double(1u << 24) - 1.0;
  };
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double th = kPi * j / nv, ph = 2 * kPi * i / nu;
      const double r = radius * (1 + 0.03 * random());
      noisy.vertices.push_back(
          r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  const int top = static_cast<int>(noisy.vertices.size());
  noisy.vertices.push_back(Vec3(0, 0, radius));
  noisy.vertices.push_back(Vec3(0, 0, -radius));
  for (int j = 0; j + 2 < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = j * nu + i, b = j * nu + (i + 1) % nu, c = (j + 1) * nu + (i + 1) % nu,
                d = (j + 1) * nu + i;
      noisy.triangles.push_back({a, d, c});
      noisy.triangles.push_back({a, c, b});
    }
  for (int i = 0; i < nu; ++i) {
    noisy.triangles.push_back({top, i, (i + 1) % nu});
    noisy.triangles.push_back({top + 1, (nv - 2) * nu + (i + 1) % nu, (nv - 2) * nu + i});
  }
  const TargetSurface surface(noisy);
  const QuadMeshResult r = make_quad_mesh(surface, Material{}, {});
  expect_sound_quads(r.quads);
  EXPECT_EQ(euler(r.quads), 2);
  EXPECT_EQ(r.method.rfind("lattice", 0), 0u) << r.method;
  EXPECT_NE(r.method.find("smoothed"), std::string::npos) << r.method;
  EXPECT_GT(r.quads.n_faces(), 200u);
  EXPECT_LT(r.quads.n_faces(), 800u);
  EXPECT_LT(r.irregular_vertices, 0.2 * r.quads.n_vertices()) << r.method;
  for (auto v : r.quads.vertices())
    EXPECT_LT(surface.closest(to_eigen(r.quads.point(v))).distance, 1e-6) << v.idx();
}

TEST(Quads, SizeRuleFollowsMaterialAndCounts) {
  const auto s = test::sphere(50, 6);
  const QuadMeshResult by_count = mesh_of(s.target, {.quads = 300});
  EXPECT_NEAR(by_count.size.size, std::sqrt(4 * kPi * 2500 / 300), 0.05 * by_count.size.size);
  EXPECT_EQ(by_count.size.reason, "--quads");
  // Kerf bound: beams 1.35 mm wide in 3 mm MDF (G / tau_eff = 100) on a 50 mm sphere need
  // strips of 0.5 * 100 * 1.35 * sqrt(9 + 1.8225) / 50 = 4.44 mm.
  EXPECT_NEAR(by_count.size.kerf_size, 0.5 * 100 * 1.35 * std::sqrt(9 + 1.8225) / 50, 0.3);
  EXPECT_THROW(mesh_of(s.target, {.quads = 5}), InvalidInput);
  EXPECT_THROW(mesh_of(s.target, {.quad_size = -1}), InvalidInput);
  EXPECT_THROW(mesh_of(s.target, {.quad_size = 0.01}), InvalidInput);  // 300 million quads
  // At most 20,000 quads, asked by count or by size (the sphere's 31,416 mm^2 in 1.2 mm quads
  // is about 21,800).
  EXPECT_THROW(mesh_of(s.target, {.quads = 20001}), InvalidInput);
  EXPECT_THROW(mesh_of(s.target, {.quad_size = 1.2}), InvalidInput);
}

/// Quad edges of \p q crossing the half-plane through the z axis at angle \p a round it: the
/// quads that go round a torus's tube there (a closed ring of quads crosses it once each).
int quads_round(const PolyMesh& q, double a) {
  const Vec3 out(std::cos(a), std::sin(a), 0), side(-std::sin(a), std::cos(a), 0);
  int n = 0;
  for (auto e : q.edges()) {
    const auto h = q.halfedge_handle(e, 0);
    const Vec3 p = to_eigen(q.point(q.from_vertex_handle(h)));
    const Vec3 r = to_eigen(q.point(q.to_vertex_handle(h)));
    const double dp = p.dot(side), dr = r.dot(side);
    if ((dp < 0) == (dr < 0)) continue;
    if ((p + (r - p) * (dp / (dp - dr))).dot(out) > 0) ++n;
  }
  return n;
}

// Thin tubes: the lattice lays about pi t / s quads round a tube t thick. A ring (R 100 mm)
// whose tube's radius runs from 25 mm down to 5 mm and back (r = 15 + 10 cos u): by the other
// bounds its quads are those of the 400-quad floor, 12.2 mm, which go round the thinnest 5 %
// of it (tubes up to about 12 mm thick: r <= 6 holds 5.3 % of the area) about 3 times, a
// prism. The rule makes them a quarter of its circumference instead.
TEST(Quads, QuadsGoAtLeastFourTimesRoundThinTubes) {
  const double R = 100;
  auto radius = [](double u) { return 15 + 10 * std::cos(2 * kPi * u); };
  const auto f = [&](double u, double v) {
    const double a = 2 * kPi * u, b = 2 * kPi * v, r = radius(u);
    return Vec3((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a),
                r * std::sin(b));
  };
  const TriangleMesh ring = triangulate(test::grid_mesh(480, 64, true, true, f));
  const QuadMeshResult r = mesh_of(ring);
  EXPECT_EQ(r.size.reason, "tubes (4 quads round the thinnest)");
  // Tubes 2 r thick; 5 % of the area lies where r <= 6 mm (5.3 %, computed from the area
  // element r (R + r cos v)), all of it where r <= 6.2 mm.
  EXPECT_GT(r.size.tube_thickness, 2 * 5.5);
  EXPECT_LT(r.size.tube_thickness, 2 * 6.2);
  EXPECT_NEAR(r.size.size, kPi * r.size.tube_thickness / 4, 1e-9);
  // What the other bounds would have taken: the 400-quad floor.
  EXPECT_LT(r.size.size, 0.8 * std::sqrt(r.size.area / 400));
  expect_sound_quads(r.quads);
  EXPECT_EQ(euler(r.quads), 0);
  // Measured on the quads: the fewest round any of 72 sections of the tube. With the rule, 4
  // at least, even round the thinnest (r 5 mm, 31 mm round); asked for the 400-quad floor's
  // 12.2 mm instead, the quads keep it and some section has 3 round it.
  QuadMeshOptions o;
  o.quad_size = std::sqrt(r.size.area / 400);
  const QuadMeshResult asked = mesh_of(ring, o);
  EXPECT_EQ(asked.size.reason, "--quad-size");
  auto fewest_round = [](const PolyMesh& q) {
    int fewest = 1 << 30;
    for (int k = 0; k < 72; ++k)
      fewest = std::min(fewest, quads_round(q, 2 * kPi * (k + 0.5) / 72));
    return fewest;
  };
  EXPECT_GE(fewest_round(r.quads), 4);
  EXPECT_LE(fewest_round(asked.quads), 3);
  // A plain torus at the floor, tubes 40 mm thick, is left as the other bounds size it.
  EXPECT_NE(mesh_of(test::torus(60, 20, 32, 16).target).size.reason,
            "tubes (4 quads round the thinnest)");
}

// A feature angle so low that most of the target's edges are sharp: Spot from its triangles at
// 250 mm with 20 deg ran for over 10 minutes in this stage (5.0 m of sharp edges for quads of
// 16.6 mm on 0.12 m^2). At a quad size the user gives it is refused at once, naming both
// cures (the quad size at which those edges are a quarter of the quads': about 12 mm); where
// the size rule chose the size, it is made finer instead (since 2026-12-03; the icosahedron
// in Cli.ALowPolyShapeGetsQuadsFineEnoughForItsEdges); 30 deg (1.5 m) still runs.
TEST(Quads, AFeatureAngleThatMarksMostEdgesSharpIsRefused) {
  const TriangleMesh spot = at_250_mm(test::real_mesh("spot_triangulated.obj"));
  try {
    mesh_of(spot, {.quad_size = 16.6, .feature_angle = 20 * kPi / 180});
    ADD_FAILURE() << "20 deg was not refused";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("raise --quad-feature-angle"), std::string::npos) << what;
    const auto at = what.find("--quad-size ");
    ASSERT_NE(at, std::string::npos) << what;
    const double size = std::stod(what.substr(at + 12));
    EXPECT_GT(size, 10.0) << what;
    EXPECT_LT(size, 14.0) << what;
  }
  EXPECT_GT(mesh_of(spot, {.feature_angle = 30 * kPi / 180}).quads.n_faces(), 300u);
}

// The size rule samples a large mesh's curvatures at every stride-th vertex (a 1M-triangle
// sphere spent 11.7 s on all of them): those are exactly the values computed at every vertex,
// the others are left 0, and on a sphere both curvatures are 1/r.
TEST(Quads, CurvaturesAtEveryStrideThVertexAreThoseAtAll) {
  const auto s = test::sphere(50, 6);
  const quads::Surface surface = quads::make_surface(s.target);
  const quads::Curvatures all = quads::principal_curvatures(surface, 10.0);
  const quads::Curvatures some = quads::principal_curvatures(surface, 10.0, 3);
  ASSERT_EQ(all.larger.size(), some.larger.size());
  ASSERT_GT(all.larger.size(), 300u);
  for (std::size_t i = 0; i < all.larger.size(); ++i) {
    if (i % 3 == 0) {
      EXPECT_EQ(some.larger[i], all.larger[i]) << i;
      EXPECT_EQ(some.smaller[i], all.smaller[i]) << i;
      EXPECT_EQ(some.weak_direction[i], all.weak_direction[i]) << i;
      EXPECT_NEAR(all.larger[i], 1.0 / 50, 0.1 / 50) << i;
      EXPECT_NEAR(all.smaller[i], 1.0 / 50, 0.1 / 50) << i;
    } else {
      EXPECT_EQ(some.larger[i], 0.0) << i;
      EXPECT_EQ(some.smaller[i], 0.0) << i;
    }
  }
}

// A count asked for is kept: where the split lattice and the pure one are both sound and only
// one comes within 10 % of the count, that one is taken (the bunny asked for 400 quads got the
// split lattice's 542, for its 100 irregular vertices against 105; fertility's 438 are within).
TEST(Quads, TheCountAskedForIsKept) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  for (const std::string name : {"bunny_closed_odedstein.obj", "fertility.off"}) {
    SCOPED_TRACE(name);
    const TriangleMesh t = at_250_mm(test::shared_meshes() / name);
    const QuadMeshResult r = mesh_of(t, {.quads = 400});
    expect_sound_quads(r.quads);
    EXPECT_NEAR(static_cast<double>(r.quads.n_faces()), 400.0, 40.0) << r.method;
  }
}

// Where the split lattice's corners lie far off the target (its new points at plain midpoints
// and centres) and the pure one's do not, the pure one is taken: the strips stage puts every
// corner on the target along its normal, and corners far off come out of it with their quads
// crushed (stanford-bunny: one-quad facets with 2 deg corners, 15 parts left unresolved and 9
// borders without a joint, against 0 and 1). Before, the split lattice won on its fewer
// irregular vertices: its corners 2.75 mm off on average for quads of 17.8 mm (bunny), 2.69 for
// 16.1 (bob); the pure one's 1.52 and 1.00. Measured here, by this test's own distances.
TEST(Quads, TheLatticeWhoseCornersLieCloserToTheTargetIsTaken) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  for (const std::string name : {"stanford-bunny.obj", "bob_tri.obj"}) {
    SCOPED_TRACE(name);
    const TriangleMesh t = at_250_mm(test::shared_meshes() / name);
    const QuadMeshResult r = mesh_of(t);
    const TargetSurface target(t);
    double sum = 0;
    for (auto v : r.quads.vertices()) sum += target.closest(to_eigen(r.quads.point(v))).distance;
    const double mean = sum / static_cast<double>(r.quads.n_vertices());
    EXPECT_LT(mean, 0.1 * r.size.size) << r.method;
  }
}

/// The share of \p q's quads with an edge shorter than 0.3 of \p size.
double share_with_short_edges(const PolyMesh& q, double size) {
  int with = 0;
  for (auto f : q.faces()) {
    const auto v = quad_vertices(q, f);
    for (int c = 0; c < 4; ++c)
      if ((to_eigen(q.point(OpenMesh::VertexHandle(v[c]))) -
           to_eigen(q.point(OpenMesh::VertexHandle(v[(c + 1) % 4]))))
              .norm() < 0.3 * size) {
        ++with;
        break;
      }
  }
  return static_cast<double>(with) / static_cast<double>(std::max<std::size_t>(q.n_faces(), 1));
}

// Demosthenes' bust at 250 mm: three of its short creases meet round one triangle, whose edges
// are then all feature edges; no row of the lattice may leave it across one, so the lattice at
// the quad size failed on that one triangle and the lattice with every face split was taken:
// 848 quads for about 400, 41 % of them with an edge under 0.3 of the quad size. Where the
// feature angle is the default, it is now raised 5 deg at a time until the lattice pairs (65 deg
// here); an angle the user chose is kept. Measured here: the raised lattice pairs, is sound and
// of the target's topology, near the count, with fewer short-edged quads than the split one.
TEST(Quads, ATriangleWalledInByCreasesRaisesTheFeatureAngleNotTheQuadCount) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const TriangleMesh t = at_250_mm(test::shared_meshes() / "demosthenes-low-res.obj");
  QuadMeshOptions o;  // the feature angle the CLI's --quad-feature-angle gives by default
  o.feature_angle = 60 * kPi / 180;
  const QuadMeshResult raised = mesh_of(t, o);
  o.raise_feature_angle = false;
  const QuadMeshResult kept = mesh_of(t, o);
  EXPECT_GT(kept.unpaired_triangles, 0);
  EXPECT_NEAR(kept.feature_angle, 60 * kPi / 180, 1e-9);
  EXPECT_EQ(kept.feature_angle_asked, 0);
  expect_sound_quads(raised.quads);
  EXPECT_EQ(raised.unpaired_triangles, 0);
  EXPECT_NEAR(raised.feature_angle, 65 * kPi / 180, 1e-9);
  EXPECT_NEAR(raised.feature_angle_asked, 60 * kPi / 180, 1e-9);
  std::set<std::pair<int, int>> edges;
  for (const auto& f : t.triangles)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(f[k], f[(k + 1) % 3]));
  EXPECT_EQ(euler(raised.quads), static_cast<int>(t.vertices.size()) -
                                     static_cast<int>(edges.size()) +
                                     static_cast<int>(t.triangles.size()));
  EXPECT_LT(raised.quads.n_faces(), 0.8 * static_cast<double>(kept.quads.n_faces()));
  EXPECT_LT(share_with_short_edges(raised.quads, raised.size.size),
            0.75 * share_with_short_edges(kept.quads, kept.size.size));
}

TEST(Quads, Deterministic) {
  const auto s = test::sphere(50, 6);
  const QuadMeshResult a = mesh_of(s.target, {.quad_size = 12});
  const QuadMeshResult b = mesh_of(s.target, {.quad_size = 12});
  ASSERT_EQ(a.quads.n_vertices(), b.quads.n_vertices());
  for (auto v : a.quads.vertices())
    EXPECT_EQ(to_eigen(a.quads.point(v)), to_eigen(b.quads.point(v)));
}

/// The largest distance from a vertex of \p target to the quads (each cut along a diagonal):
/// a quad mesh whose corners lie on the target can still bridge a thin part.
double target_to_quads(const TriangleMesh& target, const PolyMesh& q) {
  TriangleMesh cut;
  for (auto v : q.vertices()) cut.vertices.push_back(to_eigen(q.point(v)));
  for (auto f : q.faces()) {
    const auto v = quad_vertices(q, f);
    cut.triangles.push_back({v[0], v[1], v[3]});
    cut.triangles.push_back({v[1], v[2], v[3]});
  }
  const TargetSurface quads(cut);
  double worst = 0;
  for (const Vec3& p : target.vertices) worst = std::max(worst, quads.closest(p).distance);
  return worst;
}

TEST(Quads, RealMeshesBecomeSoundQuadMeshesOfTheSameTopology) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  // Spot (ears, horns), a decimated head and a scan with holes and noisy creases (the last
  // two ended in slivers or failed before the short feature lines were dropped).
  for (const std::string name : {"fandisk.obj", "spot_triangulated.obj", "bob_tri.obj",
                                 "decimated-max.obj", "stanford-bunny.obj"}) {
    SCOPED_TRACE(name);
    const TriangleMesh t = at_250_mm(test::shared_meshes() / name);
    const QuadMeshResult r = mesh_of(t);
    expect_sound_quads(r.quads);
    PolyMesh target;
    for (const auto& p : t.vertices) target.add_vertex(to_openmesh(p));
    for (const auto& f : t.triangles)
      target.add_face(OpenMesh::VertexHandle(f[0]), OpenMesh::VertexHandle(f[1]),
                      OpenMesh::VertexHandle(f[2]));
    int unused = 0;  // the scan has vertices no triangle uses
    for (auto v : target.vertices()) unused += target.is_isolated(v) ? 1 : 0;
    EXPECT_EQ(euler(r.quads), euler(target) - unused);
    EXPECT_EQ(boundary_loop_count(r.quads), boundary_loop_count(target));
    EXPECT_LT(r.max_distance, 0.03 * bounding_box(t).diagonal());
    // Nothing bridged: every point of the target within one quad size of the quads (the
    // diagonal the other way than the stage's own check).
    EXPECT_LT(target_to_quads(t, r.quads), 1.05 * r.size.size);
    // Made from a lattice (not the triangle safe net, where half the vertices are irregular),
    // so few irregular vertices: 15-25 % of them (a split lattice has three regular vertices
    // for each of its own, so it counted 14-18 %, at twice the quads).
    EXPECT_NE(r.method.find("lattice"), std::string::npos) << r.method;
    EXPECT_LT(r.irregular_vertices, 0.28 * static_cast<double>(r.quads.n_vertices()));
  }
}

// A lattice with one bad quad is untangled where it is, not given up: the bunny asked for 1500
// quads had one quad folded after its new points went onto the surface, and the mesh used
// instead was the one whose new points were left off it, up to 5.57 mm from the target (at
// 5000 quads a finer lattice: 10,792 quads). Measured here: every quad sound, about the count
// asked for, every corner on the target.
TEST(Quads, OneBadQuadIsUntangledNotAFinerOrLooserMesh) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const TriangleMesh t = at_250_mm(test::shared_meshes() / "bunny_closed_odedstein.obj");
  QuadMeshOptions o;
  o.quads = 1500;
  const QuadMeshResult r = mesh_of(t, o);
  expect_sound_quads(r.quads);
  EXPECT_EQ(r.method.find("not projected"), std::string::npos) << r.method;
  EXPECT_GT(r.quads.n_faces(), 1200u);
  EXPECT_LT(r.quads.n_faces(), 2000u);
  const TargetSurface surface(t);
  double off = 0;
  for (auto v : r.quads.vertices())
    off = std::max(off, surface.closest(to_eigen(r.quads.point(v))).distance);
  EXPECT_LT(off, 0.05 * r.size.size) << off << " mm, quads of " << r.size.size << " mm";
}

// Sharp features on quad edges, measured here: fandisk's edges folding more than 60 degrees
// (3.2 m at 250 mm), each counted where a quad edge running within 15 degrees of it, with both
// ends on a sharp edge (within 1 um), passes within a tenth of the quad size of its middle (a
// chord of a curved feature line sags by up to 5 % of the quad size). 91.0 % here (92.7 % in a
// CLI run at --size 250) since the corners near a sharp edge are moved onto it (CLI: 24.5 %
// before; the lattice's corners lay 0.1-4 mm off the target's edges, so quads folded across the
// edge beside them; a quad edge merely within a tenth of the quad size, wherever its ends:
// 86.8 % here, 91.6 % in the CLI run). What is left: places where no row of quad edges follows
// the edge (a feature line ending, or a row leaving it towards a corner 6-8 mm off).
// The stage's own measure (middles within 2 % of the quad size) is reported, not trusted here.
TEST(Quads, FandisksSharpEdgesLieOnQuadEdges) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const TriangleMesh t = at_250_mm(test::shared_meshes() / "fandisk.obj");
  const QuadMeshResult r = mesh_of(t);
  expect_sound_quads(r.quads);
  std::map<std::pair<int, int>, std::vector<int>> faces_of;
  for (int f = 0; f < static_cast<int>(t.triangles.size()); ++f)
    for (int k = 0; k < 3; ++k)
      faces_of[std::minmax(t.triangles[f][k], t.triangles[f][(k + 1) % 3])].push_back(f);
  auto normal = [&](int f) {
    const auto& tr = t.triangles[f];
    return Vec3(
               (t.vertices[tr[1]] - t.vertices[tr[0]]).cross(t.vertices[tr[2]] - t.vertices[tr[0]]))
        .normalized();
  };
  std::vector<std::pair<Vec3, Vec3>> sharp;
  for (const auto& [e, fs] : faces_of)
    if (fs.size() == 2 &&
        std::acos(std::clamp(normal(fs[0]).dot(normal(fs[1])), -1.0, 1.0)) >= 60 * kPi / 180)
      sharp.push_back({t.vertices[e.first], t.vertices[e.second]});
  auto off_sharp = [&](const Vec3& p) {
    double d = 1e300;
    for (const auto& [a, b] : sharp) {
      const Vec3 ab = b - a;
      d = std::min(d,
                   (a + std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) * ab - p).norm());
    }
    return d;
  };
  std::vector<char> on_sharp(r.quads.n_vertices());
  for (auto v : r.quads.vertices())
    on_sharp[v.idx()] = off_sharp(to_eigen(r.quads.point(v))) < 1e-3;
  double total = 0, on = 0;
  for (const auto& [a, b] : sharp) {
    const Vec3 mid = 0.5 * (a + b), dir = (b - a).normalized();
    total += (b - a).norm();
    for (auto qe : r.quads.edges()) {
      const auto h = r.quads.halfedge_handle(qe, 0);
      const auto from = r.quads.from_vertex_handle(h), to = r.quads.to_vertex_handle(h);
      if (!on_sharp[from.idx()] || !on_sharp[to.idx()]) continue;
      const Vec3 p = to_eigen(r.quads.point(from)), q = to_eigen(r.quads.point(to));
      const Vec3 d = q - p;
      const double s = std::clamp((mid - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
      if ((p + s * d - mid).norm() < 0.1 * r.size.size &&
          std::abs(d.normalized().dot(dir)) > std::cos(15 * kPi / 180)) {
        on += (b - a).norm();
        break;
      }
    }
  }
  EXPECT_GT(total, 3000.0);
  EXPECT_GT(on / total, 0.9) << on << " of " << total << " mm";
}

// Polished quads: on Spot's triangle mesh (bundled) every corner lies between 20 and 160
// degrees and no edge is shorter than 8 % of the median edge, measured here. Before the
// doublets were removed and the quads polished: corners from 3.5 to 177 degrees (94 under 30,
// 96 over 150 of 4168) and edges down to 0.4 mm of a median 11 mm. (The split lattice reached
// 30-150 degrees and a tenth of the median; the pure one, with half as many quads, has a few
// vertices of valence 6 to 8 and rows of split quads meeting at the horns: corners of
// 24.9-152.5 degrees, shortest edge 1.47 mm of a median 16.1 mm.)
TEST(Quads, SpotsQuadsHaveNoSliverCorners) {
  const TriangleMesh t = at_250_mm(test::real_mesh("spot_triangulated.obj"));
  const QuadMeshResult r = mesh_of(t);
  expect_sound_quads(r.quads);
  std::vector<double> edges;
  double lo = 180, hi = 0, off_square = 0;
  int skewed_count = 0;
  for (auto f : r.quads.faces()) {
    const auto v = quad_vertices(r.quads, f);
    for (int c = 0; c < 4; ++c) {
      const Vec3 p = to_eigen(r.quads.point(OpenMesh::VertexHandle(v[c])));
      const Vec3 a = to_eigen(r.quads.point(OpenMesh::VertexHandle(v[(c + 1) % 4]))) - p;
      const Vec3 b = to_eigen(r.quads.point(OpenMesh::VertexHandle(v[(c + 3) % 4]))) - p;
      const double angle =
          std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI;
      lo = std::min(lo, angle), hi = std::max(hi, angle);
      off_square += std::abs(angle - 90);
      skewed_count += std::abs(angle - 90) > 45 ? 1 : 0;
      edges.push_back(a.norm());
    }
  }
  std::sort(edges.begin(), edges.end());
  EXPECT_GT(lo, 20.0);
  EXPECT_LT(hi, 160.0);
  EXPECT_GT(edges.front(), 0.08 * edges[edges.size() / 2]);
  // The stage's own measures of skew (the report's quads.corner_deviation_deg and
  // quads.corners_outside_45_135) are those measured here.
  EXPECT_NEAR(r.min_corner_angle * 180 / M_PI, lo, 1e-9);
  EXPECT_NEAR(r.max_corner_angle * 180 / M_PI, hi, 1e-9);
  const double deviation = off_square / static_cast<double>(edges.size());
  const double skewed = skewed_count / static_cast<double>(edges.size());
  EXPECT_NEAR(r.mean_corner_deviation * 180 / M_PI, deviation, 1e-9);
  EXPECT_NEAR(r.skewed_corners, skewed, 1e-12);
  EXPECT_GT(deviation, 5.0);  // irregular vertices leave corners off square
  EXPECT_LT(skewed, 0.15);
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

// From the command line: a triangle mesh alone gives a quad mesh that reads back as all quads
// of the target's topology, in the target file's own frame and units: fed back with --quad,
// the same target and the same --size, it is taken (it was refused as 66 diagonals away when
// written in scaled millimetres).
TEST(Quads, TriangleTargetAloneRunsAndWritesItsQuadMesh) {
  const auto dir = test::fresh_dir();
  const auto out = dir / "out";
  const std::string cmd = std::string(KERFAB_CLI) + " run --quiet --target " +
                          test::real_mesh("spot_triangulated.obj").string() +
                          " --size 250 --quads 600 --stop-after quads --out " + out.string() +
                          " 2>" + (dir / "err").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const PolyMesh q = read_mesh(out / "model" / "quads.obj");
  EXPECT_TRUE(is_all_quads(q));
  EXPECT_EQ(static_cast<int>(q.n_vertices()) - static_cast<int>(q.n_edges()) +
                static_cast<int>(q.n_faces()),
            2);
  EXPECT_TRUE(std::filesystem::exists(out / "report.json"));
  // The report names no quad file for quads kerfab made (it named the target's).
  const auto made = test::read_report(out);
  EXPECT_TRUE(made["input"]["quad"].is_null()) << made["input"]["quad"];
  EXPECT_FALSE(made["input"]["quads_from_target"].get<bool>());
  const auto again = dir / "again";
  const std::string back = std::string(KERFAB_CLI) + " run --quiet --target " +
                           test::real_mesh("spot_triangulated.obj").string() + " --quad " +
                           (out / "model" / "quads.obj").string() +
                           " --size 250 --no-coarsen --stop-after prepare --out " + again.string() +
                           " 2>" + (dir / "err").string();
  ASSERT_EQ(std::system(back.c_str()), 0) << test::slurp(dir / "err");
  const auto report = test::read_report(again);
  EXPECT_EQ(report["input"]["quads"].get<int>(), static_cast<int>(q.n_faces()));
  EXPECT_EQ(report["input"]["quad"], (out / "model" / "quads.obj").string());
  // The same quads as made: as far from the target as the quads stage said.
  EXPECT_NEAR(report["input"]["quad_max_distance_mm"].get<double>(),
              test::read_report(out)["quads"]["max_distance_mm"].get<double>(), 1e-3);
}

// Quads asked narrower than the strips the material can bend get a warning naming the size
// that would do (Spot at 250 mm in 3 mm MDF: kerf bound 12.1 mm; 1500 quads are 9.0 mm);
// the size rule's own quads and coarser ones get none.
// An extrusion (a flat outline swept along an axis) is told apart from every other shape by
// its faces alone: each faces along the axis (a cap, at the lowest or highest height) or
// across it (the wall). A drum, a pot open at the top and a bench of C-shaped section
// are (and a square prism, three ways); a drum tapered by half a degree, a sphere and a tube
// open at both ends are not.
TEST(Quads, ExtrusionsAreFoundAlongTheirAxis) {
  const auto axis_along_z = [](const quads::Extrusion& e) {
    return std::abs(e.axis.dot(Vec3::UnitZ())) > 1 - 1e-12;
  };
  {
    const auto e = quads::find_extrusion(test::drum(100, 120, 64));
    ASSERT_TRUE(e);
    EXPECT_TRUE(axis_along_z(*e));
    EXPECT_NEAR(e->top - e->bottom, 120, 1e-9);
    EXPECT_TRUE(e->top_cap && e->bottom_cap);
    EXPECT_EQ(e->cap.triangles.size(), 64u);  // one fan
    // Its wall: 64 rectangles of 2 r sin(pi / 64) x 120 mm.
    EXPECT_NEAR(e->wall_area, 64 * 2 * 100 * std::sin(kPi / 64) * 120, 1e-6);
  }
  {
    const auto e = quads::find_extrusion(test::drum(100, 120, 64, true, false));
    ASSERT_TRUE(e);
    EXPECT_TRUE(e->bottom_cap);
    EXPECT_FALSE(e->top_cap);
    EXPECT_FALSE(e->cap_on_top);
  }
  {
    const auto e = quads::find_extrusion(test::c_bench(60, 100, 40, 80));
    ASSERT_TRUE(e);
    EXPECT_TRUE(axis_along_z(*e));
    double area = 0;
    for (const auto& t : e->cap.triangles)
      area += 0.5 * (e->cap.vertices[t[1]] - e->cap.vertices[t[0]])
                        .cross(e->cap.vertices[t[2]] - e->cap.vertices[t[0]])
                        .norm();
    // The ring sector, less the 80 segments' chords (under 0.1 %).
    const double sector = 0.5 * (100 * 100 - 60 * 60) * (2 * kPi - 0.6);
    EXPECT_NEAR(area, sector, 1e-3 * sector);
  }
  {
    // A square prism 300 long of side 141 mm (a drum of 4 sides): an extrusion three ways;
    // the largest cap wins, a side of 141 x 300 mm (the fans at its ends: 2 x 10^4 mm^2).
    const auto e = quads::find_extrusion(test::drum(100, 300, 4));
    ASSERT_TRUE(e);
    EXPECT_NEAR(e->axis.z(), 0, 1e-12);
    EXPECT_NEAR(e->top - e->bottom, 100 * std::sqrt(2.0), 1e-9);
  }
  // Not extrusions but lofts: a drum tapered by half a degree (its top outline the bottom's
  // scaled by 1 - 120 tan(0.5 deg) / 100), a tube open at both ends (scale 1, its rim fanned
  // for the sweep).
  {
    const auto e = quads::find_extrusion(test::drum(100, 120, 64, true, true, 0.5));
    ASSERT_TRUE(e);
    EXPECT_TRUE(axis_along_z(*e));
    ASSERT_EQ(e->profile.size(), 2u);
    EXPECT_FALSE(e->cap_on_top);  // the larger cap
    EXPECT_NEAR(e->profile[0][1], 1, 1e-12);
    EXPECT_NEAR(e->profile[1][1], 1 - 1.2 * std::tan(0.5 * kPi / 180), 1e-9);
    EXPECT_NEAR(e->centre.head<2>().norm(), 0, 1e-9);
  }
  {
    const auto e = quads::find_extrusion(test::drum(100, 120, 64, false, false));
    ASSERT_TRUE(e);
    EXPECT_TRUE(axis_along_z(*e));
    EXPECT_TRUE(e->cap_made);
    ASSERT_EQ(e->profile.size(), 2u);
    EXPECT_NEAR(e->profile[1][1], 1, 1e-9);
  }
  EXPECT_FALSE(quads::find_extrusion(test::sphere(80, 6).target));
  // A drum with a second, thinner one on top: a loft whose profile has a flat step (two rings
  // at one height, joined by the flat ring between them).
  {
    const auto e = quads::find_extrusion(
        test::lathe({{100, 0}, {100, 60}, {50, 60}, {50, 120}}, 64, true, true));
    ASSERT_TRUE(e);
    ASSERT_EQ(e->profile.size(), 4u);
    const std::vector<std::array<double, 2>> profile = {{0, 1}, {60, 1}, {60, 0.5}, {120, 0.5}};
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(e->profile[k][0] - e->bottom, profile[k][0], 1e-9) << k;
      EXPECT_NEAR(e->profile[k][1], profile[k][1], 1e-9) << k;
    }
  }
  // A cone that comes to a point, a sphere, and a torus (its rings in a loop) are not.
  EXPECT_FALSE(quads::find_extrusion(test::lathe({{100, 0}, {1e-3, 120}}, 64, true, false)));
  EXPECT_FALSE(quads::find_extrusion(test::torus(100, 30, 48, 16).target));
}

// A loft (a vase, a planter, a lampshade: one outline scaled along an axis) is swept like an
// extrusion, each border vertex of its cap (or, open at both ends, of quads on its rim's
// outline) scaled about the axis row by row: the rows follow the profile (a run of it between
// two corners in rows of their own), every quad corner lies on the target (on the trapezoid
// between two scaled copies of an edge of the outline), and no vertex of the wall is
// irregular. A frustum from its triangles at 250 mm in 3 mm MDF came out of the lattice as 44
// parts (Hausdorff 1.52 % of the diagonal, its cap cut in strips), swept as 13 (0.56 %).
TEST(Quads, ALoftsWallIsSweptInRowsAlongItsProfile) {
  // A vase: radius 60 + 25 sin(pi z / 200) over 200 mm in 21 rings of 48 segments, a bottom.
  const std::vector<std::array<double, 2>> vase = test::vase_profile();
  // A lampshade open at both ends, radius 100 to 60 over 150 mm, in 2 rings of 96.
  const std::vector<std::array<double, 2>> shade = {{100, 0}, {60, 150}};
  struct Case {
    std::string name;
    TriangleMesh mesh;
    bool cap;
  };
  for (const Case& c : {Case{"vase", test::lathe(vase, 48, true, false), true},
                        Case{"lampshade", test::lathe(shade, 96, false, false), false}}) {
    SCOPED_TRACE(c.name);
    const TargetSurface target(c.mesh);
    QuadMeshOptions o;
    o.quad_size = 20;
    const QuadMeshResult r = make_quad_mesh(target, Material{}, o);
    ASSERT_EQ(r.method.rfind("loft", 0), 0u) << r.method;
    EXPECT_LT(r.max_distance, 1e-6);
    const PolyMesh& q = r.quads;
    // The wall: quads with a corner off the bottom's plane; the columns round it, the rows.
    int wall = 0, bottom_faces = 0;
    for (auto f : q.faces()) {
      bool off = false;
      for (auto v : q.fv_range(f)) off = off || q.point(v)[2] > 1e-9;
      off ? ++wall : ++bottom_faces;
    }
    EXPECT_EQ(bottom_faces > 0, c.cap);
    // Every vertex off the bottom (on the wall, or its rim) regular: four quads, three on a rim.
    for (auto v : q.vertices()) {
      if (q.point(v)[2] <= 1e-9) continue;
      EXPECT_EQ(static_cast<int>(q.valence(v)), q.is_boundary(v) ? 3 : 4)
          << "at z = " << q.point(v)[2];
    }
    // Rows: the profile's length over the quad size (the vase's 207.5 mm: 10; the shade's
    // hypot(150, 40) = 155.2 mm: 8).
    std::set<long long> heights;
    for (auto v : q.vertices())
      if (q.point(v)[2] > 1e-9) heights.insert(std::llround(q.point(v)[2] * 1e6));
    const int rows_up = static_cast<int>(heights.size());
    EXPECT_EQ(rows_up, c.name == "vase" ? 10 : 8);
    EXPECT_EQ(wall % rows_up, 0);
  }
}

namespace {
/// A loft that closes to a point (the cases of ALoftThatClosesToAPointIsSweptWithDomes).
struct DomedLoft {
  std::string name;
  TriangleMesh mesh;
  int euler, borders;
  double bottom_pole, top_pole;  // the poles' heights (NaN: none there)
};

/// A capsule, a bowl, a UV sphere and a sphere as OpenSCAD writes one, from their triangles.
std::vector<DomedLoft> domed_lofts() {
  const double none = std::numeric_limits<double>::quiet_NaN();
  const int n = 48;
  // A capsule: a tube of radius 50 from z = 0 to 150 with half spheres on it, 12 rings a side.
  std::vector<std::array<double, 2>> capsule;
  for (int k = 1; k <= 12; ++k)
    capsule.push_back({50 * std::sin(kPi / 2 * k / 12), -50 * std::cos(kPi / 2 * k / 12)});
  for (int k = 1; k < 10; ++k) capsule.push_back({50, 15.0 * k});
  for (int k = 0; k < 12; ++k)
    capsule.push_back({50 * std::cos(kPi / 2 * k / 12), 150 + 50 * std::sin(kPi / 2 * k / 12)});
  // A bowl: a half sphere of radius 100 open at z = 0, its pole at z = -100; 16 rings.
  std::vector<std::array<double, 2>> bowl;
  for (int k = 1; k <= 16; ++k)
    bowl.push_back({100 * std::sin(kPi / 2 * k / 16), -100 * std::cos(kPi / 2 * k / 16)});
  // A UV sphere of radius 100: 23 rings between its poles.
  std::vector<std::array<double, 2>> sphere;
  for (int k = 1; k < 24; ++k)
    sphere.push_back({100 * std::sin(kPi * k / 24), -100 * std::cos(kPi * k / 24)});
  // A sphere as OpenSCAD writes one: 24 rings at (k + 1/2) 180 / 24 degrees from the bottom,
  // closed by flat 48-gons 7.5 degrees across, each fanned from one of its corners.
  std::vector<std::array<double, 2>> scad;
  for (int k = 0; k < 24; ++k)
    scad.push_back({100 * std::sin(kPi * (k + 0.5) / 24), -100 * std::cos(kPi * (k + 0.5) / 24)});
  TriangleMesh scad_sphere = test::lathe(scad, n, false, false);
  for (int i = 1; i + 1 < n; ++i) {
    scad_sphere.triangles.push_back({0, i + 1, i});
    scad_sphere.triangles.push_back({23 * n, 23 * n + i, 23 * n + i + 1});
  }
  const double scad_pole = 100 * std::cos(kPi * 0.5 / 24);
  // lathe() fans an end round its centre at the end ring's height: moved to the pole.
  const auto poles = [&](TriangleMesh m, std::size_t rings, double bottom, double top) {
    if (!std::isnan(bottom)) m.vertices[rings * n].z() = bottom;
    if (!std::isnan(top)) m.vertices[rings * n + (std::isnan(bottom) ? 0 : 1)].z() = top;
    return m;
  };
  return {
      DomedLoft{"capsule", poles(test::lathe(capsule, n, true, true), capsule.size(), -50, 200), 2,
                0, -50, 200},
      DomedLoft{"bowl", poles(test::lathe(bowl, n, true, false), bowl.size(), -100, none), 1, 1,
                -100, none},
      DomedLoft{"UV sphere", poles(test::lathe(sphere, n, true, true), sphere.size(), -100, 100), 2,
                0, -100, 100},
      DomedLoft{"OpenSCAD sphere", scad_sphere, 2, 0, -scad_pole, scad_pole}};
}
}  // namespace

// A loft that closes to a point (a pole vertex on the axis fanned to the ring round it: a
// capsule, a bowl, a UV sphere; or a small flat polygon, as OpenSCAD closes a sphere) is
// swept too: its wall in rings up to the ring of kDomeStop
// times the widest scale, the dome beyond it a cap meshed flat and lifted onto it. Every quad
// corner lies on the target, the rows are rings (each of the wall's edges along its rims at
// one height, each along the axis at one angle), and the domes reach their poles. From their
// triangles at 300 mm in 3 mm MDF, a capsule of radius 50 and length 150 came out of the
// lattice as 82 parts (47 critical regions, Hausdorff 1.97 % of the diagonal), swept as 51
// (21, 0.66 %); a bowl 39 -> 36 parts (0.46 -> 0.22 %).
TEST(Quads, ALoftThatClosesToAPointIsSweptWithDomes) {
  for (const DomedLoft& c : domed_lofts()) {
    SCOPED_TRACE(c.name);
    const std::optional<quads::Extrusion> e = quads::find_extrusion(c.mesh);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->cap_dome.empty() + e->other_dome.empty(), std::isnan(c.top_pole) ? 1 : 0);
    for (const auto* dome : {&e->cap_dome, &e->other_dome})
      if (!dome->empty()) {
        EXPECT_EQ(dome->back()[1], 0);                      // to the pole
        const double pole = dome->back()[0] * e->axis.z();  // heights along the axis, +-z
        EXPECT_TRUE(std::abs(pole - c.bottom_pole) < 1e-9 || std::abs(pole - c.top_pole) < 1e-9)
            << pole;
      }
    // Swept whatever the lattice would give (DomesSweptWhereTheyBeatTheLattice: which is kept).
    const QuadMeshResult r = mesh_of(
        c.mesh, {.quad_size = 20, .domed_sweep_share = std::numeric_limits<double>::infinity()});
    ASSERT_EQ(r.method.rfind("loft", 0), 0u) << r.method;
    expect_sound_quads(r.quads);
    EXPECT_EQ(euler(r.quads), c.euler);
    EXPECT_EQ(boundary_loop_count(r.quads), c.borders);
    EXPECT_LT(r.max_distance, 1e-6);
    const PolyMesh& q = r.quads;
    const auto point = [&](int v) { return to_eigen(q.point(q.vertex_handle(v))); };
    int rims = 0, rulings = 0;
    for (const auto& hint : r.bending) {
      const Vec3 a = point(hint.v0), b = point(hint.v1);
      if (hint.bendable) {
        ++rims;
        EXPECT_NEAR(a.z(), b.z(), 1e-6);
      } else {
        ++rulings;
        EXPECT_NEAR(a.x() * b.y() - a.y() * b.x(), 0, 1e-6 * a.norm() * b.norm());
        EXPECT_GT(a.x() * b.x() + a.y() * b.y(), 0);
      }
    }
    EXPECT_GT(rims, 0);
    EXPECT_GT(rulings, 0);
    // The domes reach their poles: within half a quad.
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    for (auto v : q.vertices()) {
      lowest = std::min(lowest, static_cast<double>(q.point(v)[2]));
      highest = std::max(highest, static_cast<double>(q.point(v)[2]));
    }
    EXPECT_LT(lowest, c.bottom_pole + 10);
    if (!std::isnan(c.top_pole)) {
      EXPECT_GT(highest, c.top_pole - 10);
    }
  }
}

// A sweep with a dome competes with the lattice: kept where it has at most
// QuadMeshOptions::domed_sweep_share (0.75) of the lattice's irregular vertices, else the
// lattice is (an egg swept came out with 51 parts against the lattice's 46 at 300 mm, an
// OpenSCAD sphere 52 against 39, their sweeps with 0.87 and 1.08 of the lattice's irregular
// vertices; a capsule's, with 0.36, 51 against 82). Each shape meshed three ways: swept
// (share infinite), by the lattice (share 0: no sweep has none), and by default, which must be
// the one the rule picks, and say so.
TEST(Quads, DomesSweptWhereTheyBeatTheLattice) {
  int swept = 0, lattice = 0;
  for (const DomedLoft& c : domed_lofts()) {
    SCOPED_TRACE(c.name);
    const double inf = std::numeric_limits<double>::infinity();
    const QuadMeshResult s = mesh_of(c.mesh, {.quad_size = 20, .domed_sweep_share = inf});
    const QuadMeshResult l = mesh_of(c.mesh, {.quad_size = 20, .domed_sweep_share = 0});
    const QuadMeshResult d = mesh_of(c.mesh, {.quad_size = 20});
    ASSERT_EQ(s.method.rfind("loft", 0), 0u) << s.method;
    ASSERT_EQ(l.method.rfind("lattice", 0), 0u) << l.method;
    ASSERT_GT(l.irregular_vertices, 0);
    const bool sweep = s.irregular_vertices <= 0.75 * l.irregular_vertices;
    const QuadMeshResult& picked = sweep ? s : l;
    EXPECT_EQ(d.quads.n_faces(), picked.quads.n_faces());
    EXPECT_EQ(d.irregular_vertices, picked.irregular_vertices);
    EXPECT_EQ(d.method.rfind(sweep ? "loft" : "lattice", 0), 0u) << d.method;
    const std::string counts = std::to_string(s.irregular_vertices) +
                               " irregular vertices swept, " +
                               std::to_string(l.irregular_vertices) + " on the lattice";
    EXPECT_NE(d.method.find(counts), std::string::npos) << d.method;
    (sweep ? swept : lattice) += 1;
  }
  // The capsule is swept (its lattice has far more irregular vertices), a sphere is not.
  EXPECT_GE(swept, 1);
  EXPECT_GE(lattice, 1);
}

// A target whose triangles face into the solid (or, open, the other way round) is swept the
// same, its quads facing as its triangles do: a pot open at the top whose bottom faces up
// was no extrusion (its caps looked for facing out), and a lampshade or vase so turned had all
// its swept quads taken as folded (lampshade 21 parts from the lattice instead of 17, vase 33
// instead of 19, at 250 mm).
TEST(Quads, TargetsWhoseTrianglesFaceInAreSweptToo) {
  const auto turned = [](TriangleMesh m) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    return m;
  };
  const std::vector<std::array<double, 2>> vase = test::vase_profile();
  struct Case {
    std::string name, method;
    TriangleMesh mesh;
  };
  for (const Case& c :
       {Case{"pot", "extrusion", turned(test::drum(80, 120, 96, true, false))},
        Case{"lampshade", "loft", turned(test::lathe({{100, 0}, {60, 150}}, 96, false, false))},
        Case{"vase", "loft", turned(test::lathe(vase, 48, true, false))}}) {
    SCOPED_TRACE(c.name);
    const QuadMeshResult r = mesh_of(c.mesh, {.quad_size = 20});
    ASSERT_EQ(r.method.rfind(c.method, 0), 0u) << r.method;
    // The bottom faces up (into the pot), as the target's does; the lampshade's wall in (its
    // quads' normals toward the axis).
    for (auto f : r.quads.faces()) {
      std::vector<Vec3> p;
      for (auto v : r.quads.fv_range(f)) p.push_back(to_eigen(r.quads.point(v)));
      Vec3 n = Vec3::Zero(), middle = Vec3::Zero();
      for (std::size_t i = 0; i < p.size(); ++i)
        n += p[i].cross(p[(i + 1) % p.size()]), middle += p[i] / 4;
      const bool bottom =
          std::all_of(p.begin(), p.end(), [](const Vec3& q) { return std::abs(q.z()) < 1e-9; });
      if (bottom)
        EXPECT_GT(n.z(), 0);
      else
        EXPECT_LT(n.dot(Vec3(middle.x(), middle.y(), 0)), 0);
    }
  }
}

// An extrusion's wall is swept from its cap's border in rows: every quad of the wall a
// rectangle with sides along the axis and along the rims, no irregular vertex on it, its
// rims on quad edges, and the bending program told which of its edges bend (those between
// rows) and which are rulings (those along the axis). A drum whose lattice had 81 irregular
// vertices, many on the wall, came out of the whole run (250 mm, 3 mm MDF) as 47 parts,
// Hausdorff 1.6 % of the diagonal; swept, 15 parts (two caps, the wall in rings), 0.6 %.
TEST(Quads, AnExtrusionsWallIsSweptInRingsOfRegularQuads) {
  const auto wall_is_swept = [](const QuadMeshResult& r, double height, double rim_radius,
                                double chord_sagitta) {
    ASSERT_EQ(r.method.rfind("extrusion", 0), 0u) << r.method;
    expect_sound_quads(r.quads);
    const PolyMesh& q = r.quads;
    const auto on_wall = [&](const Vec3& p) { return p.z() > 1e-6 && p.z() < height - 1e-6; };
    int wall_vertices = 0;
    for (auto v : q.vertices()) {
      const Vec3 p = to_eigen(q.point(v));
      if (on_wall(p) && !q.is_boundary(v)) {
        ++wall_vertices;
        EXPECT_EQ(q.valence(v), 4u) << "wall vertex at " << p.transpose();
      }
      // The rims (a cap's vertices with an edge up or down the wall) on the target's circle
      // (its polygon: between the chords' middles and it).
      bool rim = false;
      for (auto w : q.vv_range(v)) rim = rim || std::abs(q.point(w)[2] - p.z()) > 1e-6;
      if (rim && !on_wall(p)) {
        EXPECT_NEAR(std::hypot(p.x(), p.y()), rim_radius - chord_sagitta / 2,
                    chord_sagitta / 2 + 1e-6);
      }
    }
    EXPECT_GT(wall_vertices, 0);
    // Edges of the wall run along the axis or round it (horizontal).
    int bend = 0, rule = 0;
    for (auto e : q.edges()) {
      const auto h = q.halfedge_handle(e, 0);
      const Vec3 a = to_eigen(q.point(q.from_vertex_handle(h))),
                 b = to_eigen(q.point(q.to_vertex_handle(h)));
      if (!on_wall(a) && !on_wall(b) && std::abs(a.z() - b.z()) < 1e-6) continue;  // a cap's
      const Vec3 d = (b - a).normalized();
      EXPECT_TRUE(std::abs(d.z()) > std::cos(1e-6) || std::abs(d.z()) < 1e-9) << d.transpose();
    }
    for (const EdgeGuidance& g : r.bending) {
      const Vec3 a = to_eigen(q.point(OpenMesh::VertexHandle(g.v0)));
      const Vec3 b = to_eigen(q.point(OpenMesh::VertexHandle(g.v1)));
      ASSERT_TRUE(
          q.find_halfedge(OpenMesh::VertexHandle(g.v0), OpenMesh::VertexHandle(g.v1)).is_valid());
      if (g.bendable) {
        ++bend;
        EXPECT_NEAR(a.z(), b.z(), 1e-9);  // between rows: round the axis
      } else {
        ++rule;
        EXPECT_NEAR(std::hypot(a.x() - b.x(), a.y() - b.y()), 0, 1e-9);  // along the axis
      }
    }
    EXPECT_GT(bend, 0);
    EXPECT_GT(rule, bend);  // every row's columns, one row fewer of the edges between them
  };
  {
    std::vector<std::string> lines;
    const TargetSurface drum(test::drum(100, 120, 128));
    const QuadMeshResult r =
        make_quad_mesh(drum, Material{}, {}, [&](const std::string& l) { lines.push_back(l); });
    SCOPED_TRACE("drum");
    wall_is_swept(r, 120, 100, 100 * (1 - std::cos(kPi / 128)));
    EXPECT_EQ(euler(r.quads), 2);
    EXPECT_EQ(boundary_loop_count(r.quads), 0);
    // The cap is meshed at the model's size, and its progress says so (not "--quad-size",
    // which the user did not pass).
    int cap_lines = 0;
    for (const std::string& l : lines)
      if (l.rfind("cap: quad size", 0) == 0) {
        ++cap_lines;
        EXPECT_NE(l.find("(the model's: " + r.size.reason + ")"), std::string::npos) << l;
      }
    EXPECT_EQ(cap_lines, 1);
  }
  {
    // Open at the top: one border loop, on the top rim.
    const QuadMeshResult r = mesh_of(test::drum(100, 120, 128, true, false));
    SCOPED_TRACE("pot");
    wall_is_swept(r, 120, 100, 100 * (1 - std::cos(kPi / 128)));
    EXPECT_EQ(euler(r.quads), 1);
    EXPECT_EQ(boundary_loop_count(r.quads), 1);
    for (auto v : r.quads.vertices())
      if (r.quads.is_boundary(v)) {
        EXPECT_NEAR(r.quads.point(v)[2], 120, 1e-9);
      }
  }
  {
    const QuadMeshResult r = mesh_of(test::c_bench(60, 100, 40, 160));
    SCOPED_TRACE("C-shaped bench");
    ASSERT_EQ(r.method.rfind("extrusion", 0), 0u) << r.method;
    expect_sound_quads(r.quads);
    EXPECT_EQ(euler(r.quads), 2);
    for (auto v : r.quads.vertices()) {
      const Vec3 p = to_eigen(r.quads.point(v));
      if (p.z() > 1e-6 && p.z() < 40 - 1e-6) {
        EXPECT_EQ(r.quads.valence(v), 4u) << p.transpose();
      }
    }
  }
  // Tapered by a degree it is no extrusion but a loft
  // (Quads.ALoftsWallIsSweptInRowsAlongItsProfile).
  EXPECT_EQ(mesh_of(test::drum(100, 120, 128, true, true, 1.0)).method.rfind("loft", 0), 0u);
}

TEST(Quads, QuadsTooNarrowToBendAreWarnedAbout) {
  const auto dir = test::fresh_dir();
  auto warnings = [&](const std::string& extra) {
    const auto out = dir / "out";
    const std::string cmd = std::string(KERFAB_CLI) + " run --quiet --target " +
                            test::real_mesh("spot_triangulated.obj").string() + " --size 250 " +
                            extra + " --stop-after quads --out " + out.string() + " 2>" +
                            (dir / "err").string();
    EXPECT_EQ(std::system(cmd.c_str()), 0) << extra;
    return test::slurp(out / "report.json");
  };
  const std::string fine = warnings("--quads 1500");
  EXPECT_NE(fine.find("narrower than the 12.1 mm strips"), std::string::npos) << fine;
  EXPECT_NE(fine.find("--quad-size 12.1"), std::string::npos) << fine;
  EXPECT_EQ(warnings("").find("narrower than"), std::string::npos);
  EXPECT_EQ(warnings("--quads 400").find("narrower than"), std::string::npos);
}

}  // namespace
}  // namespace kerfab

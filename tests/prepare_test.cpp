#include "kerfab/input/prepare.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <numeric>

#include "kerfab/core/errors.h"
#include "kerfab/io/mesh_io.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

using test::poly_mesh;

TEST(Prepare, ScalesBothMeshesIdenticallyToRequestedSize) {
  const auto shape = test::sphere(1.0, 4);  // unit sphere: 2 mm across, too small without --size
  InputOptions opt;
  opt.size = 250.0;
  const PreparedInput in = prepare_input(poly_mesh(shape.target), shape.quads, opt);
  EXPECT_NEAR(in.target_summary.bbox.largest_side(), 250.0, 1e-9);
  EXPECT_NEAR(in.scale, 125.0, 1e-9);
  // Quad vertices lie on the sphere of radius 125 mm after scaling.
  for (auto v : in.quads.vertices()) EXPECT_NEAR(in.quads.point(v).norm(), 125.0, 1e-9);
  EXPECT_EQ(in.quad_summary.faces, 6 * 16);
  EXPECT_LT(in.quad_max_distance, 1e-9);
}

TEST(Prepare, RefusesModelsOutsideMillimetreRangeWithoutSize) {
  const auto small = test::sphere(1.0, 2);
  try {
    prepare_input(poly_mesh(small.target), small.quads, {});
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("--size"), std::string::npos) << e.what();
  }
  const auto huge = test::sphere(6000.0, 2);  // 12 m
  EXPECT_THROW(prepare_input(poly_mesh(huge.target), huge.quads, {}), InvalidInput);
  const auto ok = test::sphere(100.0, 2);
  EXPECT_NO_THROW(prepare_input(poly_mesh(ok.target), ok.quads, {}));
  InputOptions bad;
  bad.size = 5.0;
  EXPECT_THROW(prepare_input(poly_mesh(ok.target), ok.quads, bad), InvalidInput);
}

TEST(Prepare, NanCoordinatesAndZeroAreaFacesAreRejected) {
  auto shape = test::sphere(100.0, 2);
  PolyMesh target = poly_mesh(shape.target);
  PolyMesh nan_quads = shape.quads;
  nan_quads.set_point(nan_quads.vertex_handle(3), {std::nan(""), 0, 0});
  EXPECT_THROW(prepare_input(target, nan_quads, {}), InvalidInput);
  PolyMesh inf_target = target;
  inf_target.set_point(inf_target.vertex_handle(0), {INFINITY, 0, 0});
  EXPECT_THROW(prepare_input(inf_target, shape.quads, {}), InvalidInput);
  PolyMesh squashed = shape.quads;  // collapse one quad onto a point
  const auto f = *squashed.faces_begin();
  const auto p = squashed.point(*squashed.fv_begin(f));
  for (auto v : squashed.fv_range(f)) squashed.set_point(v, p);
  EXPECT_THROW(prepare_input(target, squashed, {}), InvalidInput);
}

/// \p in's quads are \p faces quads on \p vertices corners forming one disk (Euler
/// characteristic 1, one border loop).
void expect_quad_disk(const PreparedInput& in, int faces, int vertices) {
  EXPECT_EQ(in.quad_summary.faces, faces);
  EXPECT_EQ(in.quad_summary.vertices, vertices);
  EXPECT_EQ(in.quad_summary.euler_characteristic, 1);
  EXPECT_EQ(in.quad_summary.boundary_loops, 1);
  for (auto f : in.quads.faces()) EXPECT_EQ(in.quads.valence(f), 4u);
}

// A doublet (a zero-area quad whose opposite corners are two vertices at one point, as
// QuadriFlow left in fandisk_qf800.obj) is collapsed along that diagonal, with a warning: a
// 3 x 3 grid with its middle-left interior vertex doubled comes back as the 3 x 3 grid.
TEST(Prepare, DoubletsAreCollapsedAlongTheirDiagonal) {
  const auto plane = test::quad_plane(30, 3, 2);
  PolyMesh q;
  std::vector<OpenMesh::VertexHandle> v;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) v.push_back(q.add_vertex({10.0 * i, 10.0 * j, 0}));
  const auto twin = q.add_vertex({10, 10, 0});  // a second vertex where vertex 5 is
  auto at = [&](int i, int j) { return v[4 * j + i]; };
  // The faces around vertex 5 = (1, 1): the two on its left keep it, the two on its right take
  // its twin; the doublet [5, (1, 2), twin, (1, 0)] sits between them.
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      std::vector<OpenMesh::VertexHandle> f = {at(i, j), at(i + 1, j), at(i + 1, j + 1),
                                               at(i, j + 1)};
      if (i == 1 && j <= 1)
        for (auto& c : f)
          if (c == at(1, 1)) c = twin;
      ASSERT_TRUE(q.add_face(f).is_valid());
    }
  ASSERT_TRUE(q.add_face({at(1, 1), at(1, 0), twin, at(1, 2)}).is_valid());
  ASSERT_EQ(q.n_faces(), 10u);
  InputOptions opt;
  opt.size = 30;
  const PreparedInput in = prepare_input(poly_mesh(plane.target), q, opt);
  expect_quad_disk(in, 9, 16);
  int isolated = 0;
  for (auto vh : in.quads.vertices()) {
    if (in.quads.is_isolated(vh)) {
      ++isolated;
    } else {
      EXPECT_LE(in.quads.valence(vh), 4u);
    }
  }
  EXPECT_EQ(isolated, 1);  // the twin, kept so that every other vertex keeps its number
  ASSERT_EQ(in.warnings.size(), 1u);
  EXPECT_NE(in.warnings[0].find("face 9"), std::string::npos) << in.warnings[0];
  // The same mesh as the target alone (its own quad mesh, as a user passes a remesher's output)
  // was refused ("target mesh face 9 has zero area"): its doublet goes the same way.
  const PreparedInput own = prepare_input(q, std::nullopt, opt);
  EXPECT_TRUE(own.quads_from_target);
  expect_quad_disk(own, 9, 16);
  EXPECT_EQ(own.target_summary.faces, 9);
  EXPECT_EQ(own.target_summary.euler_characteristic, 1);
  ASSERT_EQ(own.warnings.size(), 1u);
  EXPECT_NE(own.warnings[0].find("target: 1 faces of more than three corners and no area"),
            std::string::npos)
      << own.warnings[0];
  // A zero-area quad of another kind (all corners on a line) is still refused.
  PolyMesh flat;
  for (double x : {0.0, 10.0, 20.0, 30.0}) flat.add_vertex({x, 0, 0});
  flat.add_face(
      {flat.vertex_handle(0), flat.vertex_handle(1), flat.vertex_handle(2), flat.vertex_handle(3)});
  EXPECT_THROW(prepare_input(poly_mesh(plane.target), flat, opt), InvalidInput);
}

/// Largest fold of any quad of \p mesh across either diagonal: the angle between the normals of
/// the two triangles there [deg].
double largest_diagonal_fold(const PolyMesh& mesh) {
  double worst = 0;
  for (auto f : mesh.faces()) {
    const auto c = quad_vertices(mesh, f);
    auto at = [&](int i) { return to_eigen(mesh.point(OpenMesh::VertexHandle(c[i % 4]))); };
    for (int k = 0; k < 2; ++k) {
      const Vec3 a = (at(k + 1) - at(k)).cross(at(k + 2) - at(k)),
                 b = (at(k + 2) - at(k)).cross(at(k + 3) - at(k));
      if (a.norm() > 0 && b.norm() > 0)
        worst = std::max(worst, std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI);
    }
  }
  return worst;
}

// A quad folded back onto itself across a diagonal (a dart, as QuadriFlow left two of in
// fandisk_qf800.obj at a sharp edge) is collapsed: its two corners off that diagonal merge at
// their midpoint, with a warning. A flat 3 x 3 grid of 10 mm whose middle quad (face 4, corners
// 5, 6, 10, 9) has corner 6 moved across the diagonal 5-10, to (13, 17): that quad folds by
// 180 degrees there; corners 6 and 9 merge at (11.5, 18.5). A control cage (subdivided) keeps it.
TEST(Prepare, QuadsFoldedBackAcrossADiagonalAreCollapsed) {
  const auto plane = test::quad_plane(30, 3, 2);
  PolyMesh q;
  std::vector<OpenMesh::VertexHandle> v;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) v.push_back(q.add_vertex({10.0 * i, 10.0 * j, 0}));
  q.set_point(v[6], {13, 17, 0});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      ASSERT_TRUE(q.add_face({v[4 * j + i], v[4 * j + i + 1], v[4 * j + i + 5], v[4 * j + i + 4]})
                      .is_valid());
  ASSERT_GT(largest_diagonal_fold(q), 179.0);
  InputOptions opt;
  opt.size = 30;
  const PreparedInput in = prepare_input(poly_mesh(plane.target), q, opt);
  expect_quad_disk(in, 8, 15);
  EXPECT_LT(largest_diagonal_fold(in.quads), 150.0);
  EXPECT_TRUE(in.quads.is_isolated(in.quads.vertex_handle(9)));  // numbers kept: 9 went into 6
  const auto merged = in.quads.point(in.quads.vertex_handle(6)) / in.scale;
  EXPECT_NEAR(merged[0], 11.5, 1e-9);
  EXPECT_NEAR(merged[1], 18.5, 1e-9);
  EXPECT_EQ(in.quads.valence(in.quads.vertex_handle(6)), 6u);
  ASSERT_EQ(in.warnings.size(), 1u);
  EXPECT_NE(in.warnings[0].find("face 4)"), std::string::npos) << in.warnings[0];
  // Subdivided, the mesh is a cage: nothing collapses (nine quads, four each).
  opt.subdivide = 1;
  const PreparedInput cage = prepare_input(poly_mesh(plane.target), q, opt);
  EXPECT_EQ(cage.quad_summary.faces, 36);
  EXPECT_TRUE(cage.warnings.empty());
}

// A mesh folded all over is not repaired one dart at a time (each collapse rebuilds the mesh:
// 2,500 darts in 22,500 quads took 47 s): at most 64 are tried, the rest stay and are counted.
// A 30 x 30 grid with a dart in every third row and column (100 darts, apart from each other).
TEST(Prepare, AMeshFoldedAllOverIsNotRepairedDartByDart) {
  const int n = 30;
  const auto plane = test::quad_plane(10.0 * n, n, 2);
  PolyMesh q;
  std::vector<OpenMesh::VertexHandle> v;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) v.push_back(q.add_vertex({10.0 * i, 10.0 * j, 0}));
  int darts = 0;
  for (int j = 1; j < n - 1; j += 3)
    for (int i = 1; i < n - 1; i += 3, ++darts)  // corner (i + 1, j) across the diagonal
      q.set_point(v[(n + 1) * j + i + 1], {10.0 * i + 3, 10.0 * j + 7, 0});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = (n + 1) * j + i;
      ASSERT_TRUE(q.add_face({v[a], v[a + 1], v[a + n + 2], v[a + n + 1]}).is_valid());
    }
  ASSERT_EQ(darts, 100);
  InputOptions opt;
  opt.size = 10.0 * n;
  const PreparedInput in = prepare_input(poly_mesh(plane.target), q, opt);
  EXPECT_EQ(in.quad_summary.faces, n * n - 64);
  ASSERT_EQ(in.warnings.size(), 2u);
  EXPECT_NE(in.warnings[0].find("64 quads folded back"), std::string::npos) << in.warnings[0];
  EXPECT_NE(in.warnings[1].find("36 quad(s) stay folded back"), std::string::npos)
      << in.warnings[1];
}

// QuadriFlow's fandisk: its doublet and its two darts (faces 43 and 116, folded 175 and 179
// degrees at a sharp edge) are collapsed, and so are the corners of two quads those collapses
// leave; the mesh stays closed, all quads, with the target's
// Euler characteristic, and no quad folds across a diagonal by more than 150 degrees.
TEST(Prepare, QuadriFlowsFandiskLosesItsDarts) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const PolyMesh target = read_mesh(test::shared_meshes() / "fandisk.obj");
  const PolyMesh quads = read_mesh(test::shared_meshes() / "quadriflow" / "fandisk_qf800.obj");
  ASSERT_GT(largest_diagonal_fold(quads), 179.0);
  InputOptions opt;
  opt.size = 250;
  const PreparedInput in = prepare_input(target, quads, opt);
  // One quad fewer for the doublet, two for the darts, two for the corners of two quads their
  // collapses left (a dart's collapse takes a side from each corner on its folded diagonal), and
  // one for the quad merged there that then folded back across its diagonal (face 44).
  EXPECT_EQ(in.quad_summary.faces, static_cast<int>(quads.n_faces()) - 6);
  EXPECT_EQ(in.quad_summary.euler_characteristic, 2);
  EXPECT_EQ(in.quad_summary.boundary_loops, 0);
  EXPECT_LT(largest_diagonal_fold(in.quads), 150.0);
  ASSERT_EQ(in.warnings.size(), 3u);
  EXPECT_NE(in.warnings[1].find("face 43 44 116)"), std::string::npos) << in.warnings[1];
  EXPECT_NE(in.warnings[2].find("2 vertices left with two quads"), std::string::npos)
      << in.warnings[2];
  for (auto v : in.quads.vertices()) {  // no inner corner of two quads is left
    if (in.quads.is_isolated(v)) continue;
    EXPECT_GT(in.quads.valence(v), 2u) << v.idx();
  }
}

TEST(Prepare, NonQuadFacesNeedSubdivisionAndTriangleTargetWaitsForTheQuadsStage) {
  const PolyMesh cage = read_mesh(test::real_mesh("spot_control_mesh.obj"));
  const PolyMesh target = read_mesh(test::real_mesh("spot_triangulated.obj"));
  InputOptions opt;
  opt.size = 250.0;
  try {
    prepare_input(target, cage, opt);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("--subdivide"), std::string::npos) << e.what();
  }
  // A triangle target alone: prepared, its quad mesh left to the quads stage.
  const PreparedInput alone = prepare_input(target, std::nullopt, opt);
  EXPECT_TRUE(alone.needs_quads);
  EXPECT_EQ(alone.quads.n_faces(), 0u);
  opt.subdivide = 1;
  const PreparedInput in = prepare_input(target, cage, opt);
  // One Catmull-Clark step: every n-gon becomes n quads: 160*4 + 16*5 + 4*3 = 732.
  EXPECT_EQ(in.quad_summary.faces, 732);
  EXPECT_EQ(in.quad_summary.face_sizes, (std::vector<std::pair<int, int>>{{4, 732}}));
  EXPECT_EQ(in.quad_summary.euler_characteristic, 2);
  EXPECT_LT(in.quad_max_distance, 0.03 * in.target_summary.bbox.diagonal());
}

TEST(Prepare, QuadMeshFarFromTargetIsRefusedWithItsDistance) {
  // The AmO pair of the shared collection has its quad mesh moved by about (73, 16, 39); here
  // Spot's control mesh is moved by a third of the model's size.
  const PolyMesh target = read_mesh(test::real_mesh("spot_triangulated.obj"));
  PolyMesh quads = read_mesh(test::real_mesh("spot_control_mesh.obj"));
  for (auto v : quads.vertices())
    quads.set_point(v, quads.point(v) + OpenMesh::Vec3d(0.5, 0.1, 0.3));
  InputOptions opt;
  opt.size = 250;
  opt.subdivide = 1;
  try {
    prepare_input(target, quads, opt);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("far from the target"), std::string::npos) << msg;
    EXPECT_NE(msg.find(" mm away"), std::string::npos) << msg;
  }
}

TEST(Prepare, QuadTargetServesAsItsOwnQuadMesh) {
  const PolyMesh fandisk = read_mesh(test::real_mesh("fandisk_quads.off"));
  InputOptions opt;
  opt.size = 200.0;
  const PreparedInput in = prepare_input(fandisk, std::nullopt, opt);
  EXPECT_TRUE(in.quads_from_target);
  EXPECT_EQ(in.quad_summary.faces, 764);
  EXPECT_LT(in.quad_max_distance, 1e-9);
}

TEST(Prepare, InwardFacingClosedTargetIsFlippedForSignedDistance) {
  auto shape = test::sphere(100.0, 3);
  PolyMesh inward;
  for (const auto& p : shape.target.vertices) inward.add_vertex(to_openmesh(p));
  for (const auto& f : shape.target.triangles)
    inward.add_face(inward.vertex_handle(f[0]), inward.vertex_handle(f[2]),
                    inward.vertex_handle(f[1]));
  const PreparedInput in = prepare_input(inward, shape.quads, {});
  EXPECT_EQ(in.warnings.size(), 1u);
  EXPECT_GT(in.surface.signed_distance({0, 0, 150}), 0.0);
  EXPECT_LT(in.surface.signed_distance({0, 0, 50}), 0.0);
}

// Two closed pieces, one facing in: only that one is turned (the volume summed over both had
// been positive, so the inward ball stayed inside out: its inside read as outside). A ball
// facing in inside another is a cavity and stays as it is.
TEST(Prepare, OnlyTheClosedPiecesFacingInwardAreTurned) {
  const auto ball = test::sphere(100.0, 3);
  // \p inward_offset: the second ball's centre; \p r: its radius.
  auto two = [&](const Vec3& centre, double r) {
    PolyMesh m;
    for (const auto& p : ball.target.vertices) m.add_vertex(to_openmesh(p));
    for (const auto& f : ball.target.triangles)
      m.add_face(m.vertex_handle(f[0]), m.vertex_handle(f[1]), m.vertex_handle(f[2]));
    const int offset = static_cast<int>(m.n_vertices());
    for (const auto& p : ball.target.vertices) m.add_vertex(to_openmesh(centre + p * (r / 100)));
    for (const auto& f : ball.target.triangles)  // facing in, first corners kept
      m.add_face(m.vertex_handle(offset + f[0]), m.vertex_handle(offset + f[2]),
                 m.vertex_handle(offset + f[1]));
    return m;
  };
  const PreparedInput apart = prepare_input(two({300, 0, 0}, 50), ball.quads, {});
  ASSERT_EQ(apart.warnings.size(), 1u);
  EXPECT_NE(apart.warnings[0].find("1 of its 2 closed pieces"), std::string::npos);
  EXPECT_LT(apart.surface.signed_distance({300, 0, 0}), -49.0);  // the small ball's centre
  EXPECT_GT(apart.surface.signed_distance({300, 0, 80}), 29.0);
  EXPECT_LT(apart.surface.signed_distance({0, 0, 0}), -99.0);
  // The target as used (model/target.obj) faces out too: both balls' volumes positive.
  const TriangleMesh used = triangulate(apart.target);
  double volume = 0;
  for (const auto& t : used.triangles)
    volume += used.vertices[t[0]].dot(used.vertices[t[1]].cross(used.vertices[t[2]])) / 6;
  double balls = 0;
  for (const auto& t : ball.target.triangles)
    balls += ball.target.vertices[t[0]].dot(
                 ball.target.vertices[t[1]].cross(ball.target.vertices[t[2]])) /
             6;
  EXPECT_NEAR(volume, balls * (1 + 0.125), 1e-6 * balls);  // radius 50: an eighth of the volume

  const PreparedInput hollow = prepare_input(two({0, 0, 0}, 50), ball.quads, {});
  EXPECT_TRUE(hollow.warnings.empty());
  EXPECT_GT(hollow.surface.signed_distance({0, 0, 0}), 49.0);    // in the cavity: outside
  EXPECT_LT(hollow.surface.signed_distance({0, 0, 75}), -24.0);  // in the wall
}

// Two closed boxes of quads (100 mm cubes) glued face to face are two pieces whose surfaces
// share the face between them. Given as the target alone, they are joined into their union,
// whose surface the quads stage meshes anew (the boxes' own quads follow both surfaces). With
// a quad mesh of the same boxes given too, which kerfab must use as it is, they are refused at
// once, with the area they share and where, and what to do. (Before, the quads stage tried
// four lattices and a smoothed copy for 86 s and then failed on folded quads, naming neither
// the cause nor the fix.) Boxes 1 mm apart, or meeting along an edge only, are not touching
// face to face and are prepared as before, their quads used.
TEST(Prepare, SolidsGluedFaceToFaceAreRefusedNamingWhere) {
  auto two_boxes = [](const Vec3& shift) {
    PolyMesh m;
    for (const Vec3& at : {Vec3(0, 0, 0), shift}) {
      const PolyMesh box = test::cube_grid_mesh(
          2, [&](const Vec3& p) { return Vec3(50 * (p + Vec3::Ones()) + at); });
      const int offset = static_cast<int>(m.n_vertices());
      for (auto v : box.vertices()) m.add_vertex(box.point(v));
      for (auto f : box.faces()) {
        std::vector<PolyMesh::VertexHandle> corners;
        for (auto v : box.fv_range(f)) corners.push_back(m.vertex_handle(offset + v.idx()));
        m.add_face(corners);
      }
    }
    return m;
  };
  {
    const PreparedInput in = prepare_input(two_boxes({100, 0, 0}), std::nullopt, {});
    EXPECT_TRUE(in.needs_quads);
    EXPECT_EQ(in.united_solids, 2);
    EXPECT_NEAR(in.united_surface_gone, 2e4, 1e-6);
    EXPECT_EQ(in.target_summary.euler_characteristic, 2);
  }
  try {
    prepare_input(two_boxes({100, 0, 0}), two_boxes({100, 0, 0}), {});
    ADD_FAILURE() << "two boxes glued face to face were prepared with their quads";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("lie on one another over 1e+04 mm^2"), std::string::npos) << what;
    EXPECT_NE(what.find("(at 100, "), std::string::npos) << what;  // on the shared face x = 100
    EXPECT_NE(what.find("join them"), std::string::npos) << what;
  }
  for (const Vec3& shift : {Vec3(101, 0, 0), Vec3(100, 100, 0)}) {
    const PreparedInput in = prepare_input(two_boxes(shift), std::nullopt, {});
    EXPECT_EQ(in.target_summary.faces, 2 * 24) << shift.transpose();
    EXPECT_FALSE(in.needs_quads) << shift.transpose();
  }
}

/// A closed box of triangles (each face 2 x 2 squares cut in two) from \p lo to \p hi [mm]; an
/// inward one faces inwards (a cavity).
struct TriangleBox {
  Vec3 lo, hi;
  bool inward = false;
};

/// The boxes, each its own piece, as one mesh.
PolyMesh triangle_boxes(const std::vector<TriangleBox>& boxes) {
  PolyMesh m;
  for (const TriangleBox& b : boxes) {
    const PolyMesh box = test::cube_grid_mesh(2, [&](const Vec3& p) {
      return Vec3(b.lo + (0.5 * (p + Vec3::Ones())).cwiseProduct(b.hi - b.lo));
    });
    TriangleMesh tri = triangulate(box);
    if (b.inward)
      for (auto& t : tri.triangles) std::swap(t[1], t[2]);
    const int offset = static_cast<int>(m.n_vertices());
    for (const Vec3& v : tri.vertices) m.add_vertex(PolyMesh::Point(v.x(), v.y(), v.z()));
    for (const auto& t : tri.triangles)
      m.add_face(m.vertex_handle(offset + t[0]), m.vertex_handle(offset + t[1]),
                 m.vertex_handle(offset + t[2]));
  }
  return m;
}

/// The area [mm^2] and enclosed volume [mm^3] of the surface \p in queries.
std::pair<double, double> area_and_volume(const PreparedInput& in) {
  const TriangleMesh& t = in.surface.mesh();
  double area = 0, volume = 0;
  for (const auto& c : t.triangles) {
    const Vec3 &a = t.vertices[c[0]], &b = t.vertices[c[1]], &d = t.vertices[c[2]];
    area += 0.5 * (b - a).cross(d - a).norm();
    volume += a.dot(b.cross(d)) / 6;
  }
  return {area, volume};
}

// Solids of triangles that cross or touch are one solid to the maker: where kerfab makes the
// quads, the target becomes the surface of their union (CGAL's corefinement), measured here
// against the exact area and volume. Two 100 mm cubes glued face to face: a 200 x 100 x 100 box
// (100000 mm^2, 2e6 mm^3, where the two surfaces had 120000 mm^2); a 100 mm cube with a 50 mm
// square bar pushed 50 mm into it: 60000 - 2500 + 5 * 2500 = 70000 mm^2 and 1e6 + 50^3 mm^3.
// A 20 mm cube hidden inside the 100 mm one is gone with its surface. Cubes meeting along an
// edge only have no manifold union and stay two pieces.
TEST(Prepare, SolidsThatMeetAreJoinedIntoTheirUnion) {
  auto joined = [](const PreparedInput& in) {
    for (const std::string& w : in.warnings)
      if (w.find("2 solids that overlap or touch joined into one") != std::string::npos)
        return true;
    return false;
  };
  auto expect = [&](const Vec3& lo, const Vec3& hi, double area, double volume, int euler,
                    bool united) {
    const PreparedInput in = prepare_input(
        triangle_boxes({{Vec3(0, 0, 0), Vec3(100, 100, 100)}, {lo, hi}}), std::nullopt, {});
    const auto [a, v] = area_and_volume(in);
    EXPECT_NEAR(a, area, 1e-6) << lo.transpose();
    EXPECT_NEAR(v, volume, 1e-4) << lo.transpose();
    EXPECT_EQ(in.target_summary.euler_characteristic, euler) << lo.transpose();
    EXPECT_EQ(joined(in), united) << lo.transpose();
  };
  expect({100, 0, 0}, {200, 100, 100}, 1e5, 2e6, 2, true);
  expect({50, 25, 25}, {150, 75, 75}, 7e4, 1.125e6, 2, true);
  expect({100, 100, 0}, {200, 200, 100}, 1.2e5, 2e6, 4, false);  // two pieces: Euler 2 + 2
  expect({40, 40, 40}, {60, 60, 60}, 6e4, 1e6, 2, true);         // a 20 mm cube hidden inside
}

// A hollowed model (as for 3D printing: a closed inner wall facing inwards) is cut as its outer
// shell: the cavity, which turn_closed_pieces_out leaves facing inwards, is left out with a
// warning giving its area, where kerfab makes the quads. A 100 mm cube hollowed to a 60 mm cavity:
// 60000 mm^2 of surface, 1e6 mm^3 of volume, one piece (Euler characteristic 2), the cavity's
// 21600 mm^2 named.
TEST(Prepare, AHollowModelsInnerWallIsLeftOut) {
  const PreparedInput in =
      prepare_input(triangle_boxes({{Vec3(0, 0, 0), Vec3(100, 100, 100)},
                                    {Vec3(20, 20, 20), Vec3(80, 80, 80), true}}),
                    std::nullopt, {});
  const auto [area, volume] = area_and_volume(in);
  EXPECT_NEAR(area, 6e4, 1e-6);
  EXPECT_NEAR(volume, 1e6, 1e-4);
  EXPECT_EQ(in.target_summary.euler_characteristic, 2);
  bool named = false;
  for (const std::string& w : in.warnings)
    named = named || (w.find("1 inner surface (a cavity") != std::string::npos &&
                      w.find("2.16e+04 mm^2") != std::string::npos);
  EXPECT_TRUE(named);
}

// Polygons of more than four corners are cut by ear clipping: a U (concave, 8 corners, area
// 500 mm^2) into 6 triangles that all turn its way and cover it exactly; the fan from its first
// corner had a triangle turning the other way, over the notch. A convex hexagon gives the fan.
TEST(Prepare, PolygonsAreTriangulatedByEarClipping) {
  const std::vector<Vec3> u = {{0, 0, 5},   {30, 0, 5},  {30, 20, 5}, {20, 20, 5},
                               {20, 10, 5}, {10, 10, 5}, {10, 20, 5}, {0, 20, 5}};
  std::vector<int> ids(u.size());
  for (std::size_t k = 0; k < ids.size(); ++k) ids[k] = static_cast<int>(k);
  auto check = [&](const std::vector<Vec3>& points, double area, std::size_t triangles) {
    std::vector<std::array<int, 3>> t;
    triangulate_polygon(points, ids, t);
    EXPECT_EQ(t.size(), triangles);
    double sum = 0;
    for (const auto& c : t) {
      const double z = (points[c[1]] - points[c[0]]).cross(points[c[2]] - points[c[0]]).z() / 2;
      EXPECT_GT(z, 0) << c[0] << " " << c[1] << " " << c[2];
      sum += z;
    }
    EXPECT_NEAR(sum, area, 1e-9);
    return t;
  };
  check(u, 500, 6);
  double fan_reversed = 0;  // the fan from corner 0 would have had a triangle turning back
  for (std::size_t k = 1; k + 1 < u.size(); ++k)
    fan_reversed += (u[k] - u[0]).cross(u[k + 1] - u[0]).z() < 0;
  EXPECT_GT(fan_reversed, 0);

  std::vector<Vec3> hexagon;
  for (int k = 0; k < 6; ++k)
    hexagon.emplace_back(10 * std::cos(k * M_PI / 3), 10 * std::sin(k * M_PI / 3), 0);
  ids.resize(6);
  const auto t = check(hexagon, 6 * 100 * std::sqrt(3.0) / 4, 4);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(t[k], (std::array<int, 3>{0, k + 1, k + 2}));
}

/// A 100 mm cube's eight corners (bottom 0-3, top 4-7, counter-clockwise from the origin) and
/// \p extra as vertex 8, no faces.
PolyMesh cube_corners_and(const Vec3& extra) {
  PolyMesh m;
  for (const auto& p : std::vector<Vec3>{{0, 0, 0},
                                         {100, 0, 0},
                                         {100, 100, 0},
                                         {0, 100, 0},
                                         {0, 0, 100},
                                         {100, 0, 100},
                                         {100, 100, 100},
                                         {0, 100, 100},
                                         extra})
    m.add_vertex(to_openmesh(p));
  return m;
}

/// A 100 mm cube of triangles with what exporters leave: \p needle: two needles (a corner
/// doubled 1e-9 mm away); else a sliver on the bottom's front edge (its middle corner on the
/// edge, which the front face runs along whole).
PolyMesh cube_with_degenerate_triangles(bool needle) {
  PolyMesh m = cube_corners_and(needle ? Vec3(1e-9, 0, 100) : Vec3(50, 0, 0));
  const std::vector<std::array<int, 3>> sliver = {
      {0, 3, 2}, {0, 2, 8}, {8, 2, 1}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
      {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}, {4, 5, 6}, {4, 6, 7}, {0, 8, 1}};
  const std::vector<std::array<int, 3>> needles = {
      {0, 3, 2}, {0, 2, 1}, {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7},
      {2, 7, 6}, {3, 0, 4}, {3, 4, 8}, {3, 8, 7}, {4, 5, 6}, {4, 6, 8}, {8, 6, 7}};
  for (const auto& t : needle ? needles : sliver)
    m.add_face(m.vertex_handle(t[0]), m.vertex_handle(t[1]), m.vertex_handle(t[2]));
  return m;
}

// Triangles of no area carry no surface: a sliver's middle corner goes into the face across
// its longest edge, a needle's two corners are merged; the cube is whole and closed again.
// Before, the sliver was refused ("face 13 has zero area") and the needles (area just over the
// zero mark) ended the quads stage in a CGAL precondition, a crash in the release build.
TEST(Prepare, TrianglesOfNoAreaAreMended) {
  for (const bool needle : {false, true}) {
    SCOPED_TRACE(needle);
    const PreparedInput in =
        prepare_input(cube_with_degenerate_triangles(needle), std::nullopt, {});
    ASSERT_EQ(in.warnings.size(), 1u);
    EXPECT_NE(in.warnings[0].find(needle ? "target: 2 triangles of no area"
                                         : "target: 1 triangles of no area"),
              std::string::npos)
        << in.warnings[0];
    EXPECT_EQ(in.target_summary.boundary_loops, 0);
    EXPECT_EQ(in.target_summary.euler_characteristic, 2);
    // Every face left has area, and together they are the cube's surface.
    const TriangleMesh t = triangulate(in.target);
    double area = 0;
    for (const auto& c : t.triangles) {
      const double a =
          0.5 *
          (t.vertices[c[1]] - t.vertices[c[0]]).cross(t.vertices[c[2]] - t.vertices[c[0]]).norm();
      EXPECT_GT(a, 1.0);
      area += a;
    }
    EXPECT_NEAR(area, 6 * 100.0 * 100, 1e-6);
  }
}

// A needle beside a quad that has both its corners (a corner doubled 1e-9 mm away, the top of a
// cube cut into a quad whose edge there has no length and two triangles): merging the needle's
// corners leaves the quad with a corner twice in a row, a triangle of real area. Before, that
// quad went with the needle's mate, and the cube was left with a hole of 5000 mm^2.
TEST(Prepare, AQuadBesideANeedleBecomesATriangleNotAHole) {
  PolyMesh m = cube_corners_and({1e-9, 0, 100});
  const std::vector<std::vector<int>> faces = {{0, 3, 2, 1}, {0, 1, 5, 4}, {1, 2, 6, 5},
                                               {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 8, 6, 7},
                                               {8, 5, 6},    {4, 5, 8}};
  for (const auto& f : faces) {
    std::vector<PolyMesh::VertexHandle> c;
    for (int v : f) c.push_back(m.vertex_handle(v));
    ASSERT_TRUE(m.add_face(c).is_valid());
  }
  EXPECT_EQ(boundary_loop_count(m), 0);
  const PreparedInput in = prepare_input(m, std::nullopt, {});
  ASSERT_FALSE(in.warnings.empty());
  EXPECT_NE(in.warnings[0].find("target: 1 triangles of no area"), std::string::npos)
      << in.warnings[0];
  EXPECT_EQ(in.target_summary.boundary_loops, 0);
  EXPECT_EQ(in.target_summary.euler_characteristic, 2);
  const TriangleMesh t = triangulate(in.target);
  double area = 0;
  for (const auto& c : t.triangles)
    area += 0.5 *
            (t.vertices[c[1]] - t.vertices[c[0]]).cross(t.vertices[c[2]] - t.vertices[c[0]]).norm();
  EXPECT_NEAR(area, 6 * 100.0 * 100, 1e-6);
}

// Cracks (sides cut differently along the line they share, as modellers export them) are
// zipped: points at one point become one, and points on the other side's edges are put into
// them. The box had 2 border loops (its edges open, its plates without joints there); it is
// closed, of the box's area and volume, each of its 12 edges counting n_a + n_b - 2 points
// less those both sides share (gcd(n_a, n_b) - 1).
TEST(Prepare, CracksAreZipped) {
  const std::array<int, 6> n = {2, 3, 5, 7, 2, 3};
  const PolyMesh box = test::box_cut_differently(n);
  EXPECT_GT(boundary_loop_count(box), 0);
  const PreparedInput in = prepare_input(box, std::nullopt, {});
  int expected = 0;
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b)
      if (b != a + 1 || a % 2 == 1)  // not opposite sides (0-1, 2-3, 4-5)
        expected += n[a] + n[b] - 2 - (std::gcd(n[a], n[b]) - 1);
  EXPECT_EQ(expected, 61);
  ASSERT_EQ(in.warnings.size(), 1u);
  EXPECT_NE(in.warnings[0].find("target: " + std::to_string(expected) + " vertices of a crack"),
            std::string::npos)
      << in.warnings[0];
  EXPECT_TRUE(in.needs_quads);  // sides given more corners: polygons, meshed by the quads stage
  EXPECT_EQ(in.target_summary.boundary_loops, 0);
  EXPECT_EQ(in.target_summary.euler_characteristic, 2);
  const TriangleMesh t = triangulate(in.target);
  double area = 0, volume = 0;
  for (const auto& c : t.triangles) {
    const Vec3 &p = t.vertices[c[0]], &q = t.vertices[c[1]], &r = t.vertices[c[2]];
    area += 0.5 * (q - p).cross(r - p).norm();
    volume += p.dot(q.cross(r)) / 6;
  }
  EXPECT_NEAR(area, 6 * 100.0 * 100, 1e-6);
  EXPECT_NEAR(volume, 100.0 * 100 * 100, 1e-6);
  // A mesh without cracks is left as it is.
  const PreparedInput whole =
      prepare_input(test::box_cut_differently({2, 2, 2, 2, 2, 2}), std::nullopt, {});
  EXPECT_EQ(whole.target_summary.boundary_loops, 0);
}

TEST(Prepare, CatmullClarkOfOpenGridStaysAllQuads) {
  const auto plane = test::quad_plane(100.0, 3);
  const PolyMesh sub = catmull_clark(plane.quads, 2);
  EXPECT_TRUE(is_all_quads(sub));
  EXPECT_EQ(sub.n_faces(), 9u * 16u);
  EXPECT_EQ(boundary_loop_count(sub), 1);
}

}  // namespace
}  // namespace kerfab

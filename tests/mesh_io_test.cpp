#include "kerfab/io/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "kerfab/core/errors.h"
#include "kerfab/io/orient.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

using test::fresh_dir;
using test::write_text;

TEST(MeshIo, ObjWithTextureNormalIndicesAndMissingMaterialLibrary) {
  const auto dir = fresh_dir();
  const auto path = write_text(dir / "quad.obj",
                               "mtllib missing.mtl\n"
                               "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\n"
                               "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl x\n"
                               "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
  const PolyMesh m = read_mesh(path);
  EXPECT_EQ(m.n_vertices(), 4u);
  EXPECT_EQ(m.n_faces(), 1u);
  EXPECT_EQ(m.valence(*m.faces_begin()), 4u);
  EXPECT_DOUBLE_EQ(bounding_box(m).largest_side(), 10.0);
}

TEST(MeshIo, OffWithFacesWrappedOverSeveralLines) {
  const auto dir = fresh_dir();
  const auto path = write_text(dir / "wrapped.off",
                               "OFF\n5 2 0\n0 0 0\n10 0 0\n10 10 0\n0 10 0\n20 5 0\n"
                               "4\n0 1\n2 3\n3 1 4 2\n");
  const PolyMesh m = read_mesh(path);
  EXPECT_EQ(m.n_faces(), 2u);
  EXPECT_EQ(face_size_histogram(m), (std::vector<std::pair<int, int>>{{3, 1}, {4, 1}}));
}

// PLY (ascii and binary) and STL (ascii and binary) written by OpenMesh read back unchanged.
TEST(MeshIo, PlyAndStlRoundTrip) {
  const auto dir = fresh_dir();
  const auto shape = test::sphere(40.0, 3, 1);
  PolyMesh tri;
  for (const auto& p : shape.target.vertices) tri.add_vertex(to_openmesh(p));
  for (const auto& t : shape.target.triangles)
    tri.add_face(tri.vertex_handle(t[0]), tri.vertex_handle(t[1]), tri.vertex_handle(t[2]));
  for (const char* name : {"a.ply", "a.stl"}) {
    write_mesh(tri, dir / name);
    const PolyMesh back = read_mesh(dir / name);
    EXPECT_EQ(back.n_faces(), tri.n_faces()) << name;
    EXPECT_EQ(back.n_vertices(), tri.n_vertices()) << name;
    EXPECT_NEAR(bounding_box(back).diagonal(), bounding_box(tri).diagonal(), 1e-4) << name;
  }
  // (The STL reader merges corner copies into shared vertices, as the counts above show.)
  // Binary PLY and binary STL, written byte by byte as other tools write them.
  const auto bin_ply = write_text(dir / "bin.ply",
                                  "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                                  "property float x\nproperty float y\nproperty float z\n"
                                  "element face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n");
  {
    std::ofstream out(bin_ply, std::ios::app | std::ios::binary);
    const float v[9] = {0, 0, 0, 20, 0, 0, 0, 20, 0};
    out.write(reinterpret_cast<const char*>(v), sizeof v);
    const unsigned char n = 3;
    const int idx[3] = {0, 1, 2};
    out.write(reinterpret_cast<const char*>(&n), 1);
    out.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  const PolyMesh b = read_mesh(bin_ply);
  EXPECT_EQ(b.n_faces(), 1u);
  EXPECT_DOUBLE_EQ(bounding_box(b).largest_side(), 20.0);

  const auto bin_stl = dir / "bin.stl";
  {
    std::ofstream out(bin_stl, std::ios::binary);
    char header[80] = {};
    out.write(header, 80);
    const std::uint32_t count = 1;
    out.write(reinterpret_cast<const char*>(&count), 4);
    const float data[12] = {0, 0, 1, 0, 0, 0, 30, 0, 0, 0, 30, 0};
    out.write(reinterpret_cast<const char*>(data), sizeof data);
    const std::uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
  const PolyMesh s = read_mesh(bin_stl);
  EXPECT_EQ(s.n_faces(), 1u);
  EXPECT_DOUBLE_EQ(bounding_box(s).largest_side(), 30.0);
}

/// A box [-50, 50]^3 as 48 triangles (two per cell of a 2 x 2 grid on each side), faces out.
std::vector<std::array<int, 3>> box_triangles(std::vector<Vec3>& points) {
  const PolyMesh grid = test::cube_grid_mesh(2, [](const Vec3& p) { return Vec3(50 * p); });
  points.clear();
  for (auto v : grid.vertices()) points.push_back(to_eigen(grid.point(v)));
  std::vector<std::array<int, 3>> t;
  for (auto f : grid.faces()) {
    std::vector<int> q;
    for (auto v : f.vertices()) q.push_back(v.idx());
    t.push_back({q[0], q[1], q[2]});
    t.push_back({q[0], q[2], q[3]});
  }
  return t;
}

/// The triangles as an OBJ, those in \p turn with their corners in the other order.
std::string obj_text(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& t,
                     const std::vector<int>& turn) {
  std::ostringstream s;
  for (const Vec3& p : points) s << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (std::size_t i = 0; i < t.size(); ++i) {
    const bool back = std::find(turn.begin(), turn.end(), static_cast<int>(i)) != turn.end();
    s << "f " << t[i][0] + 1 << " " << (back ? t[i][2] : t[i][1]) + 1 << " "
      << (back ? t[i][1] : t[i][2]) + 1 << "\n";
  }
  return s.str();
}

/// Each face's corners as read, starting from its smallest index (the same cycle compares equal
/// wherever it starts).
std::vector<std::vector<int>> cycles(const PolyMesh& m) {
  std::vector<std::vector<int>> out;
  for (auto f : m.faces()) {
    std::vector<int> c;
    for (auto v : f.vertices()) c.push_back(v.idx());
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.push_back(c);
  }
  return out;
}

double signed_volume_of(const PolyMesh& m) {
  double v = 0;
  for (auto f : m.faces()) {
    std::vector<Vec3> c;
    for (auto x : f.vertices()) c.push_back(to_eigen(m.point(x)));
    for (std::size_t k = 1; k + 1 < c.size(); ++k) v += c[0].dot(c[k].cross(c[k + 1])) / 6;
  }
  return v;
}

// An STL or OBJ exported with some faces the wrong way round (their neighbours walk the edges
// they share the same way) was refused as "not manifold". Its faces are turned round: the mesh
// read is the one the file with all faces agreeing gives, face for face, closed, facing out.
TEST(MeshIo, FacesTurnedAgainstTheirNeighboursAreTurnedRound) {
  const auto dir = fresh_dir();
  std::vector<Vec3> points;
  const auto t = box_triangles(points);
  ASSERT_EQ(t.size(), 48u);
  MeshRepairs clean_repairs{.faces_turned = -1};
  const PolyMesh clean =
      read_mesh(write_text(dir / "clean.obj", obj_text(points, t, {})), &clean_repairs);
  EXPECT_EQ(clean_repairs.faces_turned, 0);
  const std::vector<int> some = {0, 5, 17, 30, 47};
  MeshRepairs repairs;
  const PolyMesh mixed =
      read_mesh(write_text(dir / "mixed.obj", obj_text(points, t, some)), &repairs);
  EXPECT_EQ(repairs.faces_turned, 5);
  EXPECT_EQ(mixed.n_vertices(), clean.n_vertices());
  EXPECT_EQ(cycles(mixed), cycles(clean));
  EXPECT_EQ(boundary_loop_count(mixed), 0);
  EXPECT_NEAR(signed_volume_of(mixed), 100.0 * 100 * 100, 1e-6);

  // All but two faces inward: the closed box is turned to face out (46 turned, not 2).
  std::vector<int> most;
  for (int i = 0; i < 48; ++i)
    if (i != 3 && i != 20) most.push_back(i);
  const PolyMesh inward =
      read_mesh(write_text(dir / "inward.obj", obj_text(points, t, most)), &repairs);
  EXPECT_EQ(repairs.faces_turned, 46);
  EXPECT_EQ(cycles(inward), cycles(clean));

  // A binary STL soup of the mixed box: welded (26 vertices) and turned.
  const auto stl = dir / "mixed.stl";
  {
    std::ofstream out(stl, std::ios::binary);
    char header[80] = {};
    out.write(header, 80);
    const auto count = static_cast<std::uint32_t>(t.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (std::size_t i = 0; i < t.size(); ++i) {
      const bool back = std::find(some.begin(), some.end(), static_cast<int>(i)) != some.end();
      const std::array<int, 3> c = back ? std::array{t[i][0], t[i][2], t[i][1]} : t[i];
      float data[12] = {};
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) data[3 + 3 * k + d] = static_cast<float>(points[c[k]][d]);
      out.write(reinterpret_cast<const char*>(data), sizeof data);
      const std::uint16_t attr = 0;
      out.write(reinterpret_cast<const char*>(&attr), 2);
    }
  }
  const PolyMesh from_stl = read_mesh(stl, &repairs);
  EXPECT_EQ(repairs.faces_turned, 5);
  EXPECT_EQ(from_stl.n_vertices(), 26u);
  EXPECT_EQ(from_stl.n_faces(), 48u);
  EXPECT_EQ(boundary_loop_count(from_stl), 0);
  EXPECT_NEAR(signed_volume_of(from_stl), 100.0 * 100 * 100, 1e-3);
}

// An open piece has no outside: it keeps the way most of its faces came (the fewest turned).
TEST(MeshIo, AnOpenPieceKeepsTheWayMostOfItsFacesCame) {
  std::vector<Vec3> points;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) points.emplace_back(10.0 * i, 10.0 * j, 0);
  std::vector<std::vector<int>> up;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = 4 * j + i;
      up.push_back({a, a + 1, a + 5});
      up.push_back({a, a + 5, a + 4});
    }
  for (const int flipped : {4, 14}) {
    auto faces = up;
    for (int f = 0; f < flipped; ++f) std::reverse(faces[f].begin(), faces[f].end());
    const OrientedFaces o = orient_consistently(points, faces, "grid");
    EXPECT_EQ(o.turned, std::min(flipped, 18 - flipped)) << flipped;
    EXPECT_EQ(o.components, 1);
    // Every face now turns the same way: all up (4 given turned) or all down (14).
    const double sign = flipped < 9 ? 1 : -1;
    for (const auto& c : o.faces)
      EXPECT_GT(sign * (points[c[1]] - points[c[0]]).cross(points[c[2]] - points[c[0]]).z(), 0);
  }
}

// What no turning mends is refused with one line naming it: a one-sided surface, an edge on
// three faces, two pieces meeting at a single vertex.
// Faces with a colour of whole numbers after their corners, as OFF allows ("4 0 1 3 2 255 0 0"):
// OpenMesh's reader took the colours for corners of the faces after them, and a coloured cube
// was refused for 4 faces that repeat a vertex (with an alpha, 5 out-of-range indices). The
// colours are left out: the cube as without them, corner for corner.
TEST(MeshIo, OffFacesWithColoursReadAsWithout) {
  const auto dir = fresh_dir();
  std::string points =
      "0 0 0\n0 0 100\n0 100 0\n0 100 100\n100 0 0\n100 0 100\n100 100 0\n"
      "100 100 100\n";
  const std::vector<std::string> faces = {"0 1 3 2", "4 6 7 5", "0 4 5 1",
                                          "2 3 7 6", "0 2 6 4", "1 5 7 3"};
  std::vector<std::vector<std::vector<int>>> read;
  for (const std::string colour : {"", " 255 0 0", " 255 0 0 255", " 0.5 0.5 0.5"}) {
    std::string text = "OFF\n8 6 0\n" + points;
    for (const std::string& f : faces) text += "4 " + f + colour + "\n";
    const PolyMesh m = read_mesh(write_text(dir / "cube.off", text));
    EXPECT_EQ(m.n_vertices(), 8u) << colour;
    EXPECT_EQ(boundary_loop_count(m), 0) << colour;
    read.push_back(cycles(m));
  }
  for (std::size_t k = 1; k < read.size(); ++k) EXPECT_EQ(read[k], read[0]) << k;
}

// An OBJ whose faces each have their own corners (a triangle soup, as some exporters write
// flat-shaded meshes; or vertices split at texture seams) was read as loose triangles: a box
// was cut as 12 parts with no joint between them. Border vertices at exactly the same point
// are welded where that gives a mesh, and a face repeating another's corners (either way
// round) is dropped instead of refusing the file as "not manifold"; two borders that touch
// at a point only are read as they stand.
TEST(MeshIo, ASoupIsWeldedAndRepeatedFacesAreDropped) {
  const auto dir = fresh_dir();
  std::vector<Vec3> points;
  const auto t = box_triangles(points);
  std::ostringstream soup;
  for (const auto& f : t) {
    for (int c : f)
      soup << "v " << points[c].x() << " " << points[c].y() << " " << points[c].z() << "\n";
    soup << "f -3 -2 -1\n";
  }
  MeshRepairs repairs;
  const PolyMesh welded = read_mesh(write_text(dir / "soup.obj", soup.str()), &repairs);
  EXPECT_EQ(welded.n_vertices(), points.size());
  EXPECT_EQ(welded.n_faces(), 48u);
  EXPECT_EQ(repairs.vertices_welded, static_cast<int>(3 * t.size() - points.size()));
  EXPECT_EQ(repairs.faces_turned, 0);
  EXPECT_EQ(boundary_loop_count(welded), 0);
  EXPECT_NEAR(signed_volume_of(welded), 100.0 * 100 * 100, 1e-6);

  // The box with its first face twice and its second once more the other way round.
  std::string twice = obj_text(points, t, {});
  twice += "f " + std::to_string(t[0][0] + 1) + " " + std::to_string(t[0][1] + 1) + " " +
           std::to_string(t[0][2] + 1) + "\nf " + std::to_string(t[1][0] + 1) + " " +
           std::to_string(t[1][2] + 1) + " " + std::to_string(t[1][1] + 1) + "\n";
  const PolyMesh dropped = read_mesh(write_text(dir / "twice.obj", twice), &repairs);
  EXPECT_EQ(repairs.duplicate_faces, 2);
  EXPECT_EQ(repairs.vertices_welded, 0);
  EXPECT_EQ(dropped.n_faces(), 48u);
  EXPECT_EQ(boundary_loop_count(dropped), 0);
  EXPECT_NEAR(signed_volume_of(dropped), 100.0 * 100 * 100, 1e-6);

  // Two triangles whose corners 1 and 4 lie at one point: welded, they would meet only there.
  const PolyMesh apart = read_mesh(
      write_text(dir / "touch.obj",
                 "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 0\nv -10 0 0\nv 0 -10 0\nf 1 2 3\nf 4 5 6\n"),
      &repairs);
  EXPECT_EQ(apart.n_vertices(), 6u);
  EXPECT_EQ(apart.n_faces(), 2u);
  EXPECT_EQ(repairs.vertices_welded, 0);
}

TEST(MeshIo, OneSidedSurfacesAndNonManifoldPlacesAreRefused) {
  const auto dir = fresh_dir();
  std::ostringstream mobius;
  const int n = 24;
  for (int i = 0; i < n; ++i)
    for (const double s : {-1.0, 1.0}) {
      const double u = 2 * M_PI * i / n, r = 100 + 30 * s * std::cos(u / 2);
      mobius << "v " << r * std::cos(u) << " " << r * std::sin(u) << " " << 30 * s * std::sin(u / 2)
             << "\n";
    }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i + 1, b = 2 * i + 2;
    const int c = i + 1 < n ? 2 * i + 4 : 1, d = i + 1 < n ? 2 * i + 3 : 2;  // joined half-turned
    mobius << "f " << a << " " << d << " " << c << "\nf " << a << " " << c << " " << b << "\n";
  }
  const auto says = [&](const std::string& name, const std::string& text, const std::string& what) {
    try {
      read_mesh(write_text(dir / name, text));
      ADD_FAILURE() << name << " was read";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  says("mobius.obj", mobius.str(), "not orientable");
  says("fin.obj", "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 -10 0\nv 0 0 10\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
       "edge(s) shared by more than two faces");
  // Two tetrahedra touching at vertex 1, one face of the second turned.
  says("bowtie.obj",
       "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nv -10 0 0\nv 0 -10 0\nv 0 0 -10\n"
       "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 5 6\nf 1 7 5\nf 1 6 7\nf 5 7 6\n",
       "non-manifold vertex");
}

TEST(MeshIo, MissingUnreadableAndUnknownFormatAreIoErrors) {
  const auto dir = fresh_dir();
  EXPECT_THROW(read_mesh(dir / "nope.obj"), IoError);
  EXPECT_THROW(read_mesh(dir), IoError);
  EXPECT_THROW(read_mesh(write_text(dir / "mesh.xyz", "1 2 3\n")), IoError);
  EXPECT_THROW(read_mesh(write_text(dir / "garbage.ply", "this is not a ply file\n")), IoError);
}

TEST(MeshIo, EmptyNonManifoldAndRepeatedVertexAreInvalidInput) {
  const auto dir = fresh_dir();
  EXPECT_THROW(read_mesh(write_text(dir / "empty.obj", "v 0 0 0\nv 1 0 0\n")), InvalidInput);
  EXPECT_THROW(read_mesh(write_text(dir / "empty2.obj", "")), InvalidInput);
  // Three triangles on one edge.
  EXPECT_THROW(read_mesh(write_text(dir / "fin.obj",
                                    "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 -10 0\nv 0 0 10\n"
                                    "f 1 2 3\nf 2 1 4\nf 1 2 5\n")),
               InvalidInput);
  EXPECT_THROW(read_mesh(write_text(dir / "rep.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n")),
               InvalidInput);
  try {
    read_mesh(dir / "fin.obj");
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("not manifold"), std::string::npos) << e.what();
  }
}

TEST(MeshIo, KeepsFileVertexIndicesIncludingIsolatedVertices) {
  const auto dir = fresh_dir();
  const PolyMesh m = read_mesh(write_text(dir / "iso.obj",
                                          "v 5 5 5\nv 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\n"
                                          "f 2 3 4 5\n"));
  EXPECT_EQ(m.n_vertices(), 5u);
  auto corners = quad_vertices(m, *m.faces_begin());  // same cycle, possibly rotated
  std::rotate(corners.begin(), std::find(corners.begin(), corners.end(), 1), corners.end());
  EXPECT_EQ(corners, (std::array<int, 4>{1, 2, 3, 4}));
  EXPECT_DOUBLE_EQ(bounding_box(m).largest_side(), 10.0);  // isolated vertex ignored
}

}  // namespace
}  // namespace kerfab

#include "kerfab/io/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "kerfab/core/errors.h"
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

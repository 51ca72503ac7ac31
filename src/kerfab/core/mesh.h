#pragma once
/// \file Mesh types shared by all stages: an OpenMesh polygon mesh in double precision,
/// a plain indexed triangle mesh for queries, and small geometry helpers.
#include <Eigen/Geometry>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace kerfab {

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};

/// Polygon mesh (halfedge structure), coordinates in millimetres once prepared.
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<MeshTraits>;

using Vec3 = Eigen::Vector3d;

inline Vec3 to_eigen(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
inline OpenMesh::Vec3d to_openmesh(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

/// One key for the edge between vertices \p a and \p b, whichever way it is walked.
inline std::uint64_t undirected_edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// Indexed triangle mesh, the form the closest-point and distance queries take.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Axis-aligned bounding box.
struct BoundingBox {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());
  Vec3 size() const { return (max - min).cwiseMax(0.0); }
  double diagonal() const { return size().norm(); }
  double largest_side() const { return size().maxCoeff(); }
};

/// Bounding box of the vertices referenced by faces (isolated vertices are ignored).
BoundingBox bounding_box(const PolyMesh& mesh);

/// Bounding box of a triangle mesh's vertices.
BoundingBox bounding_box(const TriangleMesh& mesh);

/// Triangulates every face of \p mesh: triangles and quads by the fan from the face's first
/// vertex, larger polygons by ear clipping (triangulate_polygon), which is exact for non-convex
/// ones too (CAD exports and modellers' n-gons). Vertex indices are those of \p mesh.
TriangleMesh triangulate(const PolyMesh& mesh);

/// Appends to \p out the triangles of the polygon whose corners are \p ids (indices into
/// \p points, in order): ear clipping in the plane of its Newell normal, each step taking the
/// first ear from the polygon's second corner on, so a convex polygon gives the fan from its
/// first corner. A polygon with no ear left (self-intersecting, or of no area) has the rest
/// fanned.
void triangulate_polygon(const std::vector<Vec3>& points, const std::vector<int>& ids,
                         std::vector<std::array<int, 3>>& out);

/// \p mesh without its triangles of no area (a cross product of their edges under 1e-12 mm^2):
/// what a closest-point query (TargetSurface) cannot take, and contributes no surface. The
/// vertices are kept as they are.
TriangleMesh without_degenerate(const TriangleMesh& mesh);

/// Counts of faces by their number of sides, e.g. {3: 4, 4: 160, 5: 16}.
std::vector<std::pair<int, int>> face_size_histogram(const PolyMesh& mesh);

/// True when every face has exactly four sides (and there is at least one face).
bool is_all_quads(const PolyMesh& mesh);

/// True when every face has exactly three sides (and there is at least one face).
bool is_all_triangles(const PolyMesh& mesh);

/// Number of boundary loops.
int boundary_loop_count(const PolyMesh& mesh);

/// The four edges of quad \p f, in order, starting from the face's first halfedge.
/// Edge k joins local corners k and k+1; edges k and k+2 are opposite. \pre f is a quad.
std::array<int, 4> quad_edges(const PolyMesh& mesh, OpenMesh::FaceHandle f);

/// The four vertices of quad \p f, corner k being the start of local edge k. \pre f is a quad.
std::array<int, 4> quad_vertices(const PolyMesh& mesh, OpenMesh::FaceHandle f);

/// Angle between two vectors [rad], accurate near 0 and pi.
double angle_between(const Vec3& a, const Vec3& b);

/// The point of the segment from \p a to \p b nearest to \p p (\p a where they coincide).
Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);

/// The triangles \p triangles (indices) of \p mesh as a mesh of their own, their vertices
/// numbered as first met.
TriangleMesh sub_mesh(const TriangleMesh& mesh, const std::vector<int>& triangles);

/// How many triangles of \p mesh have each edge (vertex index pair, the smaller first).
std::map<std::pair<int, int>, int> edge_uses(const TriangleMesh& mesh);

/// The edges (vertex index pairs, the smaller first, ascending) that one triangle of \p mesh
/// alone has.
std::vector<std::array<int, 2>> border_edges(const TriangleMesh& mesh);

/// Unit normal of quad \p f (vertex ids into \p points) at its corner holding vertex \p v;
/// zero when that corner is degenerate or \p v is not a corner of \p f.
Vec3 corner_normal(const std::vector<Vec3>& points, const std::array<int, 4>& f, int v);

/// The sector normal: corner_normal, or where that corner is degenerate the quad's normal from
/// its diagonals, or +z when the quad has no area at all.
Vec3 sector_normal(const std::vector<Vec3>& points, const std::array<int, 4>& f, int v);

}  // namespace kerfab

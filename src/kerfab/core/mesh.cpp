#include "kerfab/core/mesh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>

namespace kerfab {

BoundingBox bounding_box(const PolyMesh& mesh) {
  BoundingBox box;
  for (auto f : mesh.faces()) {
    for (auto v : mesh.fv_range(f)) {
      const Vec3 p = to_eigen(mesh.point(v));
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    }
  }
  return box;
}

BoundingBox bounding_box(const TriangleMesh& mesh) {
  BoundingBox box;
  for (const Vec3& p : mesh.vertices) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

TriangleMesh without_degenerate(const TriangleMesh& mesh) {
  TriangleMesh out;
  out.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t[0]];
    if ((mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm() > 1e-12)
      out.triangles.push_back(t);
  }
  return out;
}

TriangleMesh triangulate(const PolyMesh& mesh) {
  TriangleMesh tri;
  tri.vertices.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) tri.vertices.push_back(to_eigen(mesh.point(v)));
  for (auto f : mesh.faces()) {
    std::vector<int> ids;
    for (auto v : mesh.fv_range(f)) ids.push_back(v.idx());
    for (std::size_t k = 1; k + 1 < ids.size(); ++k)
      tri.triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  return tri;
}

std::vector<std::pair<int, int>> face_size_histogram(const PolyMesh& mesh) {
  std::map<int, int> counts;
  for (auto f : mesh.faces()) ++counts[static_cast<int>(mesh.valence(f))];
  return {counts.begin(), counts.end()};
}

bool is_all_quads(const PolyMesh& mesh) {
  if (mesh.n_faces() == 0) return false;
  for (auto f : mesh.faces())
    if (mesh.valence(f) != 4) return false;
  return true;
}

bool is_all_triangles(const PolyMesh& mesh) {
  if (mesh.n_faces() == 0) return false;
  for (auto f : mesh.faces())
    if (mesh.valence(f) != 3) return false;
  return true;
}

int boundary_loop_count(const PolyMesh& mesh) {
  std::vector<char> seen(mesh.n_halfedges(), 0);
  int loops = 0;
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || seen[h.idx()]) continue;
    ++loops;
    auto cur = h;
    do {
      seen[cur.idx()] = 1;
      cur = mesh.next_halfedge_handle(cur);
    } while (cur != h && !seen[cur.idx()]);
  }
  return loops;
}

std::array<int, 4> quad_edges(const PolyMesh& mesh, OpenMesh::FaceHandle f) {
  assert(mesh.valence(f) == 4 && "quad_edges needs a quad");
  std::array<int, 4> edges{};
  auto h = mesh.halfedge_handle(f);
  for (int k = 0; k < 4; ++k) {
    edges[k] = mesh.edge_handle(h).idx();
    h = mesh.next_halfedge_handle(h);
  }
  return edges;
}

std::array<int, 4> quad_vertices(const PolyMesh& mesh, OpenMesh::FaceHandle f) {
  assert(mesh.valence(f) == 4 && "quad_vertices needs a quad");
  std::array<int, 4> verts{};
  auto h = mesh.halfedge_handle(f);
  for (int k = 0; k < 4; ++k) {
    verts[k] = mesh.from_vertex_handle(h).idx();
    h = mesh.next_halfedge_handle(h);
  }
  return verts;
}

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return a + t * d;
}

Vec3 corner_normal(const std::vector<Vec3>& points, const std::array<int, 4>& f, int v) {
  for (int j = 0; j < 4; ++j) {
    if (f[j] != v) continue;
    const Vec3& p = points[v];
    const Vec3 n = (points[f[(j + 1) % 4]] - p).cross(points[f[(j + 3) % 4]] - p);
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
  }
  return Vec3::Zero();
}

Vec3 sector_normal(const std::vector<Vec3>& points, const std::array<int, 4>& f, int v) {
  const Vec3 n = corner_normal(points, f, v);
  if (!n.isZero()) return n;
  const Vec3 d = (points[f[2]] - points[f[0]]).cross(points[f[3]] - points[f[1]]);
  return d.norm() > 0 ? Vec3(d.normalized()) : Vec3::UnitZ();
}

}  // namespace kerfab

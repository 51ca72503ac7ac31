#include "kerfab/core/mesh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <unordered_map>

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
    if (ids.size() > 4) {
      triangulate_polygon(tri.vertices, ids, tri.triangles);
      continue;
    }
    for (std::size_t k = 1; k + 1 < ids.size(); ++k)
      tri.triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  return tri;
}

void triangulate_polygon(const std::vector<Vec3>& points, const std::vector<int>& ids,
                         std::vector<std::array<int, 3>>& out) {
  const std::size_t m = ids.size();
  Vec3 normal = Vec3::Zero();  // Newell: twice the area vector
  for (std::size_t k = 0; k < m; ++k) normal += points[ids[k]].cross(points[ids[(k + 1) % m]]);
  std::vector<int> rest(m);  // corners left, as places in ids
  for (std::size_t k = 0; k < m; ++k) rest[k] = static_cast<int>(k);
  if (normal.norm() > 0) {
    const Vec3 n = normal.normalized();
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    std::vector<Eigen::Vector2d> flat(m);
    for (std::size_t k = 0; k < m; ++k) flat[k] = {points[ids[k]].dot(u), points[ids[k]].dot(v)};
    auto turn = [&](int a, int b, int c) {  // > 0: a, b, c turn the polygon's way
      const Eigen::Vector2d e = flat[b] - flat[a], g = flat[c] - flat[a];
      return e.x() * g.y() - e.y() * g.x();
    };
    const double tiny = 1e-12 * normal.norm();
    while (rest.size() > 3) {
      const std::size_t r = rest.size();
      bool clipped = false;
      for (std::size_t step = 1; step <= r && !clipped; ++step) {
        const std::size_t i = step % r;
        const int a = rest[(i + r - 1) % r], b = rest[i], c = rest[(i + 1) % r];
        if (turn(a, b, c) <= tiny) continue;  // reflex or flat: no ear
        bool empty = true;
        for (int q : rest) {
          if (q == a || q == b || q == c) continue;
          if (turn(a, b, q) >= 0 && turn(b, c, q) >= 0 && turn(c, a, q) >= 0) {
            empty = false;
            break;
          }
        }
        if (!empty) continue;
        out.push_back({ids[a], ids[b], ids[c]});
        rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
      if (!clipped) break;
    }
  }
  for (std::size_t k = 1; k + 1 < rest.size(); ++k)
    out.push_back({ids[rest[0]], ids[rest[k]], ids[rest[k + 1]]});
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

TriangleMesh sub_mesh(const TriangleMesh& mesh, const std::vector<int>& triangles) {
  TriangleMesh out;
  std::unordered_map<int, int> index;
  for (int i : triangles) {
    std::array<int, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[i][k];
      const auto [it, added] = index.try_emplace(v, static_cast<int>(out.vertices.size()));
      if (added) out.vertices.push_back(mesh.vertices[v]);
      t[k] = it->second;
    }
    out.triangles.push_back(t);
  }
  return out;
}

std::map<std::pair<int, int>, int> edge_uses(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  return uses;
}

std::vector<std::array<int, 2>> border_edges(const TriangleMesh& mesh) {
  std::vector<std::array<int, 2>> out;
  for (const auto& [edge, n] : edge_uses(mesh))
    if (n == 1) out.push_back({edge.first, edge.second});
  return out;
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

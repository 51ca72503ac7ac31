#include "kerfab/quads/sweep.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace kerfab::quads {
namespace {

/// \p mesh as an extrusion along \p axis, where it is one (find_extrusion's conditions).
/// \p uses: the mesh's edge_uses(), counted on first need (most shapes fail before).
std::optional<Extrusion> extrusion_along(const TriangleMesh& mesh, const Vec3& axis,
                                         const std::vector<Vec3>& normals,
                                         const std::vector<double>& areas, double same_height,
                                         std::optional<std::map<std::pair<int, int>, int>>& uses) {
  const double cos_tol = std::cos(kAxisTolerance), sin_tol = std::sin(kAxisTolerance);
  std::vector<int> up, down;
  Extrusion e;
  e.axis = axis;
  double up_area = 0, down_area = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const double d = normals[t].dot(axis);
    if (d > cos_tol) {
      up.push_back(static_cast<int>(t));
      up_area += areas[t];
    } else if (d < -cos_tol) {
      down.push_back(static_cast<int>(t));
      down_area += areas[t];
    } else if (std::abs(d) < sin_tol) {
      e.wall_area += areas[t];
    } else {
      return std::nullopt;  // neither a cap nor the wall
    }
  }
  if ((up.empty() && down.empty()) || !(e.wall_area > 0)) return std::nullopt;
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  for (const Vec3& v : mesh.vertices) {
    lowest = std::min(lowest, v.dot(axis));
    highest = std::max(highest, v.dot(axis));
  }
  // Every corner of a cap at the end it closes.
  const auto at_height = [&](const std::vector<int>& cap, double height) {
    for (int t : cap)
      for (int v : mesh.triangles[t])
        if (std::abs(mesh.vertices[v].dot(axis) - height) > same_height) return false;
    return true;
  };
  if (!at_height(up, highest) || !at_height(down, lowest)) return std::nullopt;
  e.bottom = lowest;
  e.top = highest;
  e.top_cap = !up.empty();
  e.bottom_cap = !down.empty();
  if (!(e.top - e.bottom > 100 * same_height)) return std::nullopt;
  // Borders only where a cap is missing: a rim at that end.
  if (!uses) uses = edge_uses(mesh);
  for (const auto& [edge, n] : *uses) {
    if (n == 2) continue;
    if (n != 1) return std::nullopt;
    for (int v : {edge.first, edge.second}) {
      const double h = mesh.vertices[v].dot(axis);
      const bool open_top = !e.top_cap && std::abs(h - e.top) <= same_height;
      const bool open_bottom = !e.bottom_cap && std::abs(h - e.bottom) <= same_height;
      if (!open_top && !open_bottom) return std::nullopt;
    }
  }
  // The same outline at both ends.
  if (e.top_cap && e.bottom_cap && std::abs(up_area - down_area) > 1e-3 * up_area)
    return std::nullopt;
  e.cap_on_top = e.top_cap;
  e.cap = sub_mesh(mesh, e.cap_on_top ? up : down);
  e.cap_area = e.cap_on_top ? up_area : down_area;
  return e;
}

}  // namespace

std::optional<Extrusion> find_extrusion(const TriangleMesh& mesh) {
  const int nt = static_cast<int>(mesh.triangles.size());
  if (nt < 4) return std::nullopt;
  std::vector<Vec3> normals(nt);
  std::vector<double> areas(nt);
  const BoundingBox box = bounding_box(mesh);
  if (!(box.min.allFinite() && box.max.allFinite())) return std::nullopt;
  const double same_height = kSameHeight * box.diagonal();
  // Candidate axes: the directions the most area faces (either way), a cap's among them.
  struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const {
      return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
    }
  };
  std::unordered_map<std::array<long long, 3>, std::pair<double, Vec3>, KeyHash> by_direction;
  for (int t = 0; t < nt; ++t) {
    const auto& tr = mesh.triangles[t];
    const Vec3 c = (mesh.vertices[tr[1]] - mesh.vertices[tr[0]])
                       .cross(mesh.vertices[tr[2]] - mesh.vertices[tr[0]]);
    areas[t] = 0.5 * c.norm();
    if (!(areas[t] > 0)) return std::nullopt;
    normals[t] = c.normalized();
    Vec3 n = normals[t];
    for (int k = 0; k < 3; ++k)  // one sign for both ways
      if (std::abs(n[k]) > 1e-9) {
        if (n[k] < 0) n = -n;
        break;
      }
    const std::array<long long, 3> key = {std::llround(n.x() * 1e3), std::llround(n.y() * 1e3),
                                          std::llround(n.z() * 1e3)};
    auto& [area, dir] = by_direction[key];
    if (area == 0) dir = n;
    area += areas[t];
  }
  // Most area first; equal areas (a cube's faces) in the order of their directions' keys, so
  // that the axis taken never depends on the hash table's order.
  std::vector<std::tuple<double, std::array<long long, 3>, Vec3>> candidates;
  for (const auto& [key, entry] : by_direction)
    candidates.emplace_back(entry.first, key, entry.second);
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
    return std::get<1>(a) < std::get<1>(b);
  });
  if (candidates.size() > 4) candidates.resize(4);
  std::optional<std::map<std::pair<int, int>, int>> uses;
  std::optional<Extrusion> best;
  for (const auto& [area, key, dir] : candidates) {
    std::optional<Extrusion> e = extrusion_along(mesh, dir, normals, areas, same_height, uses);
    if (e && (!best || e->cap_area > best->cap_area)) best = std::move(e);
  }
  return best;
}

PolyMesh sweep_extrusion(const PolyMesh& cap, const Extrusion& e, int rows,
                         std::vector<std::array<int, 2>>* along_rims,
                         std::vector<std::array<int, 2>>* along_axis) {
  PolyMesh out;
  if (rows < 1 || cap.n_faces() == 0) return out;
  const double from = e.cap_on_top ? e.top : e.bottom, to = e.cap_on_top ? e.bottom : e.top;
  const Vec3 d = (to - from) * e.axis;
  const bool other_cap = e.cap_on_top ? e.bottom_cap : e.top_cap;
  using VH = OpenMesh::VertexHandle;
  // The faces below are made as if the cap faced out of the solid (its triangles' way, along
  // the axis at the top, against it at the bottom); where it faces in, each is turned.
  Vec3 facing = Vec3::Zero();  // Newell's sum over the cap's faces
  for (auto f : cap.faces()) {
    std::vector<Vec3> p;
    for (auto v : cap.fv_range(f)) p.push_back(to_eigen(cap.point(v)));
    for (std::size_t i = 0; i < p.size(); ++i) facing += p[i].cross(p[(i + 1) % p.size()]);
  }
  const bool inward = facing.dot(e.cap_on_top ? e.axis : Vec3(-e.axis)) < 0;
  const int n = static_cast<int>(cap.n_vertices());
  // Row j of the cap's vertices, moved by j / rows of the way: the border in every row, the
  // inner vertices in the first and (a cap there) the last.
  std::vector<std::vector<VH>> at(rows + 1, std::vector<VH>(n));
  for (auto v : cap.vertices()) {
    const Vec3 p = to_eigen(cap.point(v));
    at[0][v.idx()] = out.add_vertex(to_openmesh(p));
    for (int j = 1; j <= rows; ++j)
      if (cap.is_boundary(v) || (j == rows && other_cap))
        at[j][v.idx()] = out.add_vertex(to_openmesh(p + (static_cast<double>(j) / rows) * d));
  }
  const auto add = [&](std::vector<VH> corners, bool turned) {
    if (turned != inward) std::reverse(corners.begin(), corners.end());
    return out.add_face(corners).is_valid();
  };
  // The cap in row \p row, turned there (the other end's copy faces the other way).
  const auto add_cap = [&](int row, bool turned) {
    for (auto f : cap.faces()) {
      std::vector<VH> corners;
      for (auto v : cap.fv_range(f)) corners.push_back(at[row][v.idx()]);
      if (!add(corners, turned)) return false;
    }
    return true;
  };
  if (!add_cap(0, false)) return PolyMesh();
  // A border halfedge u -> v of the cap (no face on it; the cap's face runs v -> u) starts a
  // column of the wall, each of its quads running u -> v along its upper rim.
  for (auto h : cap.halfedges()) {
    if (!cap.is_boundary(h)) continue;
    const int u = cap.from_vertex_handle(h).idx(), v = cap.to_vertex_handle(h).idx();
    for (int j = 0; j < rows; ++j)
      if (!add({at[j][u], at[j][v], at[j + 1][v], at[j + 1][u]}, false)) return PolyMesh();
    if (along_rims)
      for (int j = 1; j < rows; ++j) along_rims->push_back({at[j][u].idx(), at[j][v].idx()});
    if (along_axis)
      for (int j = 0; j < rows; ++j) along_axis->push_back({at[j][u].idx(), at[j + 1][u].idx()});
  }
  if (other_cap && !add_cap(rows, true)) return PolyMesh();
  return out;
}

}  // namespace kerfab::quads

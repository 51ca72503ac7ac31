#include "kerfab/input/prepare.h"

#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "kerfab/adapters/solid_union.h"
#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

std::string face_size_text(const PolyMesh& mesh) {
  std::ostringstream os;
  bool first = true;
  for (auto [sides, count] : face_size_histogram(mesh)) {
    os << (first ? "" : ", ") << count << " ";
    switch (sides) {
      case 3:
        os << "triangle" << (count > 1 ? "s" : "");
        break;
      case 4:
        os << "quad" << (count > 1 ? "s" : "");
        break;
      default:
        os << sides << "-gon" << (count > 1 ? "s" : "");
        break;
    }
    first = false;
  }
  return os.str();
}

MeshSummary summarize(const PolyMesh& mesh) {
  MeshSummary s;
  int referenced = 0;
  for (auto v : mesh.vertices()) referenced += mesh.is_isolated(v) ? 0 : 1;
  s.vertices = referenced;
  s.faces = static_cast<int>(mesh.n_faces());
  s.edges = static_cast<int>(mesh.n_edges());
  s.boundary_loops = boundary_loop_count(mesh);
  s.euler_characteristic = s.vertices - s.edges + s.faces;
  s.face_sizes = face_size_histogram(mesh);
  s.bbox = bounding_box(mesh);
  return s;
}

/// Area of polygon face \p f (the length of its area vector: exact for planar faces, a fair
/// measure otherwise) [input units squared].
double face_area(const PolyMesh& mesh, OpenMesh::FaceHandle f) {
  OpenMesh::Vec3d area(0, 0, 0);
  const auto p0 = mesh.point(mesh.from_vertex_handle(mesh.halfedge_handle(f)));
  for (auto h : mesh.fh_range(f)) {
    const auto a = mesh.point(mesh.from_vertex_handle(h)) - p0;
    const auto b = mesh.point(mesh.to_vertex_handle(h)) - p0;
    area += OpenMesh::cross(a, b);
  }
  return 0.5 * area.norm();
}

/// Faces of no area count as none below this fraction of the squared bbox diagonal [-].
constexpr double kZeroArea = 1e-12;
/// Faces of no area mended at most (mend_zero_area_faces) [-].
constexpr int kMaxMended = 10000;

/// Collapses every zero-area quad of \p mesh whose opposite corners coincide (a doublet, as
/// general remeshers leave behind: two distinct vertices at one point) along that diagonal: the
/// two corners become one vertex, the quad goes and its two pairs of sides become two edges.
/// The surface and its Euler characteristic stay as they were. Returns the faces collapsed,
/// numbered as in the file; zero-area faces of any other kind stay (check_geometry refuses them).
std::vector<int> collapse_doublets(PolyMesh& mesh) {
  const double diag = bounding_box(mesh).diagonal();
  if (!(diag > 0)) return {};
  const double min_area = kZeroArea * diag * diag, same = 1e-9 * diag;
  std::vector<int> into(mesh.n_vertices());
  for (std::size_t v = 0; v < into.size(); ++v) into[v] = static_cast<int>(v);
  auto root = [&](int v) {
    while (into[v] != v) v = into[v];
    return v;
  };
  std::vector<int> collapsed;
  for (auto f : mesh.faces()) {
    if (mesh.valence(f) != 4 || face_area(mesh, f) > min_area) continue;
    const auto c = quad_vertices(mesh, f);
    auto at = [&](int i) { return mesh.point(mesh.vertex_handle(c[i % 4])); };
    for (int k = 0; k < 2; ++k) {
      const int a = root(c[k]), b = root(c[k + 2]);
      if (a == b) break;
      // Corners k and k + 2 at one point, the other two apart from it and from each other.
      if ((at(k) - at(k + 2)).norm() > same || (at(k + 1) - at(k)).norm() <= same ||
          (at(k + 3) - at(k)).norm() <= same || (at(k + 1) - at(k + 3)).norm() <= same)
        continue;
      into[std::max(a, b)] = std::min(a, b);
      collapsed.push_back(f.idx());
      break;
    }
  }
  if (collapsed.empty()) return collapsed;
  PolyMesh out;
  std::vector<OpenMesh::VertexHandle> handle(mesh.n_vertices());
  for (auto v : mesh.vertices()) handle[v.idx()] = out.add_vertex(mesh.point(v));
  std::size_t next = 0;
  for (auto f : mesh.faces()) {
    if (next < collapsed.size() && collapsed[next] == f.idx()) {
      ++next;
      continue;
    }
    std::vector<OpenMesh::VertexHandle> corners;
    for (auto v : mesh.fv_range(f)) corners.push_back(handle[root(v.idx())]);
    if (!out.add_face(corners).is_valid())
      throw InvalidInput("quad mesh face " + std::to_string(f.idx()) +
                         " cannot be kept once the zero-area quads beside it are collapsed");
  }
  // The merged corners stay as isolated vertices: every other vertex keeps its number, so a
  // guidance file written for the mesh as given still names the same vertices.
  mesh = std::move(out);
  return collapsed;
}

/// A quad whose two triangles across a diagonal face away from each other by more than this is
/// folded back onto itself (a dart): no strip bends a quad across its diagonal, and flattened as
/// one plate its corners come out tens of degrees off (QuadriFlow's fandisk_qf800: 175 and 179
/// degrees at a sharp edge, a facet 51 degrees off) [rad].
constexpr double kFoldedBack = 150 * M_PI / 180;

/// The fold of quad corners \p c across the diagonal from corner k to k + 2: the angle between
/// the normals of its two triangles there [rad].
double fold_across(const PolyMesh& mesh, const std::array<int, 4>& c, int k) {
  auto at = [&](int i) {
    const auto p = mesh.point(mesh.vertex_handle(c[i % 4]));
    return Vec3(p[0], p[1], p[2]);
  };
  const Vec3 a = (at(k + 1) - at(k)).cross(at(k + 2) - at(k)),
             b = (at(k + 2) - at(k)).cross(at(k + 3) - at(k));
  if (!(a.norm() > 0) || !(b.norm() > 0)) return 0.0;
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// The vertices of \p mesh (each keeps its number and position) with the polygons \p faces
/// (corner lists). Empty if a face repeats a corner or cannot be added, or the result is not a
/// manifold mesh.
std::optional<PolyMesh> with_faces(const PolyMesh& mesh,
                                   const std::vector<std::vector<int>>& faces) {
  PolyMesh out;
  std::vector<OpenMesh::VertexHandle> handle(mesh.n_vertices());
  for (auto v : mesh.vertices()) handle[v.idx()] = out.add_vertex(mesh.point(v));
  std::vector<OpenMesh::VertexHandle> corners;
  for (const std::vector<int>& c : faces) {
    corners.clear();
    for (std::size_t i = 0; i < c.size(); ++i) {
      for (std::size_t j = i + 1; j < c.size(); ++j)
        if (c[i] == c[j]) return std::nullopt;
      corners.push_back(handle[c[i]]);
    }
    if (!out.add_face(corners).is_valid()) return std::nullopt;
  }
  for (auto v : out.vertices())
    if (!out.is_isolated(v) && !out.is_manifold(v)) return std::nullopt;
  return out;
}

/// \p mesh rebuilt with each face's corners given by \p corners_of (none: the face goes); every
/// vertex keeps its number and position. Empty where with_faces() is.
std::optional<PolyMesh> rebuilt(
    const PolyMesh& mesh, const std::function<std::vector<int>(OpenMesh::FaceHandle)>& corners_of) {
  std::vector<std::vector<int>> faces;
  for (auto f : mesh.faces())
    if (std::vector<int> c = corners_of(f); !c.empty()) faces.push_back(std::move(c));
  return with_faces(mesh, faces);
}

/// \p mesh without face \p drop and with vertex \p from merged into \p into (which moves to
/// \p at); every other vertex keeps its number (\p from stays, isolated). Empty if that is not
/// a manifold mesh.
std::optional<PolyMesh> merged_without(const PolyMesh& mesh, int drop, int from, int into,
                                       const OpenMesh::Vec3d& at) {
  std::optional<PolyMesh> out = rebuilt(mesh, [&](OpenMesh::FaceHandle f) {
    std::vector<int> corners;
    if (f.idx() != drop)
      for (auto v : mesh.fv_range(f)) corners.push_back(v.idx() == from ? into : v.idx());
    return corners;
  });
  if (out) out->set_point(out->vertex_handle(into), at);
  return out;
}

/// \p mesh with the two quads around inner vertex \p v merged into one (a doublet: \p v has
/// valence 2, so the quads share both its edges and each has a corner of about 180 degrees
/// there, or they fold back onto each other). Quads (v, a, x, b) and (v, b, y, a) become
/// (a, x, b, y) in the place of the first; \p v stays, isolated, so every vertex keeps its
/// number. \p second: the face dropped. Empty if \p v is no such vertex, or the merged quad has
/// no area or leaves the mesh non-manifold.
std::optional<PolyMesh> without_doublet(const PolyMesh& mesh, OpenMesh::VertexHandle v,
                                        double min_area, int& second) {
  if (mesh.is_boundary(v) || mesh.valence(v) != 2) return std::nullopt;
  std::vector<OpenMesh::FaceHandle> around;
  for (auto f : mesh.vf_range(v)) around.push_back(f);
  if (around.size() != 2 || around[0] == around[1] || mesh.valence(around[0]) != 4 ||
      mesh.valence(around[1]) != 4)
    return std::nullopt;
  auto from_v = [&](OpenMesh::FaceHandle f) {  // corners of f starting at v
    const auto c = quad_vertices(mesh, f);
    const int at = static_cast<int>(std::find(c.begin(), c.end(), v.idx()) - c.begin());
    return std::array<int, 4>{c[at % 4], c[(at + 1) % 4], c[(at + 2) % 4], c[(at + 3) % 4]};
  };
  const auto p = from_v(around[0]), q = from_v(around[1]);
  if (q[1] != p[3] || q[3] != p[1]) return std::nullopt;
  std::optional<PolyMesh> out = rebuilt(mesh, [&](OpenMesh::FaceHandle f) {
    if (f == around[1]) return std::vector<int>{};
    if (f == around[0]) return std::vector<int>{p[1], p[2], p[3], q[2]};
    std::vector<int> corners;
    for (auto u : mesh.fv_range(f)) corners.push_back(u.idx());
    return corners;
  });
  // The merged quad, where the first of the two was (the second, if before it, is gone).
  const int merged = around[0].idx() - (around[1].idx() < around[0].idx() ? 1 : 0);
  if (!out || face_area(*out, out->face_handle(merged)) <= min_area) return std::nullopt;
  second = around[1].idx();
  return out;
}

/// Collapses tried at most: each rebuilds the mesh, so a mesh folded all over (22,500 quads with
/// 2,500 darts took 47 s) is not a remesher's stray fault to repair one by one.
constexpr int kMaxFoldedRepairs = 64;

/// True when quad corners \p c fold back across one of their diagonals (kFoldedBack).
bool folded_back(const PolyMesh& mesh, const std::array<int, 4>& c) {
  return std::max(fold_across(mesh, c, 0), fold_across(mesh, c, 1)) > kFoldedBack;
}

struct FoldedQuads {
  std::vector<int> collapsed;  ///< numbered as in the file
  std::vector<int> doublets;   ///< the inner vertices of two quads the collapses left, removed
  int left = 0;                ///< still folded back
};

/// Collapses every quad of \p mesh folded back onto itself across a diagonal (kFoldedBack): its
/// two other corners, on the same side of that diagonal, become one vertex at their midpoint,
/// the quad goes and its two pairs of sides become two edges (as for a doublet; the surface
/// keeps its Euler characteristic). A collapse that would leave the mesh non-manifold is not
/// made, nor any beyond kMaxFoldedRepairs tries. A collapse takes a side from each corner on the
/// folded diagonal: a corner left with two quads (a doublet, the two folded back onto each other
/// at a sharp edge: fandisk_qf800's parts 178 and 179 were single quads of 22 mm^2 there, too
/// small for any part and folded 177 degrees against their neighbour) has the two merged into
/// one (without_doublet), within the same limit. \p dropped: the faces of the file already gone
/// (sorted).
FoldedQuads collapse_folded_quads(PolyMesh& mesh, const std::vector<int>& dropped) {
  std::vector<int> original;  // face of \p mesh as it is now -> in the file
  for (int f = 0, k = 0; f < static_cast<int>(mesh.n_faces() + dropped.size()); ++f) {
    if (k < static_cast<int>(dropped.size()) && dropped[k] == f) {
      ++k;
      continue;
    }
    original.push_back(f);
  }
  FoldedQuads out;
  std::set<int> refused;  // as in the file
  int tries = 0;
  const double diag = bounding_box(mesh).diagonal();
  const double min_area = kZeroArea * diag * diag;
  for (bool again = true; again && tries < kMaxFoldedRepairs;) {
    again = false;
    if (!out.collapsed.empty())  // only collapses make doublets here (none in the file stays)
      for (auto v : mesh.vertices()) {
        int second = -1;
        std::optional<PolyMesh> merged = without_doublet(mesh, v, min_area, second);
        if (!merged) continue;
        if (++tries > kMaxFoldedRepairs) break;
        out.doublets.push_back(v.idx());
        original.erase(original.begin() + second);
        mesh = std::move(*merged);
        again = true;
        break;
      }
    if (again) continue;
    for (auto f : mesh.faces()) {
      if (mesh.valence(f) != 4 || refused.count(original[f.idx()])) continue;
      const auto c = quad_vertices(mesh, f);
      if (!folded_back(mesh, c)) continue;
      if (++tries > kMaxFoldedRepairs) break;
      // Corners k and k + 2: off the folded diagonal.
      const int k = fold_across(mesh, c, 0) >= fold_across(mesh, c, 1) ? 1 : 0;
      const auto a = mesh.vertex_handle(c[k]), b = mesh.vertex_handle(c[k + 2]);
      std::optional<PolyMesh> merged;
      if (!mesh.is_boundary(a) && !mesh.is_boundary(b))
        merged = merged_without(mesh, f.idx(), std::max(c[k], c[k + 2]), std::min(c[k], c[k + 2]),
                                0.5 * (mesh.point(a) + mesh.point(b)));
      if (!merged) {
        refused.insert(original[f.idx()]);
        continue;
      }
      out.collapsed.push_back(original[f.idx()]);
      original.erase(original.begin() + f.idx());
      mesh = std::move(*merged);
      again = true;
      break;
    }
  }
  std::sort(out.collapsed.begin(), out.collapsed.end());
  for (auto f : mesh.faces())
    out.left += mesh.valence(f) == 4 && folded_back(mesh, quad_vertices(mesh, f)) ? 1 : 0;
  return out;
}

/// A border vertex lies on a border edge where it is this close to it, as a fraction of the
/// edge's length [-] (an exporter's corners are floats: 1e-7 of the coordinates).
constexpr double kOnEdge = 1e-5;
/// Border edges times border vertices looked at most when zipping: a scan's holes have
/// thousands of each, and such a border is no T-junction's crack.
constexpr double kMaxZipPairs = 5e7;

/// The directed edges (a, b) of polygons \p faces that no face walks the other way (b, a):
/// the borders, each with its face and the position of a in it.
struct BorderEdge {
  int a, b, face, at;
};
std::vector<BorderEdge> border_edges(const std::vector<std::vector<int>>& faces) {
  std::set<std::pair<int, int>> directed;
  for (const auto& c : faces)
    for (std::size_t k = 0; k < c.size(); ++k) directed.insert({c[k], c[(k + 1) % c.size()]});
  std::vector<BorderEdge> out;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t k = 0; k < faces[f].size(); ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % faces[f].size()];
      if (!directed.count({b, a})) out.push_back({a, b, static_cast<int>(f), static_cast<int>(k)});
    }
  return out;
}

/// \p mesh with its cracks zipped, or nothing where it has none (or where zipped it is no
/// manifold mesh): faces cut differently along the line they share, as modellers export them,
/// leave that line a crack (a cube whose top was cut at a point of its front edge, the front
/// face not, had no joint between its top and front plates). Border vertices at exactly the
/// same point become one, and a border vertex lying on a border edge of another face is put
/// into that face between the edge's ends (a T-junction), so that the faces on either side
/// share their edges. A triangle so given more corners on one edge is cut into a fan from the
/// corner opposite; any other face takes them as corners. \p zipped: the vertices merged or
/// put in.
std::optional<PolyMesh> zip_cracks(const PolyMesh& mesh, int& zipped) {
  zipped = 0;
  std::vector<std::vector<int>> faces;
  for (auto f : mesh.faces()) {
    std::vector<int> c;
    for (auto v : mesh.fv_range(f)) c.push_back(v.idx());
    faces.push_back(std::move(c));
  }
  const auto point = [&](int v) { return to_eigen(mesh.point(mesh.vertex_handle(v))); };
  std::vector<BorderEdge> edges = border_edges(faces);
  if (edges.empty()) return std::nullopt;
  // Border vertices at one point merged into the first.
  std::map<std::array<double, 3>, int> first;
  std::map<int, int> merged;
  for (const BorderEdge& e : edges) {
    const Vec3 p = point(e.a);
    const auto [it, fresh] = first.try_emplace({p.x(), p.y(), p.z()}, e.a);
    if (!fresh && it->second != e.a) merged[e.a] = it->second;
  }
  zipped = static_cast<int>(merged.size());
  if (!merged.empty()) {
    for (auto& c : faces)
      for (int& v : c)
        if (const auto it = merged.find(v); it != merged.end()) v = it->second;
    edges = border_edges(faces);
  }
  std::vector<int> corners;  // border vertices
  for (const BorderEdge& e : edges) corners.push_back(e.a);
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  if (static_cast<double>(edges.size()) * static_cast<double>(corners.size()) > kMaxZipPairs)
    return std::nullopt;
  // Per face, per corner: the vertices put in after that corner, in order along the edge.
  std::map<int, std::map<int, std::vector<std::pair<double, int>>>> put;
  for (const BorderEdge& e : edges) {
    const Vec3 pa = point(e.a), d = point(e.b) - pa;
    const double length = d.norm();
    if (!(length > 0)) continue;
    for (int v : corners) {
      if (v == e.a || v == e.b) continue;
      const Vec3 pv = point(v);
      const double t = (pv - pa).dot(d) / (length * length);
      if (t <= kOnEdge || t >= 1 - kOnEdge || (pa + t * d - pv).norm() > kOnEdge * length) continue;
      put[e.face][e.at].push_back({t, v});
      ++zipped;
    }
  }
  if (zipped == 0) return std::nullopt;
  std::vector<std::vector<int>> out;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::vector<int>& c = faces[f];
    const auto it = put.find(static_cast<int>(f));
    if (it == put.end()) {
      out.push_back(c);
      continue;
    }
    std::vector<int> polygon;
    for (std::size_t k = 0; k < c.size(); ++k) {
      polygon.push_back(c[k]);
      const auto in = it->second.find(static_cast<int>(k));
      if (in == it->second.end()) continue;
      std::vector<std::pair<double, int>> along = in->second;
      std::sort(along.begin(), along.end());
      for (const auto& [t, v] : along) polygon.push_back(v);
    }
    // A fan from the corner no vertex was put beside (both its edges as they were); with
    // vertices on two edges there is none, and the polygon stays whole (ear clipping cuts it).
    int apex = -1;
    for (int k = 0; k < 3 && c.size() == 3; ++k)
      if (!it->second.count(k) && !it->second.count((k + 2) % 3)) apex = k;
    if (apex < 0) {
      out.push_back(std::move(polygon));
      continue;
    }
    std::rotate(polygon.begin(), std::find(polygon.begin(), polygon.end(), c[apex]), polygon.end());
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
      out.push_back({polygon[0], polygon[k], polygon[k + 1]});
  }
  return with_faces(mesh, out);
}

/// \p mesh with its triangles of no area (thinner than a millionth of its median edge) mended, or
/// nothing where it has none (or where the mended faces do not make a mesh again): a sliver whose
/// corners lie on one line (a cap) goes, its middle corner put into the face across its longest
/// edge (a triangle there split in two at it); a needle, two corners at one point, has them
/// merged. A larger face of no area with two corners at one
/// point (a general remesher's quad whose opposite corners coincide: QuadriFlow's fandisk, face
/// 740) has them merged the same way. Either way a face left with a corner twice in a row keeps
/// it once (a quad beside a needle becomes a triangle), one left with it twice apart, pinched to
/// no area, goes. \p mended: the triangles mended;
/// \p mended_larger: the larger faces.
std::optional<PolyMesh> mend_zero_area_faces(const PolyMesh& mesh, int& mended,
                                             int& mended_larger) {
  mended = mended_larger = 0;
  std::vector<Vec3> p;
  for (auto v : mesh.vertices()) p.push_back(to_eigen(mesh.point(v)));
  // Thin against the mesh's own median edge, not its extent (one stray vertex 1e30 away makes
  // every real face thin against that; check_geometry names it).
  std::vector<double> lengths;
  for (auto e : mesh.edges()) lengths.push_back(mesh.calc_edge_length(e));
  if (lengths.empty()) return std::nullopt;
  std::nth_element(lengths.begin(),
                   lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2),
                   lengths.end());
  const double short_edge = 1e-6 * lengths[lengths.size() / 2];
  if (!(short_edge > 0.0) || !std::isfinite(short_edge)) return std::nullopt;
  std::vector<std::vector<int>> faces;
  for (auto f : mesh.faces()) {
    std::vector<int> c;
    for (auto v : mesh.fv_range(f)) c.push_back(v.idx());
    faces.push_back(std::move(c));
  }
  auto area = [&](const std::vector<int>& c) {
    Vec3 a = Vec3::Zero();
    for (std::size_t k = 1; k + 1 < c.size(); ++k)
      a += (p[c[k]] - p[c[0]]).cross(p[c[k + 1]] - p[c[0]]);
    return 0.5 * a.norm();
  };
  // Thinner than a millionth of the median edge (a needle's two corners or a cap's height): such a
  // triangle carries no surface, and CGAL's constructions on it fail (a cube with a needle 1e-9
  // across, of area just over the zero mark, ended the quads stage with a segmentation fault in the
  // release build: "squared_radius >= 0 and o != COLLINEAR").
  // Two corners of a larger face at one point, nearest first; none where there are not.
  auto coincident = [&](const std::vector<int>& c) -> std::optional<std::pair<int, int>> {
    std::optional<std::pair<int, int>> pair;
    double nearest = short_edge;
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = i + 1; j < c.size(); ++j)
        if (const double d = (p[c[j]] - p[c[i]]).norm(); d <= nearest) nearest = d, pair = {i, j};
    return pair;
  };
  auto zero = [&](const std::vector<int>& c) {
    if (c.size() > 3) {
      double longest = 0;
      for (std::size_t k = 0; k < c.size(); ++k)
        longest = std::max(longest, (p[c[(k + 1) % c.size()]] - p[c[k]]).norm());
      return 2 * area(c) <= short_edge * longest && coincident(c).has_value();
    }
    if (c.size() != 3) return false;
    double longest = 0, shortest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const double len = (p[c[(k + 1) % 3]] - p[c[k]]).norm();
      longest = std::max(longest, len);
      shortest = std::min(shortest, len);
    }
    return shortest <= short_edge || 2 * area(c) <= short_edge * longest;
  };
  for (const auto& c : faces)
    if (zero(c)) ++(c.size() > 3 ? mended_larger : mended);
  // Each mend looks through every face: beyond this many the mesh is no export's slip.
  if (mended + mended_larger == 0 || mended + mended_larger > kMaxMended) return std::nullopt;
  // Two corners at one point become one: a face left with a corner twice in a row keeps it once
  // (a needle's neighbouring quad becomes a triangle, not a hole); one pinched (a corner twice
  // apart) or left with under three corners (the needle's mate across its short edge) goes.
  auto merge = [&](int keep, int gone) {
    for (auto& c : faces) {
      std::replace(c.begin(), c.end(), gone, keep);
      for (std::size_t k = 0; k < c.size() && c.size() > 1;)
        if (c[k] == c[(k + 1) % c.size()])
          c.erase(c.begin() + static_cast<std::ptrdiff_t>(k));
        else
          ++k;
    }
    std::erase_if(faces, [](const std::vector<int>& c) {
      std::vector<int> s = c;
      std::sort(s.begin(), s.end());
      return c.size() < 3 || std::adjacent_find(s.begin(), s.end()) != s.end();
    });
  };
  // One at a time, onwards from the last (each change may leave another, a needle's neighbour,
  // or mend one), and once more round from the start.
  std::size_t from = 0;
  for (int tries = 0; tries < 2 * kMaxMended; ++tries) {
    auto it = std::find_if(faces.begin() + static_cast<std::ptrdiff_t>(from), faces.end(), zero);
    if (it == faces.end()) it = std::find_if(faces.begin(), faces.end(), zero);
    if (it == faces.end()) break;
    from = static_cast<std::size_t>(it - faces.begin());
    const std::vector<int> t = *it;
    faces.erase(it);
    if (t.size() > 3) {
      const auto [i, j] = *coincident(t);
      merge(t[i], t[j]);
      continue;
    }
    int k_short = 0, k_long = 0;  // edge k: corners k, k + 1
    for (int k = 1; k < 3; ++k) {
      const double len = (p[t[(k + 1) % 3]] - p[t[k]]).norm();
      if (len < (p[t[(k_short + 1) % 3]] - p[t[k_short]]).norm()) k_short = k;
      if (len > (p[t[(k_long + 1) % 3]] - p[t[k_long]]).norm()) k_long = k;
    }
    if ((p[t[(k_short + 1) % 3]] - p[t[k_short]]).norm() <= short_edge) {  // a needle
      merge(t[k_short], t[(k_short + 1) % 3]);
      continue;
    }
    // A cap: the face across its longest edge a -> b walks it b -> a; m goes between them.
    const int a = t[k_long], b = t[(k_long + 1) % 3], m = t[(k_long + 2) % 3];
    for (std::size_t g = 0; g < faces.size(); ++g) {
      auto& c = faces[g];
      const std::size_t n = c.size();
      std::size_t at = n;
      for (std::size_t k = 0; k < n; ++k)
        if (c[k] == b && c[(k + 1) % n] == a) at = k;
      if (at == n) continue;
      if (n == 3) {  // (x, b, a) -> (x, b, m), (x, m, a)
        const int x = c[(at + 2) % 3];
        c = {x, b, m};
        faces.push_back({x, m, a});
      } else {
        c.insert(c.begin() + static_cast<std::ptrdiff_t>(at + 1), m);
      }
      break;
    }
  }
  if (std::any_of(faces.begin(), faces.end(), zero)) return std::nullopt;
  PolyMesh out;
  for (auto v : mesh.vertices()) out.add_vertex(mesh.point(v));
  std::vector<PolyMesh::VertexHandle> corners;
  for (const auto& c : faces) {
    corners.clear();
    for (int v : c) corners.push_back(out.vertex_handle(v));
    if (!out.add_face(corners).is_valid()) return std::nullopt;
  }
  return out;
}

void check_geometry(const PolyMesh& mesh, const std::string& what) {
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InvalidInput(what + " vertex " + std::to_string(v.idx()) +
                         " has a NaN or infinite coordinate");
  }
  const double diag = bounding_box(mesh).diagonal();
  if (!(diag > 0.0)) throw InvalidInput(what + " has zero extent (all vertices coincide)");
  const double min_area = kZeroArea * diag * diag;
  for (auto f : mesh.faces()) {
    const double area = face_area(mesh, f);
    if (area > min_area) continue;
    std::ostringstream os;
    os.precision(4);
    os << what << " face " << f.idx() << " has zero area";
    // A face of real size next to a model 10^6 times larger: a stray vertex far from the rest
    // (a coordinate of 1e30 beside ones of 1 said only "zero area"). Named: the vertex farthest
    // from the median of the vertices.
    if (area > 0) {
      std::array<std::vector<double>, 3> xyz;
      for (auto v : mesh.vertices())
        for (int k = 0; k < 3; ++k) xyz[k].push_back(mesh.point(v)[k]);
      Vec3 median;
      for (int k = 0; k < 3; ++k) {
        auto mid = xyz[k].begin() + static_cast<std::ptrdiff_t>(xyz[k].size() / 2);
        std::nth_element(xyz[k].begin(), mid, xyz[k].end());
        median[k] = *mid;
      }
      int far = -1;
      double farthest = -1;
      for (auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        const double d = (Vec3(p[0], p[1], p[2]) - median).norm();
        if (d > farthest) farthest = d, far = v.idx();
      }
      const auto& p = mesh.point(OpenMesh::VertexHandle(far));
      os << " next to the model's extent: it is " << std::sqrt(area) << " across, the model "
         << diag << "; vertex " << far << " at (" << p[0] << ", " << p[1] << ", " << p[2]
         << ") lies " << farthest << " from the middle of the others: a stray vertex?";
    }
    throw InvalidInput(os.str());
  }
}

void scale_mesh(PolyMesh& mesh, double s) {
  for (auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v) * s);
}

/// True when a ray from \p from along \p dir crosses triangle \p t of \p tri (Moller-Trumbore;
/// a ray grazing an edge counts on one side or the other, which a generic \p dir makes rare).
bool ray_crosses(const TriangleMesh& tri, const std::array<int, 3>& t, const Vec3& from,
                 const Vec3& dir) {
  const Vec3 &a = tri.vertices[t[0]], &b = tri.vertices[t[1]], &c = tri.vertices[t[2]];
  const Vec3 e1 = b - a, e2 = c - a, q = dir.cross(e2);
  const double det = e1.dot(q);
  if (std::abs(det) < 1e-300) return false;
  const Vec3 s = from - a;
  const double u = s.dot(q) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 r = s.cross(e1);
  const double v = dir.dot(r) / det;
  if (v < 0 || u + v > 1) return false;
  return e2.dot(r) / det > 0;
}

/// The pieces of \p tri (triangles joined through shared vertices): per piece its triangles,
/// ascending; the pieces in the order of their first triangles.
std::vector<std::vector<int>> pieces_of(const TriangleMesh& tri) {
  const int n = static_cast<int>(tri.vertices.size());
  std::vector<int> root(n);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int v) {  // iterative: a scan's million vertices would recurse too deep
    int r = v;
    while (root[r] != r) r = root[r];
    while (root[v] != r) v = std::exchange(root[v], r);
    return r;
  };
  for (const auto& t : tri.triangles)
    for (int k = 0; k < 3; ++k) root[find(t[k])] = find(t[(k + 1) % 3]);
  std::unordered_map<int, int> id;  // root -> piece
  std::vector<std::vector<int>> pieces;
  for (int i = 0; i < static_cast<int>(tri.triangles.size()); ++i) {
    const auto [it, added] = id.try_emplace(find(tri.triangles[i][0]), static_cast<int>(id.size()));
    if (added) pieces.emplace_back();
    pieces[it->second].push_back(i);
  }
  return pieces;
}

/// What turn_closed_pieces_out() did.
struct Turned {
  int turned = 0;             ///< pieces turned
  int closed = 0;             ///< closed pieces
  std::vector<int> cavities;  ///< closed pieces left facing inwards, inside another (in pieces)
};

/// Turns the triangles of every closed piece of \p tri (triangles joined through shared
/// vertices, each of their edges on two of them) that faces inwards (negative volume), unless
/// the piece lies inside another closed piece (a cavity, which faces inwards by right).
/// \p pieces: pieces_of(\p tri). \p turned_vertex: per vertex, 1 in a piece turned.
Turned turn_closed_pieces_out(TriangleMesh& tri, const std::vector<std::vector<int>>& pieces,
                              std::vector<char>& turned_vertex) {
  turned_vertex.assign(tri.vertices.size(), 0);
  std::unordered_map<std::uint64_t, int> edges;
  edges.reserve(tri.triangles.size() * 2);
  for (const auto& t : tri.triangles)
    for (int k = 0; k < 3; ++k) ++edges[undirected_edge_key(t[k], t[(k + 1) % 3])];
  std::vector<char> open(pieces.size(), 0);
  for (std::size_t r = 0; r < pieces.size(); ++r)
    for (int i : pieces[r])
      for (int k = 0; k < 3; ++k) {
        const auto& t = tri.triangles[i];
        if (edges[undirected_edge_key(t[k], t[(k + 1) % 3])] != 2) open[r] = 1;
      }
  std::vector<int> inward;
  Turned out;
  for (std::size_t r = 0; r < pieces.size(); ++r) {
    if (open[r]) continue;
    const std::vector<int>& list = pieces[r];
    ++out.closed;
    double volume = 0;
    for (int i : list) {
      const auto& t = tri.triangles[i];
      volume += tri.vertices[t[0]].dot(tri.vertices[t[1]].cross(tri.vertices[t[2]])) / 6.0;
    }
    if (volume < 0) inward.push_back(static_cast<int>(r));
  }
  const Vec3 dir = Vec3(0.5773, 0.5774, 0.5775).normalized();  // generic: no axis, no diagonal
  for (int r : inward) {
    const Vec3 from = tri.vertices[tri.triangles[pieces[r].front()][0]];
    int crossings = 0;
    for (std::size_t other = 0; other < pieces.size(); ++other)
      if (static_cast<int>(other) != r && !open[other])
        for (int i : pieces[other]) crossings += ray_crosses(tri, tri.triangles[i], from, dir);
    if (crossings % 2 == 1) {  // a cavity
      out.cavities.push_back(r);
      continue;
    }
    for (int i : pieces[r]) {
      std::swap(tri.triangles[i][1], tri.triangles[i][2]);
      for (int v : tri.triangles[i]) turned_vertex[v] = 1;
    }
    ++out.turned;
  }
  return out;
}

/// Each of \p pieces (pieces_of) of \p tri as a mesh on its own.
std::vector<TriangleMesh> piece_meshes(const TriangleMesh& tri,
                                       const std::vector<std::vector<int>>& pieces) {
  std::vector<TriangleMesh> piece;
  piece.reserve(pieces.size());
  for (const std::vector<int>& triangles : pieces) piece.push_back(sub_mesh(tri, triangles));
  return piece;
}

/// True when boxes \p a and \p b meet, each grown by \p eps.
bool boxes_meet(const BoundingBox& a, const BoundingBox& b, double eps) {
  return (a.min.array() <= b.max.array() + eps).all() &&
         (b.min.array() <= a.max.array() + eps).all();
}

double surface_area(const TriangleMesh& mesh) {
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += 0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                      .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]])
                      .norm();
  return area;
}

/// \p tri without the \p cavities among its \p pieces (pieces_of), as turn_closed_pieces_out()
/// found them (a hollowed model's inner wall); nothing where there are none. \p area: their
/// surface [mm^2].
std::optional<TriangleMesh> without_cavities(const TriangleMesh& tri,
                                             const std::vector<std::vector<int>>& pieces,
                                             const std::vector<int>& cavities, double& area) {
  area = 0;
  if (cavities.empty()) return std::nullopt;
  std::vector<char> drop(tri.triangles.size(), 0);
  for (int r : cavities) {
    for (int i : pieces[r]) drop[i] = 1;
    area += surface_area(sub_mesh(tri, pieces[r]));
  }
  std::vector<int> kept;
  for (int i = 0; i < static_cast<int>(tri.triangles.size()); ++i)
    if (!drop[i]) kept.push_back(i);
  return sub_mesh(tri, kept);
}

/// Most pieces among which unite_meeting_solids() looks for solids that meet (a scan in
/// thousands of crumbs is not a model built of solids) [-].
constexpr std::size_t kMaxPiecesToUnite = 200;

/// Solids that overlap or touch, united: the closed pieces of \p tri (\p pieces:
/// pieces_of) that bound a solid (bounds_solid) and meet another such (solids_meet: their
/// surfaces cross or touch, or one lies inside the other), grouped, each group
/// replaced by the surface of its union (solid_union), the other pieces kept as they are.
/// Nothing where no group is united (a group whose union has no manifold surface, such as two
/// boxes meeting along an edge only, is kept as it is). \p united: how many pieces went into
/// unions.
std::optional<TriangleMesh> unite_meeting_solids(const TriangleMesh& tri,
                                                 const std::vector<std::vector<int>>& pieces,
                                                 int& united) {
  united = 0;
  if (pieces.size() < 2 || pieces.size() > kMaxPiecesToUnite) return std::nullopt;
  const std::vector<TriangleMesh> piece = piece_meshes(tri, pieces);
  std::vector<BoundingBox> box(piece.size());
  for (std::size_t p = 0; p < piece.size(); ++p) box[p] = bounding_box(piece[p]);
  std::vector<signed char> solid(piece.size(), -1);  // bounds_solid, once asked
  auto is_solid = [&](std::size_t p) {
    if (solid[p] < 0) solid[p] = bounds_solid(piece[p]) ? 1 : 0;
    return solid[p] == 1;
  };
  std::vector<int> group(piece.size());
  std::iota(group.begin(), group.end(), 0);
  auto find = [&](int p) {
    while (group[p] != p) p = group[p] = group[group[p]];
    return p;
  };
  bool any = false;
  for (std::size_t b = 0; b < piece.size(); ++b)
    for (std::size_t a = 0; a < b; ++a)
      if (boxes_meet(box[a], box[b], 0.0) &&
          find(static_cast<int>(a)) != find(static_cast<int>(b)) && is_solid(a) && is_solid(b) &&
          solids_meet(piece[a], piece[b])) {
        group[find(static_cast<int>(a))] = find(static_cast<int>(b));
        any = true;
      }
  if (!any) return std::nullopt;
  std::map<int, std::vector<int>> groups;
  for (std::size_t p = 0; p < piece.size(); ++p)
    groups[find(static_cast<int>(p))].push_back(static_cast<int>(p));
  TriangleMesh out;
  auto append = [&](const TriangleMesh& m) {
    const int base = static_cast<int>(out.vertices.size());
    out.vertices.insert(out.vertices.end(), m.vertices.begin(), m.vertices.end());
    for (const auto& t : m.triangles)
      out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  };
  for (const auto& [root, members] : groups) {
    std::optional<TriangleMesh> whole = piece[members.front()];
    for (std::size_t k = 1; k < members.size() && whole; ++k)
      whole = solid_union(*whole, piece[members[k]]);
    if (members.size() > 1 && whole) {
      append(*whole);
      united += static_cast<int>(members.size());
    } else {
      for (int p : members) append(piece[p]);
    }
  }
  if (united == 0) return std::nullopt;
  return out;
}

/// Where \p pieces of \p tri (pieces_of: triangles joined through shared vertices) lie on one
/// another: the area of the triangles whose middle lies within \p eps of another piece's
/// surface (of each pair, the first piece's), and one such middle. Two solids glued face to face,
/// each closed, come so: their surfaces share the face they touch along, and no quad mesh follows
/// both.
struct PieceContact {
  double area = 0;  ///< [mm^2]
  Vec3 at = Vec3::Zero();
};
PieceContact touching_pieces(const TriangleMesh& tri, const std::vector<std::vector<int>>& pieces,
                             double eps) {
  PieceContact contact;
  if (pieces.size() < 2) return contact;
  const std::vector<TriangleMesh> piece = piece_meshes(tri, pieces);
  std::vector<BoundingBox> box(pieces.size());
  for (std::size_t p = 0; p < pieces.size(); ++p) box[p] = bounding_box(piece[p]);
  auto within = [&](const Vec3& lo, const Vec3& hi, const BoundingBox& b) {
    return boxes_meet(BoundingBox{lo, hi}, b, eps);
  };
  std::vector<std::optional<TargetSurface>> surface(pieces.size());  // built where needed
  for (std::size_t b = 0; b < pieces.size(); ++b)
    for (std::size_t a = 0; a < b; ++a) {
      if (!within(box[a].min, box[a].max, box[b])) continue;
      if (!surface[b]) surface[b].emplace(piece[b]);
      for (const auto& t : piece[a].triangles) {
        const Vec3 &p0 = piece[a].vertices[t[0]], &p1 = piece[a].vertices[t[1]],
                   &p2 = piece[a].vertices[t[2]];
        const Vec3 middle = (p0 + p1 + p2) / 3.0;
        if (!within(middle, middle, box[b]) || surface[b]->closest(middle).distance > eps) continue;
        contact.area += 0.5 * (p1 - p0).cross(p2 - p0).norm();
        contact.at = middle;
      }
    }
  return contact;
}

}  // namespace

PolyMesh catmull_clark(const PolyMesh& mesh, int steps) {
  PolyMesh out = mesh;
  if (steps <= 0) return out;
  // The subdivider works on a mesh without deleted elements or isolated vertices.
  for (auto v : out.vertices())
    if (out.is_isolated(v)) out.delete_vertex(v, false);
  out.garbage_collection();
  OpenMesh::Subdivider::Uniform::CatmullClarkT<PolyMesh> subdivider;
  subdivider.attach(out);
  subdivider(static_cast<std::size_t>(steps));
  subdivider.detach();
  return out;
}

PreparedInput prepare_input(const PolyMesh& target_given, const std::optional<PolyMesh>& quad_in,
                            const InputOptions& options) {
  if (target_given.n_faces() == 0) throw InvalidInput("target mesh has no faces");
  // Triangles of no area (an exporter's slivers and needles) carry no surface: mended where
  // that leaves a mesh, else refused below by check_geometry.
  int zipped = 0;
  const std::optional<PolyMesh> zipped_target = zip_cracks(target_given, zipped);
  const PolyMesh& target_whole = zipped_target ? *zipped_target : target_given;
  int mended = 0, mended_larger = 0;
  const std::optional<PolyMesh> mended_target =
      mend_zero_area_faces(target_whole, mended, mended_larger);
  const PolyMesh& target_in = mended_target ? *mended_target : target_whole;
  if (options.subdivide < 0 || options.subdivide > 4)
    throw InvalidInput("--subdivide must be between 0 and 4, got " +
                       std::to_string(options.subdivide));
  if (!(options.max_quad_distance > 0.0)) throw InvalidInput("maximum quad distance must be > 0");
  check_geometry(target_in, "target mesh");
  std::vector<std::string> warnings;
  if (zipped_target)
    warnings.push_back("target: " + std::to_string(zipped) +
                       " vertices of a crack (a border vertex at the point of another, or lying "
                       "on a border edge of another face: a T-junction) joined to the faces "
                       "across it, closing the crack");
  if (mended_target && mended > 0)
    warnings.push_back(
        "target: " + std::to_string(mended) +
        " triangles of no area (thinner than a millionth of the median edge) mended: a "
        "sliver's middle corner joined to the face across its longest edge, a "
        "needle's two corners at one point merged");
  if (mended_target && mended_larger > 0)
    warnings.push_back("target: " + std::to_string(mended_larger) +
                       " faces of more than three corners and no area, two of their corners at "
                       "one point (a quad whose opposite corners coincide), mended: those two "
                       "corners merged, the face gone");
  std::optional<PolyMesh> repaired;  // the quad mesh with its doublets collapsed
  if (quad_in) {
    if (quad_in->n_faces() == 0) throw InvalidInput("quad mesh has no faces");
    repaired = *quad_in;
    const std::vector<int> collapsed = collapse_doublets(*repaired);
    if (!collapsed.empty()) {
      std::ostringstream w;
      w << "quad mesh: " << collapsed.size() << " zero-area quad"
        << (collapsed.size() > 1 ? "s" : "") << " whose opposite corners coincide (face";
      for (std::size_t i = 0; i < collapsed.size() && i < 8; ++i) w << " " << collapsed[i];
      w << (collapsed.size() > 8 ? " ..." : "") << ") collapsed along that diagonal";
      warnings.push_back(w.str());
    }
    // A control cage (subdivided) is no surface yet: its quads may fold as they like.
    const FoldedQuads darts =
        options.subdivide == 0 ? collapse_folded_quads(*repaired, collapsed) : FoldedQuads{};
    const std::vector<int>& folded = darts.collapsed;
    if (!folded.empty()) {
      std::ostringstream w;
      w << "quad mesh: " << folded.size() << " quad" << (folded.size() > 1 ? "s" : "")
        << " folded back onto " << (folded.size() > 1 ? "themselves" : "itself")
        << " across a diagonal (by more than 150 deg; face";
      for (std::size_t i = 0; i < folded.size() && i < 8; ++i) w << " " << folded[i];
      w << (folded.size() > 8 ? " ..." : "")
        << ") collapsed: the two corners off that diagonal merged at their midpoint";
      warnings.push_back(w.str());
    }
    if (!darts.doublets.empty()) {
      std::ostringstream w;
      w << "quad mesh: " << darts.doublets.size() << " vert"
        << (darts.doublets.size() > 1 ? "ices" : "ex")
        << " left with two quads by those collapses (vertex";
      for (std::size_t i = 0; i < darts.doublets.size() && i < 8; ++i)
        w << " " << darts.doublets[i];
      w << (darts.doublets.size() > 8 ? " ..." : "") << "): the two quads merged into one";
      warnings.push_back(w.str());
    }
    if (darts.left > 0)
      warnings.push_back("quad mesh: " + std::to_string(darts.left) +
                         " quad(s) stay folded back onto themselves across a diagonal (by more "
                         "than 150 deg): collapsing them would leave the mesh non-manifold, or "
                         "more than " +
                         std::to_string(kMaxFoldedRepairs) + " are to repair");
    check_geometry(*repaired, "quad mesh");
  }
  const std::optional<PolyMesh>& quad_mesh = repaired;

  // Units and scale: decided on the target, applied identically to both meshes.
  const double side = bounding_box(target_in).largest_side();
  double scale = 1.0;
  if (options.size) {
    const double size = *options.size;
    if (!std::isfinite(size) || size < options.min_model_mm || size > options.max_model_mm)
      throw InvalidInput("--size must be between " + fmt(options.min_model_mm) + " and " +
                         fmt(options.max_model_mm) + " mm, got " + fmt(size));
    scale = size / side;
  } else if (side < options.min_model_mm || side > options.max_model_mm) {
    throw InvalidInput("target's largest bounding-box side is " + fmt(side) + " mm, outside " +
                       fmt(options.min_model_mm) + " mm .. " + fmt(options.max_model_mm / 1000.0) +
                       " m; inputs are read as millimetres, so pass --size MM to scale the model");
  }

  // The quad mesh: given, or the target itself.
  const bool from_target = !quad_mesh.has_value();
  const PolyMesh& quad_source = from_target ? target_in : *quad_mesh;
  // A target that is not all quads, without a quad mesh: the quads stage makes one
  // (make_quad_mesh) on its triangles. One of triangles and quads or n-gons is taken as the
  // surface it stands for, not as a cage to smooth, unless --subdivide asks for that.
  bool needs_quads = from_target && !is_all_quads(target_in) && options.subdivide == 0;
  // (Not where the zip alone made it so: a box of quads cut differently on each side.)
  if (needs_quads && !is_all_triangles(target_in) &&
      !(zipped_target && (is_all_quads(target_given) || is_all_triangles(target_given))))
    warnings.push_back("target has " + face_size_text(target_in) +
                       ": meshed as it stands by the quads stage; if it is a subdivision cage, "
                       "pass --subdivide 1 to smooth it first (Catmull-Clark)");
  if (!needs_quads && options.subdivide == 0 && !is_all_quads(quad_source))
    throw InvalidInput(std::string(from_target ? "target" : "quad mesh") + " has " +
                       face_size_text(quad_source) +
                       "; kerfab needs all quads: pass --subdivide 1 (Catmull-Clark)");

  PolyMesh target = target_in;
  PolyMesh quads = needs_quads ? PolyMesh() : catmull_clark(quad_source, options.subdivide);
  scale_mesh(target, scale);
  scale_mesh(quads, scale);
  if (!needs_quads && !is_all_quads(quads))
    throw InvalidInput("quad mesh is not all quads after subdivision");

  TriangleMesh tri = triangulate(target);
  std::vector<char> turned_vertex;
  std::vector<std::vector<int>> pieces = pieces_of(tri);  // turning keeps them
  const Turned turning = turn_closed_pieces_out(tri, pieces, turned_vertex);
  if (turning.turned > 0) {
    // The target as used (model/target.obj) faces the same way: the turned pieces' faces in
    // the other order, each first corner kept first.
    PolyMesh turned_target;
    for (auto v : target.vertices()) turned_target.add_vertex(target.point(v));
    std::vector<PolyMesh::VertexHandle> corners;
    for (auto f : target.faces()) {
      corners.clear();
      for (auto v : target.fv_range(f)) corners.push_back(turned_target.vertex_handle(v.idx()));
      if (turned_vertex[corners.front().idx()]) std::reverse(corners.begin() + 1, corners.end());
      turned_target.add_face(corners);
    }
    target = std::move(turned_target);
    if (turning.turned == turning.closed) {
      warnings.push_back(
          "target faces point inward (negative volume); flipped them for inside/outside tests");
    } else {
      std::ostringstream w;
      w << "target: " << turning.turned << " of its " << turning.closed
        << " closed pieces face inward (negative volume) and lie inside no other; flipped them "
           "for inside/outside tests";
      warnings.push_back(w.str());
    }
  }
  // Solids that overlap or touch (a model built of overlapping primitives, of blocks glued face
  // to face, or with a part hidden inside another) are one solid to the maker: kerfab meshes the
  // surface of their union. (Each surface on its own had rows of quads run into the other
  // solid, and the sheets of the two meet there.) A hollowed model's inner wall (a cavity) is no
  // surface a kerfed shell can have, the shell being one sheet thick: the outer surface alone is
  // meshed (a hollow sphere with both walls was cut as two shells through one another: 23 parts
  // inside out). Both where kerfab makes the quads, or where the target is its own quad mesh
  // (whose quads then cannot be used as they are: it is meshed anew).
  int united = 0, cavities = 0;
  double united_gone = 0, cavity_area = 0;  // [mm^2]
  if (from_target && options.subdivide == 0) {
    if (std::optional<TriangleMesh> outer =
            without_cavities(tri, pieces, turning.cavities, cavity_area)) {
      cavities = static_cast<int>(turning.cavities.size());
      tri = std::move(*outer);
      pieces = pieces_of(tri);
      warnings.push_back("target: " + std::to_string(cavities) + " inner surface" +
                         (cavities > 1 ? "s" : "") + " (a cavity, facing inwards inside a " +
                         "closed piece: a hollowed model's inner wall, " + fmt(cavity_area) +
                         " mm^2) left out: a kerfed shell is one surface, the outer one");
    }
    if (std::optional<TriangleMesh> whole = unite_meeting_solids(tri, pieces, united)) {
      const double before = surface_area(tri);
      united_gone = before - surface_area(*whole);
      tri = std::move(*whole);
      pieces = pieces_of(tri);
      warnings.push_back("target: " + std::to_string(united) +
                         " solids that overlap or touch joined into one (their union, as "
                         "a modeller's mesh union makes it): " +
                         fmt(united_gone) + " of their " + fmt(before) +
                         " mm^2 of surface lay inside another solid or on two, and is gone");
    }
    if ((cavities > 0 || united > 0) && !needs_quads) {
      needs_quads = true;
      quads = PolyMesh();
      warnings.push_back(
          "target: its quads are not used as they stand (they follow the surfaces just mended); "
          "the quads stage meshes the mended surface");
    }
  }
  if (cavities > 0 || united > 0) {  // the target as used (model/target.obj) is the new surface
    PolyMesh surface;
    for (const Vec3& v : tri.vertices) surface.add_vertex(PolyMesh::Point(v.x(), v.y(), v.z()));
    for (const auto& t : tri.triangles)
      surface.add_face(surface.vertex_handle(t[0]), surface.vertex_handle(t[1]),
                       surface.vertex_handle(t[2]));
    target = std::move(surface);
  }
  // Solids glued face to face: refused, naming where (two cubes sharing a face had the quads
  // stage try four lattices and a smoothed copy for 86 s, then fail on folded quads).
  if (const PieceContact c = touching_pieces(tri, pieces, 1e-4 * bounding_box(tri).diagonal());
      c.area > 0)
    throw InvalidInput("target: pieces of it lie on one another over " + fmt(c.area) +
                       " mm^2 (at " + fmt(c.at.x()) + ", " + fmt(c.at.y()) + ", " + fmt(c.at.z()) +
                       " mm): solids touching face to face are no one surface to cut; join them "
                       "into one (a mesh union in the modeller) or move them apart");
  PreparedInput out{.target = std::move(target),
                    .quads = std::move(quads),
                    .surface = TargetSurface(tri),
                    .scale = scale,
                    .quads_from_target = from_target && !needs_quads,
                    .needs_quads = needs_quads,
                    .united_solids = united,
                    .united_surface_gone = united_gone,
                    .cavities_left_out = cavities,
                    .cavity_area = cavity_area,
                    .warnings = std::move(warnings)};
  out.target_summary = summarize(out.target);
  out.target_diagonal = bounding_box(out.surface.mesh()).diagonal();
  if (!needs_quads) attach_quads(out, std::move(out.quads), options);
  return out;
}

void attach_quads(PreparedInput& out, PolyMesh quads, const InputOptions& options) {
  out.quads = std::move(quads);
  out.quad_summary = summarize(out.quads);

  // The quad mesh must lie on (near) the target.
  const VertexDistances off = vertex_distances(out.quads, out.surface);
  out.quad_max_distance = off.max;
  out.quad_mean_distance = off.mean;
  const double diag = out.target_summary.bbox.diagonal();
  if (off.max > options.max_quad_distance * diag)
    throw InvalidInput("quad mesh is far from the target: a vertex lies " + fmt(off.max) +
                       " mm away (" + fmt(100.0 * off.max / diag) + "% of the target's " +
                       fmt(diag) + " mm diagonal, limit " + fmt(100.0 * options.max_quad_distance) +
                       "%); are both meshes in the same frame and units?");
}

}  // namespace kerfab

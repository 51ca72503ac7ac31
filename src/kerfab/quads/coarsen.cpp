#include "kerfab/quads/coarsen.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <set>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

using Quad = std::array<int, 4>;

int find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// A quad mesh as plain lists, with its edges and their faces.
struct QuadList {
  std::vector<Vec3> points;
  std::vector<Quad> faces;
  // Edges: per edge its ends and up to two (face, local edge); found through edges_at.
  std::vector<std::array<int, 2>> ends;
  std::vector<std::vector<std::pair<int, int>>> faces_of;
  std::vector<std::array<int, 4>> face_edges;  // local edge k joins corners k and k + 1
  std::vector<std::vector<int>> edges_at;      // per vertex

  /// The edge between vertices \p a and \p b, or -1.
  int edge(int a, int b) const {
    for (int e : edges_at[a])
      if (ends[e][0] == b || ends[e][1] == b) return e;
    return -1;
  }

  void index() {
    ends.clear();
    faces_of.clear();
    face_edges.assign(faces.size(), {});
    edges_at.assign(points.size(), {});
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (int k = 0; k < 4; ++k) {
        const int a = faces[f][k], b = faces[f][(k + 1) % 4];
        int e = edge(a, b);
        if (e < 0) {
          e = static_cast<int>(ends.size());
          ends.push_back({a, b});
          faces_of.emplace_back();
          edges_at[a].push_back(e);
          edges_at[b].push_back(e);
        }
        faces_of[e].push_back({static_cast<int>(f), k});
        face_edges[f][k] = e;
      }
  }
  bool boundary(int e) const { return faces_of[e].size() == 1; }
  Vec3 centre(int f) const {
    Vec3 c = Vec3::Zero();
    for (int v : faces[f]) c += points[v];
    return c / 4.0;
  }
  Vec3 normal(int f) const {
    const Quad& q = faces[f];
    const Vec3 n = (points[q[2]] - points[q[0]]).cross(points[q[3]] - points[q[1]]);
    return n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
  }
  /// Fold across interior edge \p e between its two faces [rad]; 0 on the border.
  double fold_across(int e) const {
    if (faces_of[e].size() != 2) return 0.0;
    return angle_between(normal(faces_of[e][0].first), normal(faces_of[e][1].first));
  }
  /// Curvature across interior edge \p e: its fold over the faces' centres' distance [1/mm].
  double curvature_across(int e) const {
    if (faces_of[e].size() != 2) return 0.0;
    const double d = (centre(faces_of[e][0].first) - centre(faces_of[e][1].first)).norm();
    return d > 0 ? fold_across(e) / d : 0.0;
  }
  double length(int e) const { return (points[ends[e][1]] - points[ends[e][0]]).norm(); }
};

QuadList to_list(const PolyMesh& m) {
  QuadList q;
  for (auto v : m.vertices()) q.points.push_back(to_eigen(m.point(v)));
  for (auto f : m.faces()) {
    if (m.valence(f) != 4)
      throw InvalidInput("coarsening: the quad mesh has a face that is not a quad");
    q.faces.push_back(quad_vertices(m, f));
  }
  q.index();
  return q;
}

/// Builds the OpenMesh of \p q (unused vertices stay, isolated); empty optional when a face
/// cannot be added (the collapse would make the surface non-manifold).
std::optional<PolyMesh> to_mesh(const QuadList& q) {
  PolyMesh m;
  for (const Vec3& p : q.points) m.add_vertex(to_openmesh(p));
  for (const Quad& f : q.faces) {
    std::vector<OpenMesh::VertexHandle> c;
    for (int v : f) c.push_back(m.vertex_handle(v));
    if (!m.add_face(c).is_valid()) return std::nullopt;
  }
  for (auto v : m.vertices())
    if (!m.is_isolated(v) && !m.is_manifold(v)) return std::nullopt;
  return m;
}

struct Shape {
  int euler = 0, borders = 0;
};

Shape shape_of(const PolyMesh& m) {
  int used = 0;
  for (auto v : m.vertices()) used += m.is_isolated(v) ? 0 : 1;
  return {used - static_cast<int>(m.n_edges()) + static_cast<int>(m.n_faces()),
          boundary_loop_count(m)};
}

/// take_back_subdivision on plain lists: the coarser list (indexed, the V vertices only, in the
/// order the coarser faces first use them), or nothing. \p from, if set: per coarser face the
/// four finer ones it is made of.
std::optional<QuadList> taken_back(const QuadList& q,
                                   std::vector<std::array<int, 4>>* from = nullptr) {
  enum Class : signed char { kUnknown = -1, kV = 0, kE = 1, kF = 2 };
  static constexpr std::array<signed char, 4> kPattern = {kV, kE, kF, kE};  // round every quad
  const int nv = static_cast<int>(q.points.size());
  std::vector<std::vector<int>> faces_at(nv);
  for (std::size_t f = 0; f < q.faces.size(); ++f)
    for (int v : q.faces[f]) faces_at[v].push_back(static_cast<int>(f));
  std::vector<signed char> cls(nv, kUnknown);
  std::vector<char> done(q.faces.size(), 0);
  // The turn r of the pattern that quad \p c's known corners follow (class of corner k =
  // pattern[(k + r) % 4]): -1 where none does, -2 where more than one would.
  auto turn_of = [&](const Quad& c) {
    int found = -1;
    for (int r = 0; r < 4; ++r) {
      bool fits = true;
      for (int k = 0; k < 4; ++k)
        fits = fits && (cls[c[k]] == kUnknown || cls[c[k]] == kPattern[(k + r) % 4]);
      if (!fits) continue;
      if (found >= 0) return -2;
      found = r;
    }
    return found;
  };
  // Each vertex's place: every F inside, among four quads, and every E among four (two on the
  // border).
  auto placed = [&](int v) {
    bool border = false;
    for (int e : q.edges_at[v]) border = border || q.boundary(e);
    const std::size_t around = faces_at[v].size();
    if (cls[v] == kF) return !border && around == 4;
    if (cls[v] == kE) return around == (border ? 2u : 4u);
    return true;
  };
  // Each piece of the mesh: its first quad takes each of the four turns until one carries over
  // every quad joined to it across an edge and puts every vertex in its place (V and F swapped
  // fit every quad as well: the pattern turned by two).
  for (std::size_t seed = 0; seed < q.faces.size(); ++seed) {
    if (done[seed]) continue;
    bool fits = false;
    for (int r = 0; r < 4 && !fits; ++r) {
      std::vector<int> assigned, queue;
      auto assign = [&](int f, int turn) {
        done[f] = 1;
        queue.push_back(f);
        for (int k = 0; k < 4; ++k) {
          const int v = q.faces[f][k];
          const signed char want = kPattern[(k + turn) % 4];
          if (cls[v] == kUnknown) {
            cls[v] = want;
            assigned.push_back(v);
          } else if (cls[v] != want) {
            return false;
          }
        }
        return true;
      };
      fits = assign(static_cast<int>(seed), r);
      for (std::size_t i = 0; fits && i < queue.size(); ++i)
        for (int k = 0; fits && k < 4; ++k)
          for (const auto& [g, kg] : q.faces_of[q.face_edges[queue[i]][k]]) {
            if (done[g]) continue;
            const int turn = turn_of(q.faces[g]);
            fits = turn >= 0 && assign(g, turn);
            if (!fits) break;
          }
      for (std::size_t i = 0; fits && i < assigned.size(); ++i) fits = placed(assigned[i]);
      if (!fits) {
        for (int v : assigned) cls[v] = kUnknown;
        for (int f : queue) done[f] = 0;
      }
    }
    if (!fits) return std::nullopt;
  }
  // Round each F, quad by quad (F, E, V, E' and on across F-E' to the next), the V corners.
  QuadList out;
  std::vector<int> id(nv, -1);
  std::vector<int> used(q.faces.size(), 0);
  if (from) from->clear();
  for (int fv = 0; fv < nv; ++fv) {
    if (cls[fv] != kF || faces_at[fv].empty()) continue;
    Quad coarse;
    std::array<int, 4> finer;
    int at = faces_at[fv].front();
    for (int k = 0; k < 4; ++k) {
      const Quad& c = q.faces[at];
      ++used[at];
      finer[k] = at;
      const int j = static_cast<int>(std::find(c.begin(), c.end(), fv) - c.begin());
      const int v = c[(j + 2) % 4], next_e = c[(j + 3) % 4];
      if (id[v] < 0) {
        id[v] = static_cast<int>(out.points.size());
        out.points.push_back(q.points[v]);
      }
      coarse[k] = id[v];
      int next = -1;
      for (int g : faces_at[fv])
        if (g != at && std::find(q.faces[g].begin(), q.faces[g].end(), next_e) != q.faces[g].end())
          next = g;
      if (next < 0) return std::nullopt;
      at = next;
    }
    if (at != faces_at[fv].front()) return std::nullopt;
    out.faces.push_back(coarse);
    if (from) from->push_back(finer);
  }
  for (int n : used)
    if (n != 1) return std::nullopt;
  out.index();
  return out;
}

/// The smallest and largest corner of face \p f of \p q [rad].
std::pair<double, double> corner_range(const QuadList& q, int f) {
  double lo = M_PI, hi = 0;
  const Quad& c = q.faces[f];
  for (int k = 0; k < 4; ++k) {
    const double a = angle_between(q.points[c[(k + 3) % 4]] - q.points[c[k]],
                                   q.points[c[(k + 1) % 4]] - q.points[c[k]]);
    lo = std::min(lo, a), hi = std::max(hi, a);
  }
  return {lo, hi};
}

/// One row (polychord): its cross edges and its quads.
struct Row {
  std::vector<int> edges;
  std::vector<int> faces;
  bool crosses_itself = false;
};

std::vector<Row> rows_of(const QuadList& q) {
  std::vector<int> parent(q.ends.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& fe : q.face_edges)
    for (int k = 0; k < 2; ++k) {
      const int a = find(parent, fe[k]), b = find(parent, fe[k + 2]);
      if (a != b) parent[a] = b;
    }
  std::map<int, int> row_of;
  std::vector<Row> rows;
  auto row = [&](int e) -> Row& {
    const int r = find(parent, e);
    const auto [it, added] = row_of.try_emplace(r, static_cast<int>(rows.size()));
    if (added) rows.emplace_back();
    return rows[it->second];
  };
  for (std::size_t e = 0; e < q.ends.size(); ++e)
    row(static_cast<int>(e)).edges.push_back(static_cast<int>(e));
  for (std::size_t f = 0; f < q.faces.size(); ++f) {
    const auto& fe = q.face_edges[f];
    Row& r0 = row(fe[0]);
    if (find(parent, fe[0]) == find(parent, fe[1])) r0.crosses_itself = true;
    r0.faces.push_back(static_cast<int>(f));
    row(fe[1]).faces.push_back(static_cast<int>(f));
  }
  return rows;
}

/// What the coarsening knows of every vertex: on a sharp feature line or the border, and
/// whether it is a corner of them (one, or three or more, such edges).
struct Features {
  std::vector<int> count;  // feature edges at each vertex
  std::vector<char> edge;  // per edge: sharp or border
  bool on(int v) const { return count[v] > 0; }
  bool corner(int v) const { return count[v] > 0 && count[v] != 2; }
};

Features features_of(const QuadList& q, double angle) {
  Features f;
  f.count.assign(q.points.size(), 0);
  f.edge.assign(q.ends.size(), 0);
  for (std::size_t e = 0; e < q.ends.size(); ++e) {
    bool sharp = q.boundary(static_cast<int>(e));
    if (!sharp && q.faces_of[e].size() == 2)
      sharp =
          angle_between(q.normal(q.faces_of[e][0].first), q.normal(q.faces_of[e][1].first)) > angle;
    if (q.faces_of[e].size() > 2) sharp = true;
    if (!sharp) continue;
    f.edge[e] = 1;
    for (int v : q.ends[e]) ++f.count[v];
  }
  return f;
}

/// Measures of one cross edge of a row: the bend along the row there, and the rows beside it.
struct Beside {
  int far = -1;                 // the far end of the cross edge of the neighbouring row at this end
  double width = 0;             // that edge's length [mm]
  double ruling_curvature = 0;  // fold across the rail between the two rows [1/mm]
};

/// The cross edges of the rows beside \p e at its end \p v (through each face of e: along the
/// rail at v into the face beyond, and the edge of that face at v other than the rail).
std::vector<Beside> beside(const QuadList& q, int e, int v) {
  std::vector<Beside> out;
  for (const auto& [f, k] : q.faces_of[e]) {
    const Quad& c = q.faces[f];
    // The rail at v in face f: the edge of f at v other than e.
    const int at = c[k] == v ? k : (k + 1) % 4;
    const int rail_local = at == k ? (k + 3) % 4 : (k + 1) % 4;
    const int rail = q.face_edges[f][rail_local];
    for (const auto& [g, kg] : q.faces_of[rail]) {
      if (g == f) continue;
      const Quad& d = q.faces[g];
      const int j = static_cast<int>(std::find(d.begin(), d.end(), v) - d.begin());
      if (j == 4) continue;
      const int ea = q.face_edges[g][j], eb = q.face_edges[g][(j + 3) % 4];
      const int cross = ea == rail ? eb : ea;
      const int far = q.ends[cross][0] == v ? q.ends[cross][1] : q.ends[cross][0];
      out.push_back({far, q.length(cross), q.curvature_across(rail)});
    }
  }
  return out;
}

/// Distance from \p x to the segment from \p a to \p b [mm].
double distance_to_segment3(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double t =
      d.squaredNorm() > 0 ? std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (x - (a + t * d)).norm();
}

/// The border edges at vertex \p v.
std::vector<int> border_edges_at(const QuadList& q, int v) {
  std::vector<int> out;
  for (int e : q.edges_at[v])
    if (q.boundary(e)) out.push_back(e);
  return out;
}

class Coarsener {
 public:
  Coarsener(const TargetSurface& target, const Material& material, const CoarsenOptions& o)
      : target_(target), o_(o) {
    const double g = material.shear_modulus * material.safety / material.yield_strength;
    const double h = material.thickness, d = 1.5 * o.min_cut_spacing;
    // Kerf (docs/kerf-cuts.md, docs/quad-meshing.md "Size"): beams d wide twisted by kappa d
    // over a strip l wide hold while g d sqrt(h^2 + d^2) <= 2 l / kappa.
    per_curvature_ =
        (h > 0 && std::isfinite(g) && g > 0) ? 0.5 * g * d * std::sqrt(h * h + d * d) : 0.0;
    tolerance_ = o.tolerance * bounding_box(target.mesh()).diagonal();
    // Where two borders meet at a strip's end their slots and margins take room from both
    // sides of the first cut: one spacing more on each side.
    fit_ =
        o.min_cut_length + o.bridge + 2 * o.kerf_margin + 2 * o.joint_depth + 2 * o.min_cut_spacing;
    // The target's border edges (edges of one triangle).
    const TriangleMesh& t = target.mesh();
    std::map<std::pair<int, int>, int> count;
    for (const auto& tri : t.triangles)
      for (int k = 0; k < 3; ++k) ++count[std::minmax(tri[k], tri[(k + 1) % 3])];
    for (const auto& [e, n] : count)
      if (n == 1) border_.push_back({t.vertices[e.first], t.vertices[e.second]});
  }

  /// Width a row needs where it folds across cross edge \p e: wide enough for its beams to
  /// hold (the torsion relation) and for a cut to fit at all; none where it hardly bends [mm].
  /// Distance from \p x to the target's border [mm]; infinity on a closed target.
  double off_border(const Vec3& x) const {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : border_) d = std::min(d, distance_to_segment3(x, s[0], s[1]));
    return d;
  }

  double needed_width(const QuadList& q, int e) const {
    if (q.fold_across(e) <= o_.min_fold) return 0.0;
    return std::max(per_curvature_ * q.curvature_across(e), fit_);
  }
  /// Widest straight ruling on a surface curving \p kappa along it within the tolerance [mm].
  double faithful_width(double kappa) const {
    return kappa > 0 ? std::sqrt(8 * tolerance_ / kappa) : std::numeric_limits<double>::infinity();
  }
  bool active() const { return per_curvature_ > 0; }

  /// Fraction of interior cross edges with a row there (its own, or one beside it) narrower
  /// than its bend needs.
  double narrow_fraction(const QuadList& q) const {
    int narrow = 0, all = 0;
    for (const Row& r : rows_of(q))
      for (int e : r.edges) {
        if (q.boundary(e)) continue;
        ++all;
        narrow += narrow_at(q, e) ? 1 : 0;
      }
    return all ? static_cast<double>(narrow) / all : 0.0;
  }

  /// True when the row through cross edge \p e, or a row beside it there, is narrower than its
  /// bend needs and could be that wide: a straight ruling that long stays within the tolerance
  /// on the surface's curvature across the rows (where it could not, widening is no cure and
  /// the resolve stage makes facets there instead).
  bool narrow_at(const QuadList& q, int e) const {
    const double need = needed_width(q, e);
    if (!(need > 0)) return false;
    bool narrow = q.length(e) < need;
    double across = 0;
    for (int v : q.ends[e])
      for (const Beside& b : beside(q, e, v)) {
        narrow = narrow || b.width < need;
        across = std::max(across, b.ruling_curvature);
      }
    return narrow && need <= faithful_width(across);
  }

  /// Rows worth collapsing, narrowest (relative to the bend's need) first.
  std::vector<int> candidates(const QuadList& q, const std::vector<Row>& rows,
                              const Features& feat) const {
    std::vector<std::pair<double, int>> ranked;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const Row& row = rows[r];
      if (row.crosses_itself || row.faces.empty()) continue;
      int interior = 0, narrow = 0;
      double relative = 0;
      bool sharp = false;
      for (int e : row.edges) {
        if (q.boundary(e)) continue;
        sharp = sharp || feat.edge[e];
        ++interior;
        if (narrow_at(q, e)) ++narrow;
        const double need = needed_width(q, e);
        relative += need > 0 ? std::min(10.0, q.length(e) / need) : 10.0;
      }
      if (sharp || interior == 0 || narrow < o_.need_fraction * interior) continue;
      ranked.push_back({relative / interior, static_cast<int>(r)});
    }
    std::sort(ranked.begin(), ranked.end());
    std::vector<int> out;
    for (const auto& [score, r] : ranked) out.push_back(r);
    return out;
  }

  /// Rows \p rows collapsed (none touching another's quads), or nothing where that may not
  /// be: the new list.
  std::optional<QuadList> collapse(const QuadList& q, const std::vector<const Row*>& rows,
                                   const Features& feat, const Shape& shape) const {
    std::vector<int> parent(q.points.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (const Row* row : rows)
      for (int e : row->edges) {
        const int a = find(parent, q.ends[e][0]), b = find(parent, q.ends[e][1]);
        if (a != b) parent[a] = b;
      }
    std::map<int, std::vector<int>> groups;
    for (const Row* row : rows)
      for (int e : row->edges)
        for (int v : q.ends[e]) groups[find(parent, v)].push_back(v);
    QuadList out;
    out.points = q.points;
    std::set<int> moved;
    for (auto& [root, members] : groups) {
      std::sort(members.begin(), members.end());
      members.erase(std::unique(members.begin(), members.end()), members.end());
      std::vector<int> on, corners;
      for (int v : members) {
        if (feat.on(v)) on.push_back(v);
        if (feat.corner(v)) corners.push_back(v);
      }
      Vec3 p = Vec3::Zero();
      if (corners.size() > 1) return std::nullopt;
      if (corners.size() == 1) {
        p = q.points[corners[0]];
      } else if (on.size() == 1) {
        p = q.points[on[0]];
      } else if (on.size() > 1) {
        // Two feature or border vertices merge only as the two ends of a border edge (the
        // row's end on the border): the border straightens there, while it stays within the
        // tolerance of the target's border, or no farther than it was (a coarsened open
        // surface once lost 4 % of its diagonal along its border).
        if (on.size() != 2) return std::nullopt;
        const int shared = q.edge(on[0], on[1]);
        if (shared < 0 || !q.boundary(shared)) return std::nullopt;
        p = target_.closest(0.5 * (q.points[on[0]] + q.points[on[1]])).point;
        double was = std::max(off_border(q.points[on[0]]), off_border(q.points[on[1]]));
        std::vector<Vec3> beyond;
        for (int k = 0; k < 2; ++k)
          for (int e : border_edges_at(q, on[k])) {
            const int b = q.ends[e][0] == on[k] ? q.ends[e][1] : q.ends[e][0];
            if (b == on[1 - k]) continue;
            beyond.push_back(q.points[b]);
            was = std::max(was, off_border(q.points[b]));
          }
        double now = off_border(p);
        for (const Vec3& b : beyond) now = std::max(now, off_border(0.5 * (b + p)));
        if (now > std::max(was, tolerance_)) return std::nullopt;
      } else {
        for (int v : members) p += q.points[v];
        p = target_.closest(p / static_cast<double>(members.size())).point;
      }
      for (int v : members) {
        out.points[v] = p;
        moved.insert(v);
      }
    }
    std::set<int> dropped;
    for (const Row* row : rows) dropped.insert(row->faces.begin(), row->faces.end());
    for (std::size_t f = 0; f < q.faces.size(); ++f) {
      if (dropped.count(static_cast<int>(f))) continue;
      Quad c = q.faces[f];
      for (int& v : c) v = find(parent, v);
      std::set<int> distinct(c.begin(), c.end());
      if (distinct.size() != 4) return std::nullopt;
      out.faces.push_back(c);
    }
    // The merged vertex keeps one of the ids (the root); its position is the group's.
    for (auto& [root, members] : groups) out.points[root] = out.points[members.front()];
    const auto mesh = to_mesh(out);
    if (!mesh) return std::nullopt;
    const Shape after = shape_of(*mesh);
    if (after.euler != shape.euler || after.borders != shape.borders) return std::nullopt;
    out.index();
    // Every quad at a moved vertex: convex, corners in range, facing the target's way.
    for (std::size_t f = 0; f < out.faces.size(); ++f) {
      const Quad& c = out.faces[f];
      bool touched = false;
      for (int v : c) touched = touched || moved.count(v) || groups.count(v);
      if (touched && !sound(out, static_cast<int>(f))) return std::nullopt;
    }
    return out;
  }

  /// True when quad \p f of \p q is convex, its corners within [min_corner, max_corner], and
  /// it faces the way the target does at its centre.
  bool sound(const QuadList& q, int f) const { return sound(q, f, o_.min_corner, o_.max_corner); }
  bool sound(const QuadList& q, int f, double min_corner, double max_corner) const {
    const Quad& c = q.faces[f];
    const Vec3 n = q.normal(f);
    if (n.isZero()) return false;
    for (int k = 0; k < 4; ++k) {
      const Vec3 a = q.points[c[(k + 3) % 4]] - q.points[c[k]];
      const Vec3 b = q.points[c[(k + 1) % 4]] - q.points[c[k]];
      const double angle = angle_between(a, b);
      if (angle < min_corner || angle > max_corner) return false;
      if (b.cross(a).dot(n) <= 0) return false;  // reflex corner
    }
    return n.dot(target_.closest(q.centre(f)).normal) > 0;
  }

  /// True when \p coarse, a level of subdivision of \p fine taken back (\p from: per coarse
  /// quad its four finer ones), keeps faith with the target: every quad sound (its corners in
  /// range, or within kSubdivisionSlack of its finer quads' corners where those are out of it:
  /// the quads round an uneven vertex keep about their shape level after level, a few degrees
  /// sharper on the coarser one: Spot's cage 19.8 deg where its subdivisions have 20.9, 23.2
  /// where they have 25), and the middles of its
  /// edges and its quads (where the finer mesh had its E and F points, on the surface) within
  /// the tolerance of the target: a straight ruling across a row twice as wide misses the
  /// surface by no more.
  bool keeps_faith(const QuadList& coarse, const QuadList& fine,
                   const std::vector<std::array<int, 4>>& from) const {
    for (std::size_t f = 0; f < coarse.faces.size(); ++f) {
      double lo = o_.min_corner, hi = o_.max_corner;
      for (int g : from[f]) {
        const auto [a, b] = corner_range(fine, g);
        lo = std::min(lo, a - kSubdivisionSlack), hi = std::max(hi, b + kSubdivisionSlack);
      }
      if (!sound(coarse, static_cast<int>(f), lo, hi) ||
          target_.closest(coarse.centre(static_cast<int>(f))).distance > tolerance_)
        return false;
    }
    for (const auto& e : coarse.ends)
      if (target_.closest(0.5 * (coarse.points[e[0]] + coarse.points[e[1]])).distance > tolerance_)
        return false;
    return true;
  }

  /// True when the rows beside \p row stay faithful once it is collapsed: each of their cross
  /// edges at the row's vertices, from the merged point to its far end, no longer than a
  /// straight ruling may be on the surface's curvature across the rail (or than it was).
  bool faithful(const QuadList& q, const Row& row) const {
    for (int e : row.edges) {
      const Vec3 mid = 0.5 * (q.points[q.ends[e][0]] + q.points[q.ends[e][1]]);
      for (int v : q.ends[e])
        for (const Beside& b : beside(q, e, v)) {
          const double width = (q.points[b.far] - mid).norm();
          if (width > std::max(b.width, faithful_width(b.ruling_curvature))) return false;
        }
    }
    return true;
  }

 private:
  const TargetSurface& target_;
  const CoarsenOptions& o_;
  double per_curvature_ = 0;                 // strip width needed per unit of bend curvature [mm^2]
  double fit_ = 0;                           // strip width a cut needs to fit at all [mm]
  std::vector<std::array<Vec3, 2>> border_;  // the target's border edges
  double tolerance_ = 0;                     // [mm]
  /// How much sharper or flatter than its finer quads a coarser quad's corners may be where
  /// those are out of range [rad].
  static constexpr double kSubdivisionSlack = 5 * M_PI / 180;
};

}  // namespace

/// A coarsening is kept only if it lowers the fraction of narrow cross edges by this much [-].
constexpr double kLeast = 0.02;

namespace {

/// What one way of coarsening gave: the mesh, compact, and its counts.
struct Attempt {
  QuadList quads;
  int levels = 0, collapsed = 0, refused = 0;
  double narrow = 0;
};

/// Rows of \p q collapsed, narrowest first (coarsen_quads), with \p levels of subdivision
/// taken back before; \p narrow: the narrow fraction of \p q as it is.
Attempt collapse_rows(QuadList q, int levels, double narrow, const Coarsener& c,
                      const CoarsenOptions& options, const Shape& shape) {
  Attempt out;
  out.levels = levels;
  std::set<std::vector<int>> refused;  // rows (by their faces' corners) that could not go
  // Each pass collapses, narrowest first, every candidate row whose quads and the quads around
  // them no earlier row of the pass touched (what it measured is still true), all at once; if
  // the batch is refused, the rows are tried one at a time. A pass is linear in the mesh, and
  // the widths about double per pass where rows are narrow.
  for (int pass = 0; pass < 10000; ++pass) {
    const std::vector<Row> rows = rows_of(q);
    const Features feat = features_of(q, options.feature_angle);
    std::vector<std::vector<int>> faces_at(q.points.size());
    for (std::size_t f = 0; f < q.faces.size(); ++f)
      for (int v : q.faces[f]) faces_at[v].push_back(static_cast<int>(f));
    std::vector<char> touched(q.faces.size(), 0);
    auto key_of = [&](const Row& row) {
      std::vector<int> key;
      for (int f : row.faces) key.insert(key.end(), q.faces[f].begin(), q.faces[f].end());
      std::sort(key.begin(), key.end());
      return key;
    };
    std::vector<const Row*> batch;
    for (int r : c.candidates(q, rows, feat)) {
      const Row& row = rows[r];
      bool free = true;
      for (int f : row.faces)
        for (int v : q.faces[f])
          for (int g : faces_at[v]) free = free && !touched[g];
      if (!free) continue;
      const auto key = key_of(row);
      if (refused.count(key)) continue;
      if (!c.faithful(q, row)) {
        refused.insert(key);
        continue;
      }
      batch.push_back(&row);
      for (int f : row.faces)
        for (int v : q.faces[f])
          for (int g : faces_at[v]) touched[g] = 1;
    }
    if (batch.empty()) break;
    if (auto next = c.collapse(q, batch, feat, shape)) {
      q = std::move(*next);
      out.collapsed += static_cast<int>(batch.size());
      continue;
    }
    // Some rows of the batch may not go: found by halving (each half checked on the mesh as
    // it is), refused, and the rest collapsed at once.
    std::vector<const Row*> good;
    std::function<void(const std::vector<const Row*>&)> sort_out =
        [&](const std::vector<const Row*>& part) {
          if (part.empty()) return;
          if (c.collapse(q, part, feat, shape)) {
            good.insert(good.end(), part.begin(), part.end());
            return;
          }
          if (part.size() == 1) {
            refused.insert(key_of(*part.front()));
            return;
          }
          const std::size_t half = part.size() / 2;
          sort_out({part.begin(), part.begin() + static_cast<std::ptrdiff_t>(half)});
          sort_out({part.begin() + static_cast<std::ptrdiff_t>(half), part.end()});
        };
    sort_out(batch);
    if (!good.empty()) {
      if (auto next = c.collapse(q, good, feat, shape)) {
        q = std::move(*next);
        out.collapsed += static_cast<int>(good.size());
        continue;
      }
    }
    for (const Row* row : good) {  // each pass collapses a row or refuses one at least
      if (auto next = c.collapse(q, {row}, feat, shape)) {
        q = std::move(*next);
        ++out.collapsed;
        break;
      }
      refused.insert(key_of(*row));
    }
  }
  out.refused = static_cast<int>(refused.size());
  if (out.collapsed == 0) {  // as it came (a level taken back is compact already)
    out.narrow = narrow;
    out.quads = std::move(q);
    return out;
  }
  // Compact: only the vertices still used, in their order.
  std::vector<int> id(q.points.size(), -1);
  QuadList compact;
  for (Quad& f : q.faces)
    for (int& v : f) {
      if (id[v] < 0) {
        id[v] = static_cast<int>(compact.points.size());
        compact.points.push_back(q.points[v]);
      }
      v = id[v];
    }
  compact.faces = q.faces;
  compact.index();
  out.narrow = c.narrow_fraction(compact);
  out.quads = std::move(compact);
  return out;
}

}  // namespace

CoarsenResult coarsen_quads(const PolyMesh& quads, const TargetSurface& target,
                            const Material& material, const CoarsenOptions& options) {
  if (!(options.min_cut_spacing > 0)) throw InvalidInput("coarsening: min_cut_spacing must be > 0");
  if (!(options.tolerance > 0)) throw InvalidInput("coarsening: tolerance must be > 0");
  if (!(options.feature_angle > 0 && options.feature_angle < M_PI))
    throw InvalidInput("coarsening: feature_angle must be in (0, pi)");
  if (!(options.min_corner >= 0 && options.min_corner < M_PI / 4) ||
      !(options.max_corner > M_PI / 2 && options.max_corner <= M_PI))
    throw InvalidInput("coarsening: corners must be allowed within [< pi/4, > pi/2]");
  CoarsenResult out;
  out.quads = quads;
  out.quads_before = out.quads_after = static_cast<int>(quads.n_faces());
  const Coarsener c(target, material, options);
  QuadList q = to_list(quads);
  out.narrow_before = out.narrow_after = c.narrow_fraction(q);
  if (!options.enabled || !c.active()) return out;
  const auto given = to_mesh(q);
  if (!given) return out;  // not a manifold quad mesh: used as given, the later stages say why
  const Shape shape = shape_of(*given);
  Attempt best = collapse_rows(q, 0, out.narrow_before, c, options, shape);
  // Where the mesh is a subdivision, levels of it taken back first: each doubles every row's
  // width at once, where the rows of a subdivided cage cannot be collapsed one by one (they
  // wind round the model and cross themselves: Spot with 4 Catmull-Clark steps at 500 mm kept
  // 7470 of its 46,848 quads that way, 65 % of its cross edges still beside a row too narrow).
  // Taken back while each level lowers that fraction and keeps faith with the target; kept
  // where it then leaves fewer narrow rows than the rows collapsed one by one alone.
  std::vector<std::array<int, 4>> from;
  int levels = 0;
  double narrow = out.narrow_before;  // of q
  for (auto coarse = taken_back(q, &from); coarse; coarse = taken_back(q, &from)) {
    for (Vec3& p : coarse->points) p = target.closest(p).point;
    const auto mesh = to_mesh(*coarse);
    if (!mesh) break;
    const Shape s = shape_of(*mesh);
    if (s.euler != shape.euler || s.borders != shape.borders || !c.keeps_faith(*coarse, q, from))
      break;
    const double coarser = c.narrow_fraction(*coarse);
    if (coarser > narrow - kLeast) break;
    q = std::move(*coarse);
    narrow = coarser;
    ++levels;
  }
  if (levels > 0) {
    Attempt taken = collapse_rows(std::move(q), levels, narrow, c, options, shape);
    if (taken.narrow < best.narrow - kLeast) best = std::move(taken);
  }
  out.rows_refused = best.refused;
  if (best.levels == 0 && best.collapsed == 0) return out;
  // Kept only where it helped: fewer places with a row too narrow that could be wide enough
  // (a ring 15 mm tall that needs 49 mm strips merges its two rows into one, still too narrow,
  // and its facets then come out narrower).
  if (best.narrow > out.narrow_before - kLeast) {
    out.rows_refused += best.collapsed;
    return out;
  }
  out.levels_taken_back = best.levels;
  out.rows_collapsed = best.collapsed;
  out.quads = *to_mesh(best.quads);
  out.quads_after = static_cast<int>(out.quads.n_faces());
  out.narrow_after = best.narrow;
  return out;
}

std::optional<PolyMesh> take_back_subdivision(const PolyMesh& quads) {
  if (!is_all_quads(quads)) return std::nullopt;
  const auto coarse = taken_back(to_list(quads));
  return coarse ? to_mesh(*coarse) : std::nullopt;
}

}  // namespace kerfab

#include "kerfab/quads/quads.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <future>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "kerfab/adapters/remesh.h"
#include "kerfab/core/errors.h"
#include "kerfab/core/parallel.h"
#include "kerfab/quads/cleanup.h"
#include "kerfab/quads/dislocations.h"
#include "kerfab/quads/fields.h"
#include "kerfab/quads/lattice.h"
#include "kerfab/quads/sweep.h"

namespace kerfab {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// Pure and split lattices are told apart by their sharp features on quad edges first when
/// the two differ by more than this share of the feature length.
constexpr double kFeatureMargin = 0.1;
/// The lattice held on the feature lines is taken where the feature length it leaves off quad
/// edges is at most this share of what the lattice as the fields come leaves [-].
constexpr double kHeldShare = 0.6;
/// ... tried only where the lattice as the fields come leaves at most this share of the feature
/// length off quad edges [-] (a star prism 6 %, fandisk 9 %).
constexpr double kFollowedShare = 0.5;
/// Where one of them gives a count asked for within this share of it and the other does not,
/// that one is taken first.
constexpr double kCountMargin = 0.1;
/// Then by how close their corners lie to the target, where the split lattice's lie farther on
/// average by more than this share of the quad size: the strips stage puts every corner on the
/// target along its normal, blind to the quads around it, so a corner far off comes out of it
/// with its quads skewed or crushed. stanford-bunny at 250 mm (quads of 17.8 mm): the split
/// lattice's corners 2.75 mm off on average (its new points at plain midpoints and centres, up
/// to 11.4 mm off), the pure one's 1.52 mm; whole run with the split against the pure one:
/// parts left unresolved 15 -> 0, borders without a joint 9 -> 1, Hausdorff 3.53 -> 3.00 % of
/// the diagonal. bob_tri (16.1 mm): 2.69 against 1.00 mm, Hausdorff 2.33 -> 1.78 %, parts
/// 185 -> 224. The sphere's split lattice lies on it (0 against 0): the irregular vertices
/// decide there.
constexpr double kCloserMargin = 0.05;
/// The dislocation step's longest path, in triangles crossed (about 30 remeshed edges, eight
/// lattice spacings: a lattice of 1/3.5 spacing remeshing edges).
constexpr int kMaxDislocationPath = 100;
/// A border that turns by more than this [rad] between its points kBorderCornerReach quad
/// sizes before and after a vertex has a corner there (border_corners()) ...
constexpr double kBorderCornerTurn = 40.0 * kPi / 180.0;
/// ... one quad size: at a quarter or half of it, stanford-bunny's scan holes had 3-8 such
/// points and its run came out worse.
constexpr double kBorderCornerReach = 1.0;
/// ... where the border on either side stays within this share of that reach of the straight
/// line from the vertex.
constexpr double kBorderCornerStraight = 0.1;
/// The sharp edges may be at most this many times the area over the quad size long: a quarter
/// of the quads' edges (make_quad_mesh) [-].
constexpr double kMaxFeatureShare = 0.5;
/// Where the size rule's quads cannot follow the sharp edges (kMaxFeatureShare), the size is made
/// this much finer than the largest that can, so that the creases found at the new size do not
/// tip it over again [-].
constexpr double kFinerForFeatures = 0.95;

/// The 3D length of \p edges (vertex pairs of \p mesh) in all [mm].
double edges_length(const TriangleMesh& mesh, const std::vector<std::array<int, 2>>& edges) {
  double length = 0;
  for (const auto& [u, v] : edges) length += (mesh.vertices[u] - mesh.vertices[v]).norm();
  return length;
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(3);
  os << v;
  return os.str();
}

double smoothstep(double x, double lo, double hi) {
  const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

/// Area-weighted quantile of \p values.
double weighted_quantile(const std::vector<double>& values, const std::vector<double>& weights,
                         double q) {
  std::vector<std::size_t> order(values.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return values[a] < values[b]; });
  double total = 0;
  for (double w : weights) total += w;
  double acc = 0;
  for (auto i : order) {
    acc += weights[i];
    if (acc >= q * total) return values[i];
  }
  return values.empty() ? 0.0 : values[order.back()];
}

/// The triangles round each edge of a triangle mesh and the angle it folds by.
struct Folds {
  using Edge = std::pair<int, int>;
  explicit Folds(const TriangleMesh& m) : mesh(m) {
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t)
      for (int k = 0; k < 3; ++k) faces_of[edge_of(t, k)].push_back(t);
    for (const auto& [edge, faces] : faces_of)
      fold[edge] = faces.size() == 2 ? angle_between(normal(faces[0]), normal(faces[1])) : -1.0;
  }
  /// Side \p k of triangle \p t.
  Edge edge_of(int t, int k) const {
    return std::minmax(mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]);
  }
  /// Normal of triangle \p t (not normalised).
  Vec3 normal(int t) const {
    const auto& tr = mesh.triangles[t];
    return (mesh.vertices[tr[1]] - mesh.vertices[tr[0]])
        .cross(mesh.vertices[tr[2]] - mesh.vertices[tr[0]]);
  }
  const TriangleMesh& mesh;
  std::map<Edge, std::vector<int>> faces_of;
  std::map<Edge, double> fold;  ///< [rad]; -1 on the border and at non-manifold edges
};

/// Edges folding by more than \p angle [rad] (borders are added by the remesher).
std::vector<std::array<int, 2>> sharp_edges(const Folds& folds, double angle) {
  std::vector<std::array<int, 2>> out;
  for (const auto& [edge, fold] : folds.fold)
    if (fold > angle) out.push_back({edge.first, edge.second});
  return out;
}

/// A shallow fold is a feature line too where both its sides are planes: folding more than
/// this [rad] (the plate step's fold, resolve.cpp) ...
constexpr double kCreaseAngle = 20 * kPi / 180;
/// ... while every other edge of its two triangles folds under this share of it (or over
/// kCreaseAngle, where such folds meet) [-], and on both sides the triangles facing within this
/// share of it from the first reach kCreaseReach across it (a wall, a roof plane). A house's
/// eaves fold 47 degrees, under the 60 of --quad-feature-angle: rows of quads crossed them,
/// each quad half bent round the eave, and the wall and roof planes beside them came out as
/// kerfed strips. The reach tells panels from a coarse tessellation of a curved surface:
/// Spot's flanks fold 28-33 degrees along 4 edges between flat triangles, fandisk's faceted
/// fillets 22, the facets of a 12-sided prism 30, but none of them is a plane three quads wide
/// (a reach of one quad size took Spot's and fandisk's, and their runs came out no more
/// buildable) ...
constexpr double kCreaseFlatness = 0.25;
/// ... in quad sizes [-] ...
constexpr double kCreaseReach = 3.0;
/// ... or, on one side, a plane this many quad sizes across that folds over kCreaseAngle close
/// all round (a chamfer: a 200 mm cube's 28 mm chamfers at 23.9 mm quads, 39 -> 10 parts;
/// fandisk's sharp lines fade into shallow folds beside planes a quad wide that curve away
/// beyond, and with those its run came out no more buildable) [-] ...
constexpr double kCreaseNearReach = 1.0;
/// ... and the lines they make count where this many quad sizes long [-]. The sheets of the
/// twelve shared triangle meshes at 250 mm come out byte-identical with and without them.
constexpr double kCreaseLine = 3.0;

/// Edges folding more than kCreaseAngle but at most \p angle [rad] between two flat sides
/// (kCreaseFlatness), each a plane reaching kCreaseReach quad sizes \p size [mm] across the edge
/// or, on one side, a narrower plane (at least kCreaseNearReach across) closed all round by
/// such folds or sharper ones (a chamfer).
std::vector<std::array<int, 2>> shallow_creases(const Folds& folds, double angle, double size) {
  using Edge = Folds::Edge;
  const TriangleMesh& mesh = folds.mesh;
  struct Side {
    bool wide = false;    // reaches kCreaseReach quad sizes across
    bool closed = false;  // else reaches kCreaseNearReach and is closed by folds
  };
  // The triangles joined to \p start facing within \p flat of it (a plane, not just a smooth
  // surface), how far they reach from the line of \p crease, across it, and whether every edge
  // round them folds more than kCreaseAngle (a bounded search: it stops once wide).
  const auto side = [&](int start, const Edge& crease, double flat) {
    const Vec3 a = mesh.vertices[crease.first];
    const Vec3 along = (mesh.vertices[crease.second] - a).normalized();
    const Vec3 facing = folds.normal(start);
    std::vector<int> queue{start};
    std::set<int> seen{start};
    double reach = 0;
    bool closed = true;
    for (std::size_t i = 0; i < queue.size(); ++i) {
      if (i == 4096) return Side{};
      const int t = queue[i];
      for (int k = 0; k < 3; ++k) {
        reach = std::max(reach, (mesh.vertices[mesh.triangles[t][k]] - a).cross(along).norm());
        if (reach >= kCreaseReach * size) return Side{true, false};
        const Edge e = folds.edge_of(t, k);
        if (e == crease) continue;
        for (int n : folds.faces_of.at(e)) {
          if (n == t || seen.count(n)) continue;
          if (angle_between(folds.normal(n), facing) < flat) {
            seen.insert(n);
            queue.push_back(n);
          } else if (!(folds.fold.at(e) > kCreaseAngle)) {
            closed = false;
          }
        }
      }
    }
    return Side{false, closed && reach >= kCreaseNearReach * size};
  };
  std::vector<std::array<int, 2>> out;
  for (const auto& [edge, faces] : folds.faces_of) {
    const double here = folds.fold.at(edge);
    if (!(here > kCreaseAngle && here <= angle)) continue;
    bool flat_sides = true;
    for (int t : faces)
      for (int k = 0; k < 3; ++k) {
        const Edge other = folds.edge_of(t, k);
        const double there = folds.fold.at(other);
        flat_sides =
            flat_sides && (other == edge || there < kCreaseFlatness * here || there > kCreaseAngle);
      }
    if (!flat_sides) continue;
    const Side one = side(faces[0], edge, kCreaseFlatness * here),
               two = side(faces[1], edge, kCreaseFlatness * here);
    if ((one.wide && (two.wide || two.closed)) || (two.wide && one.closed))
      out.push_back({edge.first, edge.second});
  }
  return out;
}

/// \p edges without the feature lines that are noise at the quad size: lines (chains through
/// vertices where exactly two sharp edges meet) shorter than \p min_length [mm]. Scans and
/// decimated meshes have many; each pins its ends and leaves slivers no quad edge can follow.
std::vector<std::array<int, 2>> drop_short_features(const TriangleMesh& mesh,
                                                    std::vector<std::array<int, 2>> edges,
                                                    double min_length) {
  for (bool changed = true; changed;) {
    changed = false;
    std::map<int, std::vector<int>> at;  // vertex -> its sharp edges
    for (int e = 0; e < static_cast<int>(edges.size()); ++e)
      for (int v : edges[e]) at[v].push_back(e);
    std::vector<char> seen(edges.size(), 0), drop(edges.size(), 0);
    for (int start = 0; start < static_cast<int>(edges.size()); ++start) {
      if (seen[start]) continue;
      std::vector<int> chain{start};
      seen[start] = 1;
      double length = (mesh.vertices[edges[start][0]] - mesh.vertices[edges[start][1]]).norm();
      for (int side = 0; side < 2; ++side) {
        int e = start, v = edges[start][side];
        while (true) {
          const auto& around = at[v];
          if (around.size() != 2) break;
          const int next = around[0] == e ? around[1] : around[0];
          if (seen[next]) break;  // back at the start: a closed line
          seen[next] = 1;
          chain.push_back(next);
          length += (mesh.vertices[edges[next][0]] - mesh.vertices[edges[next][1]]).norm();
          v = edges[next][0] == v ? edges[next][1] : edges[next][0];
          e = next;
        }
      }
      if (length < min_length) {
        for (int e : chain) drop[e] = 1;
        changed = true;
      }
    }
    std::vector<std::array<int, 2>> kept;
    for (std::size_t e = 0; e < edges.size(); ++e)
      if (!drop[e]) kept.push_back(edges[e]);
    edges = std::move(kept);
  }
  return edges;
}

/// The vertices of \p folds' mesh where its border turns sharply: the corners of an open
/// patch (a square panel's four), which the quads must keep as corners. The remesher and the
/// lattice keep the vertices where feature lines meet or end, but a border is one line that
/// turns, and without this its corners slid along it and were cut off (a saddle patch at 250 mm
/// lost 2.6 mm at each, a terrain tile 6.3 mm). A vertex is a corner where the border turns by
/// more than kBorderCornerTurn between the points of the border \p reach [mm] before and after
/// it along the border (a scan's jagged hole turns at single vertices, not over that reach),
/// the most within \p reach either way.
std::vector<int> border_corners(const Folds& folds, double reach) {
  const TriangleMesh& m = folds.mesh;
  std::map<int, std::vector<int>> next;  // border vertex -> its border neighbours
  for (const auto& [edge, faces] : folds.faces_of)
    if (faces.size() == 1) {
      next[edge.first].push_back(edge.second);
      next[edge.second].push_back(edge.first);
    }
  // The point \p reach along the border from v, leaving it towards w; the vertices passed.
  auto along = [&](int v, int w, std::vector<int>* passed) {
    Vec3 at = m.vertices[v];
    double left = reach;
    for (int from = v, to = w, steps = 0; steps < 10000; ++steps) {
      const Vec3 d = m.vertices[to] - m.vertices[from];
      const double length = d.norm();
      if (length >= left) return Vec3(m.vertices[from] + d * (left / length));
      left -= length;
      at = m.vertices[to];
      if (passed) passed->push_back(to);
      const auto it = next.find(to);
      if (it == next.end() || it->second.size() != 2 || to == v) break;
      const int after = it->second[0] == from ? it->second[1] : it->second[0];
      from = to;
      to = after;
    }
    return at;
  };
  std::map<int, double> turn;
  for (const auto& [v, nb] : next) {
    if (nb.size() != 2) continue;  // where borders meet the remesher keeps the vertex anyway
    const Vec3 before = along(v, nb[0], nullptr), after = along(v, nb[1], nullptr);
    turn[v] = angle_between(m.vertices[v] - before, after - m.vertices[v]);
  }
  std::vector<int> out;
  for (const auto& [v, t] : turn) {
    if (!(t > kBorderCornerTurn)) continue;
    // Both arms nearly straight: a corner between two lines, not a jagged or winding stretch
    // (a scan's hole) that turns as much.
    std::vector<int> near;
    const auto& nb = next.at(v);
    bool straight = true;
    for (int k = 0; k < 2; ++k) {
      std::vector<int> arm;
      const Vec3 end = along(v, nb[k], &arm);
      for (int u : arm)
        straight = straight &&
                   (m.vertices[u] - closest_on_segment(m.vertices[u], m.vertices[v], end)).norm() <=
                       kBorderCornerStraight * reach;
      near.insert(near.end(), arm.begin(), arm.end());
    }
    if (!straight) continue;
    bool most = true;
    for (int u : near) {
      const auto it = turn.find(u);
      if (u != v && it != turn.end() && (it->second > t || (it->second == t && u < v)))
        most = false;
    }
    if (most) out.push_back(v);
  }
  return out;
}

struct Topology {
  int euler = 0;
  int boundaries = 0;
};

Topology topology(const TriangleMesh& mesh) {
  const std::map<std::pair<int, int>, int> edges = edge_uses(mesh);
  std::set<int> used;
  for (const auto& t : mesh.triangles) used.insert(t.begin(), t.end());
  Topology out;
  out.euler = static_cast<int>(used.size()) - static_cast<int>(edges.size()) +
              static_cast<int>(mesh.triangles.size());
  // Border loops: border edges chained at their vertices (each border vertex of a manifold
  // has one outgoing border edge per loop through it; count loops by union-find).
  std::map<int, int> parent;
  std::function<int(int)> find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  int border_edges = 0;
  for (const auto& [e, n] : edges)
    if (n == 1) {
      ++border_edges;
      for (int v : {e.first, e.second})
        if (!parent.count(v)) parent[v] = v;
      const int a = find(e.first), b = find(e.second);
      if (a != b) parent[a] = b;
    }
  std::set<int> roots;
  for (auto& [v, p] : parent) roots.insert(find(v));
  out.boundaries = border_edges ? static_cast<int>(roots.size()) : 0;
  return out;
}

/// The quad size rule's curvatures are sampled at about this many vertices at most [-]
/// (stanford-bunny, 35k vertices, and every mesh smaller: all of them).
constexpr int kCurvatureSamples = 100000;

/// Tubes: the lattice lays about pi t / s quads round a tube t thick; where that rounds to 3 or
/// fewer (under this) the ring is a prism folded 120 deg at every edge or worse ...
constexpr double kFewestRoundTubes = 3.5;
/// ... and the quads are made small enough to go this many times round it [-] ...
constexpr double kQuadsRoundTubes = 4;
/// ... round the thinnest tubes that make up this much of the surface (a tail or a finger tip
/// alone does not size the whole model) [-].
constexpr double kThinTubeShare = 0.05;

/// The thickness of \p surface at each of its vertices that lies on a tube, +inf at the others:
/// how far the line into the solid along the vertex's normal goes to the surface's other side
/// [mm]. On a tube, the larger curvature is about 2 / thickness (here 1.3 to 3 / thickness:
/// not a plate's flat side, nor a hole's wall in it, nor a solid much thicker than it curves)
/// and the smaller under half of it (not a ball). Every \p stride -th vertex only.
std::vector<double> tube_thickness(const quads::Surface& surface, const TargetSurface& target,
                                   const quads::Curvatures& k, double diagonal, int stride) {
  const TriangleMesh& mesh = *surface.mesh;
  const int n = (static_cast<int>(mesh.vertices.size()) + stride - 1) / stride;
  std::vector<double> out(n, std::numeric_limits<double>::infinity());
  // Hits nearer than this are the vertex's own surface [mm].
  const double own = 1e-3 * diagonal;
  for_each_index(n, hardware_threads(), [&](int j) {
    const int i = j * stride;
    if (!(surface.normals[i].squaredNorm() > 0.5)) return;
    double t = std::numeric_limits<double>::infinity();
    for (const RayHit& h : target.hits_along_line(mesh.vertices[i], -surface.normals[i], diagonal))
      if (h.t > own) t = std::min(t, h.t);
    const double round = k.larger[i] * t;
    if (round >= 1.3 && round <= 3 && k.smaller[i] < 0.5 * k.larger[i]) out[j] = t;
  });
  return out;
}

QuadSizeRule choose_size(const TargetSurface& target, double diagonal, const Material& material,
                         const QuadMeshOptions& o) {
  QuadSizeRule rule;
  const quads::Surface surface = quads::make_surface(target.mesh());
  for (double a : surface.areas) rule.area += a;
  // The curvatures' quantiles over every stride-th vertex of a large mesh, weighted by their
  // areas: a 1M-triangle sphere spent 11.7 s here on all 500k vertices.
  const int n = static_cast<int>(surface.areas.size());
  const int stride = std::max(1, (n + kCurvatureSamples - 1) / kCurvatureSamples);
  const quads::Curvatures k = quads::principal_curvatures(surface, diagonal / 60.0, stride);
  std::vector<double> larger, smaller, areas;
  for (int i = 0; i < n; i += stride) {
    larger.push_back(k.larger[i]);
    smaller.push_back(k.smaller[i]);
    areas.push_back(surface.areas[i]);
  }
  rule.bend_curvature = weighted_quantile(larger, areas, 0.8);
  rule.ruling_curvature = weighted_quantile(smaller, areas, 0.8);
  rule.tube_thickness = weighted_quantile(tube_thickness(surface, target, k, diagonal, stride),
                                          areas, kThinTubeShare);
  rule.tube_size = kPi * rule.tube_thickness / kQuadsRoundTubes;
  // Kerf: beams d wide, twisted by kappa d over a strip l wide, hold while
  // g d sqrt(h^2 + d^2) <= 2 l / kappa (docs/kerf-cuts.md); with d = 1.5 x the minimum cut
  // spacing (room to place them) the strip must be at least this wide.
  const double g = material.shear_modulus * material.safety / material.yield_strength;
  const double h = material.thickness, d = 1.5 * o.min_cut_spacing;
  rule.kerf_size = (h > 0 && std::isfinite(g) && g > 0)
                       ? 0.5 * g * d * std::sqrt(h * h + d * d) * rule.bend_curvature
                       : 0.0;
  // Fidelity: a straight ruling l long on a surface curving kappa that way misses it by
  // kappa l^2 / 8.
  const double tol = o.tolerance * diagonal;
  rule.fidelity_size = rule.ruling_curvature > 0 ? std::sqrt(8 * tol / rule.ruling_curvature)
                                                 : std::numeric_limits<double>::infinity();
  const double s_min = std::sqrt(rule.area / o.max_quads),
               s_max = std::sqrt(rule.area / o.min_quads);
  if (o.quad_size) {
    rule.size = *o.quad_size;
    rule.reason = o.quad_size_from;
  } else if (o.quads) {
    rule.size = std::sqrt(rule.area / *o.quads);
    rule.reason = "--quads";
  } else if (rule.kerf_size >= rule.fidelity_size) {
    rule.size = std::clamp(rule.kerf_size, s_min, s_max);
    rule.reason = rule.size == rule.kerf_size ? "kerf (strips wide enough to bend)" : "quad count";
  } else {
    // Between the two bounds: the widest strips that are still faithful (fewest parts).
    rule.size = std::clamp(rule.fidelity_size, s_min, s_max);
    rule.reason =
        rule.size == rule.fidelity_size ? "fidelity (rulings within tolerance)" : "quad count";
  }
  // Whatever the strips would take, the quads must go round the shape's thin tubes.
  if (!o.quad_size && !o.quads && kPi * rule.tube_thickness / rule.size < kFewestRoundTubes) {
    rule.size = std::max(rule.tube_size, s_min);
    rule.reason = rule.size == rule.tube_size ? "tubes (4 quads round the thinnest)" : "quad count";
  }
  return rule;
}

/// The corners of quad \p f of \p q, in order [mm].
std::array<Vec3, 4> quad_points(const PolyMesh& q, OpenMesh::FaceHandle f) {
  const auto v = quad_vertices(q, f);
  std::array<Vec3, 4> p;
  for (int c = 0; c < 4; ++c) p[c] = to_eigen(q.point(OpenMesh::VertexHandle(v[c])));
  return p;
}

/// Per corner of quad \p p, the cross product of its two sides (next, previous); their sum is
/// along the quad's normal. A convex quad has every one of them pointing the sum's way.
std::array<Vec3, 4> corner_normals(const std::array<Vec3, 4>& p) {
  std::array<Vec3, 4> n;
  for (int c = 0; c < 4; ++c) n[c] = (p[(c + 1) % 4] - p[c]).cross(p[(c + 3) % 4] - p[c]);
  return n;
}

Vec3 sum_of(const std::array<Vec3, 4>& n) { return n[0] + n[1] + n[2] + n[3]; }

std::array<double, 4> corner_angles(const PolyMesh& q, OpenMesh::FaceHandle f) {
  const auto p = quad_points(q, f);
  std::array<double, 4> out{};
  for (int c = 0; c < 4; ++c) out[c] = angle_between(p[(c + 3) % 4] - p[c], p[(c + 1) % 4] - p[c]);
  return out;
}

/// The feature (sharp or border) segments of a triangle mesh, found by position.
class FeatureLines {
 public:
  struct Nearest {
    double distance = std::numeric_limits<double>::infinity();
    Vec3 point = Vec3::Zero(), tangent = Vec3::Zero();
  };

  /// Segments are looked up within \p reach [mm] (> 0) of a point.
  FeatureLines(const FeatureTriangleMesh& features, double reach) : cell_(reach) {
    for (const auto& [a, b] : features.features) {
      const Vec3 pa = features.mesh.vertices[a], pb = features.mesh.vertices[b];
      if (!((pb - pa).norm() > 0)) continue;
      const int s = static_cast<int>(segments_.size());
      segments_.push_back({pa, pb});
      const auto lo = key(pa.cwiseMin(pb) - Vec3::Constant(reach));
      const auto hi = key(pa.cwiseMax(pb) + Vec3::Constant(reach));
      for (long x = lo[0]; x <= hi[0]; ++x)
        for (long y = lo[1]; y <= hi[1]; ++y)
          for (long z = lo[2]; z <= hi[2]; ++z) grid_[{x, y, z}].push_back(s);
    }
  }

  /// The nearest point of a feature line within the reach of \p p (distance infinite if none).
  Nearest nearest(const Vec3& p) const {
    Nearest out;
    const auto it = grid_.find(key(p));
    if (it == grid_.end()) return out;
    for (int s : it->second) {
      const auto& [a, b] = segments_[s];
      const Vec3 d = b - a;
      const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const Vec3 c = a + t * d;
      if ((c - p).norm() < out.distance) out = {(c - p).norm(), c, d.normalized()};
    }
    return out;
  }

 private:
  std::array<long, 3> key(const Vec3& p) const {
    return {static_cast<long>(std::floor(p.x() / cell_)),
            static_cast<long>(std::floor(p.y() / cell_)),
            static_cast<long>(std::floor(p.z() / cell_))};
  }
  double cell_;
  std::vector<std::pair<Vec3, Vec3>> segments_;
  std::map<std::array<long, 3>, std::vector<int>> grid_;
};

/// How far a quad corner may lie from a feature line and still be moved onto it, as a fraction
/// of the quad size [-]. The lattice's corners on a feature line come out 0.1-4 mm off the
/// target's (the remesher keeps feature vertices on their polylines but collapses some, so its
/// lines are chords of a curved edge, and the lattice's corners are means): on fandisk at 250 mm
/// (quads of 18.6 mm) 49 of 526 corners lay within 0.01 mm of a sharp edge and 128 more within
/// 4 mm, so quads folded across the edge beside it. Moved onto it (173 then lie on it), 92.7 % of
/// the sharp-edge length lies under quad edges whose ends are on that edge, within 15 degrees
/// (24.5 % before; 89.4 % with a reach of 0.1; Quads.FandisksSharpEdgesLieOnQuadEdges: 91.0 %
/// at 0.3, 87.7 % at 0.2). Its critical regions of the first build: 66 -> 36, its largest
/// flattening angle error 56 -> 19.6 degrees.
constexpr double kFeatureSnap = 0.3;
/// How far short of a feature line a corner stops where on it one of its quads would be flat
/// [mm] (the plate step takes quads within 0.05 mm of a plane, resolve.cpp).
constexpr double kSnapShort = 0.01;
/// A quad corner whose sides' cross product is under this share of the squared quad size is
/// flat [-].
constexpr double kFlatCorner = 1e-6;

/// Quad corners \p p of one face (quads of about \p size [mm]): convex, none flat
/// (kFlatCorner) or under \p min_corner [rad], and facing the way \p normal does.
bool sound_quad(const std::array<Vec3, 4>& p, double size, double min_corner, const Vec3& normal) {
  const auto n = corner_normals(p);
  const Vec3 sum = sum_of(n);
  if (!(sum.dot(normal) > 0)) return false;
  for (int c = 0; c < 4; ++c)
    if (!(n[c].dot(sum) > 0) || !(n[c].norm() >= kFlatCorner * size * size) ||
        angle_between(p[(c + 1) % 4] - p[c], p[(c + 3) % 4] - p[c]) < min_corner)
      return false;
  return true;
}

/// How far a corner may lie from a feature line and still be moved onto it where it is a dent
/// in a row of quad edges on that line (its two neighbours on the line, on either side of where
/// it would go), as a fraction of the quad size [-]. A pentagonal prism at 250 mm: one corner of
/// the bottom 0.64 quad sizes inside its rim, between two rim corners, and the two side quads
/// over it folded 43 and 52 degrees across the rim, cut as two one-quad strips beside 7 plates.
constexpr double kDentReach = 1.0;

/// Moves corner \p v of \p q (off the line) onto the feature line at \p on, or else
/// just short of it, where every quad around it stays convex, facing as before, with no corner
/// under \p min_corner (or under its smallest before). False (the corner where it was) if none.
bool move_onto_line(PolyMesh& q, OpenMesh::VertexHandle v, const Vec3& on, double size,
                    double min_corner) {
  const auto from = q.point(v);
  std::vector<std::pair<OpenMesh::FaceHandle, std::pair<Vec3, double>>> before;
  for (auto f : q.vf_range(v)) {
    const auto angles = corner_angles(q, f);
    before.push_back({f,
                      {sum_of(corner_normals(quad_points(q, f))),
                       *std::min_element(angles.begin(), angles.end())}});
  }
  // Onto the line, or else just short of it: where another quad round the corner has two
  // more corners on the line, the corner on it would leave that quad flat (a house's gable
  // where it meets the roof line at the eave: two roof quads stayed folded 2.4 mm and were
  // cut as kerfed parts beside the roof's plate), the way the corner came.
  const Vec3 at = to_eigen(from);
  const std::array<Vec3, 2> targets = {on, Vec3(on + kSnapShort * (at - on).normalized())};
  for (const Vec3& to : targets) {
    q.set_point(v, to_openmesh(to));
    bool ok = true;
    for (const auto& [f, was] : before)
      ok = ok && sound_quad(quad_points(q, f), size, std::min(min_corner, was.second), was.first);
    if (ok) return true;
  }
  q.set_point(v, from);
  return false;
}

/// Moves the corners of \p q that lie near a feature line of \p features (the target's sharp
/// and border edges; within kFeatureSnap of the quad size \p size) onto it, where the corner is on
/// a row of quad edges along that line (one of its edges runs within 30 degrees of the line to
/// another corner near it) and every quad around it stays convex, facing as before, with no corner
/// under 10 degrees (or under its smallest before). Nearest corners first. Then the dents
/// (kDentReach): corners off the line whose two neighbours, not neighbours of each other, lie on
/// it, on either side of the corner's nearest point of it, the same way. Returns the corners
/// moved.
int snap_to_features(PolyMesh& q, const FeatureTriangleMesh& features, double size) {
  const double reach = kFeatureSnap * size;
  const FeatureLines lines(features, reach);
  const double cos_along = std::cos(30 * kPi / 180), min_corner = 10 * kPi / 180;
  std::vector<FeatureLines::Nearest> near(q.n_vertices());
  for (auto v : q.vertices()) near[v.idx()] = lines.nearest(to_eigen(q.point(v)));
  std::vector<int> order;
  for (auto v : q.vertices()) {
    const auto& n = near[v.idx()];
    if (!(n.distance <= reach) || n.distance < 1e-9 * size) continue;
    bool along = false;
    for (auto w : q.vv_range(v)) {
      const Vec3 d = to_eigen(q.point(w)) - to_eigen(q.point(v));
      along = along || (near[w.idx()].distance <= reach && d.norm() > 0 &&
                        std::abs(d.normalized().dot(n.tangent)) > cos_along);
    }
    if (along) order.push_back(v.idx());
  }
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return near[a].distance < near[b].distance; });
  int moved = 0;
  for (int i : order)
    moved += move_onto_line(q, q.vertex_handle(i), near[i].point, size, min_corner) ? 1 : 0;
  // The dents, after the rows they dent are on their lines.
  const FeatureLines far(features, kDentReach * size);
  const double on_line = 1e-6 * size, same_line = 0.02 * size;
  for (auto v : q.vertices()) {
    const FeatureLines::Nearest n = far.nearest(to_eigen(q.point(v)));
    if (!(n.distance <= kDentReach * size) || n.distance < 1e-9 * size) continue;
    std::vector<OpenMesh::VertexHandle> row;  // neighbours on the same line
    for (auto w : q.vv_range(v)) {
      const Vec3 p = to_eigen(q.point(w)), d = p - n.point;
      if (far.nearest(p).distance <= on_line &&
          (d - d.dot(n.tangent) * n.tangent).norm() <= same_line)
        row.push_back(w);
    }
    if (row.size() != 2 || q.find_halfedge(row[0], row[1]).is_valid()) continue;
    const Vec3 a = to_eigen(q.point(row[0])), b = to_eigen(q.point(row[1]));
    if ((n.point - a).dot(n.point - b) >= 0) continue;  // not between them
    moved += move_onto_line(q, v, n.point, size, min_corner) ? 1 : 0;
  }
  return moved;
}

/// Length of the feature (sharp or border) edges of \p remeshed that lie along edges of \p q
/// [mm]: a feature segment counts where its middle lies on a quad edge (within 2 % of the quad
/// size \p size) running the same way (within 15 degrees).
double feature_length_on_edges(const PolyMesh& q, const FeatureTriangleMesh& remeshed,
                               double size) {
  double on_length = 0;
  for (const auto& [a, b] : remeshed.features) {
    const Vec3 pa = remeshed.mesh.vertices[a], pb = remeshed.mesh.vertices[b];
    const Vec3 mid = 0.5 * (pa + pb), dir = (pb - pa).normalized();
    bool on = false;
    for (auto e : q.edges()) {
      const Vec3 e0 = to_eigen(q.point(q.from_vertex_handle(q.halfedge_handle(e, 0))));
      const Vec3 e1 = to_eigen(q.point(q.to_vertex_handle(q.halfedge_handle(e, 0))));
      const Vec3 d = e1 - e0;
      if ((mid - e0).squaredNorm() > d.squaredNorm() + 1 &&
          (mid - e1).squaredNorm() > d.squaredNorm() + 1)
        continue;
      const double t = std::clamp((mid - e0).dot(d) / d.squaredNorm(), 0.0, 1.0);
      if ((e0 + t * d - mid).norm() < 0.02 * size &&
          std::abs(d.normalized().dot(dir)) > std::cos(15 * kPi / 180)) {
        on = true;
        break;
      }
    }
    if (on) on_length += (pb - pa).norm();
  }
  return on_length;
}

/// Inner vertices of valence other than 4 and border vertices of valence other than 3.
int irregular_vertices(const PolyMesh& q) {
  int n = 0;
  for (auto v : q.vertices())
    n += static_cast<int>(q.valence(v)) != (q.is_boundary(v) ? 3 : 4) ? 1 : 0;
  return n;
}

/// How far the target strays from the quad mesh: the largest distance from a vertex or
/// triangle centre of the target to the quads (each cut along a diagonal) [mm]. The quads'
/// corners lie on the target, but a lattice coarser than a thin part (an ear, a horn) can
/// bridge it; this sees that.
double target_gap(const PolyMesh& q, const TriangleMesh& mesh) {
  const TargetSurface quads(triangulate(q));
  double gap = 0;
  for (const Vec3& p : mesh.vertices) gap = std::max(gap, quads.closest(p).distance);
  for (const auto& t : mesh.triangles)
    gap = std::max(
        gap, quads.closest((mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0)
                 .distance);
  return gap;
}

/// Face \p f of \p q facing the target's way, convex, with no flat corner (quads of about
/// \p size [mm]).
bool sound_face(const PolyMesh& q, OpenMesh::FaceHandle f, const TargetSurface& target,
                double size) {
  const auto p = quad_points(q, f);
  const auto corner_n = corner_normals(p);
  const Vec3 quad_n = sum_of(corner_n);
  for (int c = 0; c < 4; ++c)  // convex, no flat corner
    if (!(corner_n[c].norm() >= kFlatCorner * size * size && corner_n[c].dot(quad_n) > 0))
      return false;
  // Not inside out: the target's normal at one of the corners (they lie on the target)
  // agrees (near thin parts the centre's nearest facet may be the other side's).
  if (quad_n.normalized().dot(target.closest(0.25 * (p[0] + p[1] + p[2] + p[3])).normal) > 0)
    return true;
  for (int c = 0; c < 4; ++c)
    if (quad_n.normalized().dot(target.closest(p[c]).normal) > 0) return true;
  return false;
}

/// What is wrong with \p q as a quad mesh of \p mesh (empty: nothing): not all quads, another
/// topology, or a folded, reflex or flat corner.
std::string check(const PolyMesh& q, const TriangleMesh& mesh, const TargetSurface& target,
                  double size) {
  const Topology want = topology(mesh);
  const int euler = static_cast<int>(q.n_vertices()) - static_cast<int>(q.n_edges()) +
                    static_cast<int>(q.n_faces());
  if (!is_all_quads(q)) return "not all quads";
  if (euler != want.euler)
    return "Euler characteristic " + std::to_string(euler) + " instead of " +
           std::to_string(want.euler);
  if (boundary_loop_count(q) != want.boundaries)
    return std::to_string(boundary_loop_count(q)) + " border loops instead of " +
           std::to_string(want.boundaries);
  int bad = 0;
  for (auto f : q.faces()) bad += sound_face(q, f, target, size) ? 0 : 1;
  if (bad > 0) return std::to_string(bad) + " folded, reflex or flat quads";
  const double gap = target_gap(q, mesh), max_gap = size;
  if (gap > max_gap)
    return "the target strays " + fmt(gap) + " mm from the quads (at most " + fmt(max_gap) +
           "): a thin part bridged";
  return {};
}

/// Fills in what \p r's quads are like: their corners, valences and distance from the target,
/// and how much of \p features' length lies along their edges.
void describe(QuadMeshResult& r, const TargetSurface& target, const FeatureTriangleMesh& features,
              double feature_angle, std::vector<double> raisable) {
  const PolyMesh& q = r.quads;
  r.min_corner_angle = kPi;
  r.max_corner_angle = r.mean_corner_deviation = 0;
  r.irregular_vertices = 0;
  int corners = 0, skewed = 0;
  for (auto f : q.faces())
    for (double angle : corner_angles(q, f)) {
      r.min_corner_angle = std::min(r.min_corner_angle, angle);
      r.max_corner_angle = std::max(r.max_corner_angle, angle);
      const double off_square = std::abs(angle - kPi / 2);
      r.mean_corner_deviation += off_square;
      skewed += off_square > kPi / 4 ? 1 : 0;
      ++corners;
    }
  if (corners > 0) {
    r.mean_corner_deviation /= corners;
    r.skewed_corners = static_cast<double>(skewed) / corners;
  }
  std::map<int, int> valences;
  for (auto v : q.vertices()) {
    const int val = static_cast<int>(q.valence(v));
    if (q.is_boundary(v)) {
      r.irregular_vertices += val != 3 ? 1 : 0;
      continue;
    }
    ++valences[val];
    r.irregular_vertices += val != 4 ? 1 : 0;
  }
  r.valences.assign(valences.begin(), valences.end());
  r.max_distance = vertex_distances(q, target).max;
  r.feature_length_on_quads = feature_length_on_edges(q, features, r.size.size);
  r.feature_angle = feature_angle;
  r.folds_over_feature_angle = std::move(raisable);
}

/// The most quads the stage makes [-]. Its time grows with the quads (the remeshed surface has
/// about 12 vertices per quad, each swept 200 times by the position field, and every attempt
/// is cleaned up): the bunny at 250 mm asked for 5000 quads takes 44 s, for 20,000 400 s and
/// 530 MB on a 2-core machine, so 100,000 would run for over half an hour. Quads that small
/// are far narrower than any material bends (the run warns at the size rule's kerf bound).
constexpr int kMaxQuads = 20000;

/// \p mesh smoothed by Taubin's lambda/mu steps (0.5, -0.53, umbrella weights) \p rounds times,
/// its border vertices held: noise a few facets wide goes, the shape's volume stays (G. Taubin,
/// "A signal processing approach to fair surface design", 1995).
TriangleMesh taubin_smoothed(const TriangleMesh& mesh, int rounds) {
  const int n = static_cast<int>(mesh.vertices.size());
  std::vector<std::vector<int>> nb(n);
  std::map<std::pair<int, int>, int> edge_faces;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      nb[a].push_back(b);
      ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<char> held(n, 0);
  for (const auto& [e, count] : edge_faces)
    if (count != 2) held[e.first] = held[e.second] = 1;
  for (auto& list : nb) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  TriangleMesh out = mesh;
  std::vector<Vec3> next(n);
  for (int round = 0; round < 2 * rounds; ++round) {
    const double step = round % 2 == 0 ? 0.5 : -0.53;
    for (int i = 0; i < n; ++i) {
      next[i] = out.vertices[i];
      if (held[i] || nb[i].empty()) continue;
      Vec3 mean = Vec3::Zero();
      for (int j : nb[i]) mean += out.vertices[j];
      mean /= static_cast<double>(nb[i].size());
      next[i] += step * (mean - out.vertices[i]);
    }
    out.vertices.swap(next);
  }
  return out;
}

/// Rounds of taubin_smoothed() for the copy a noisy target is meshed on [-].
constexpr int kDenoiseRounds = 10;

/// make_quad_mesh on \p target as it is (below): swept where it is an extrusion or a loft (not
/// with \p sweep false), else its lattices alone, or with \p safe_net its triangles split into
/// quads alone.
QuadMeshResult make_quad_mesh_on(const TargetSurface& target, const Material& material,
                                 const QuadMeshOptions& o,
                                 const std::function<void(const std::string&)>& progress,
                                 bool safe_net, bool sweep = true);

/// The feature angle is raised by this much at a time [rad] ...
constexpr double kFeatureAngleStep = 5.0 * kPi / 180.0;
/// ... up to this [rad].
constexpr double kMostRaisedFeatureAngle = 90.0 * kPi / 180.0;

/// \p first (made at \p o's feature angle, where the lattice at the quad size left triangles
/// with no partner and the lattice with every face split was taken) or, where raising the
/// feature angle by kFeatureAngleStep at a time, up to kMostRaisedFeatureAngle, lets that lattice
/// pair them all, the quads made at the first such angle.
/// A triangle whose three edges lie on feature lines (where three short creases meet round it,
/// as on demosthenes' bust) has no row of quads out (bridges.h: a row leaves no triangle across
/// a feature edge); one is enough to lose the lattice, and the split one makes quads too small
/// and too many (the bust at 250 mm, 3 mm MDF: 848 quads for about 400, 41 % of them with an
/// edge under 0.3 of the quad size). Dropping the shallowest creases first lets the lattice
/// through: the bust's lattice pairs at 65 deg (597 quads), and its whole run went from 5 parts
/// unresolved to 2, 39 left out to 18, Hausdorff 3.59 to 2.71 % of the diagonal
/// (docs/quad-meshing.md).
QuadMeshResult with_features_raised(const TargetSurface& target, const Material& material,
                                    const QuadMeshOptions& o,
                                    const std::function<void(const std::string&)>& progress,
                                    QuadMeshResult first) {
  QuadMeshOptions raised = o;
  int unpaired = first.unpaired_triangles;
  const std::vector<double>& folds = first.folds_over_feature_angle;
  double tried = o.feature_angle;
  for (double angle = o.feature_angle + kFeatureAngleStep; angle <= kMostRaisedFeatureAngle + 1e-9;
       angle += kFeatureAngleStep) {
    // No fold of the target between the last angle tried and this one: the same features, the
    // same quads (a chamfered cube's folds are all under 60 deg: nothing to try).
    if (std::upper_bound(folds.begin(), folds.end(), tried) ==
        std::upper_bound(folds.begin(), folds.end(), angle))
      continue;
    tried = angle;
    if (progress)
      progress(std::to_string(unpaired) + " triangles of the lattice found no partner at " +
               fmt(raised.feature_angle * 180 / kPi) + " deg; trying sharp features over " +
               fmt(angle * 180 / kPi) + " deg");
    raised.feature_angle = angle;
    try {
      QuadMeshResult r = make_quad_mesh_on(target, material, raised, progress, false);
      if (r.unpaired_triangles == 0) {
        r.feature_angle_asked = o.feature_angle;
        return r;
      }
      unpaired = r.unpaired_triangles;
    } catch (const SolverError&) {  // no lattice at all at this angle: the next one
    } catch (const InvalidInput&) {
    }
  }
  return first;
}

}  // namespace

QuadMeshResult make_quad_mesh(const TargetSurface& target, const Material& material,
                              const QuadMeshOptions& o,
                              const std::function<void(const std::string&)>& progress) {
  try {
    QuadMeshResult r = make_quad_mesh_on(target, material, o, progress, false);
    if (r.unpaired_triangles > 0 && o.raise_feature_angle)
      r = with_features_raised(target, material, o, progress, std::move(r));
    return r;
  } catch (const SolverError&) {
  }
  // No lattice on the target as given: where that is noise (a scan, ridges a few facets wide),
  // the lattice of a smoothed copy may hold. Its quads are kept where they pass the check on
  // the target itself; the strips are projected onto the target as ever. A noisy sphere of
  // 3480 triangles (3 % radial noise) got 7667 quads with 2896 irregular vertices from its
  // triangles, 600 parts and 19 left unresolved in 192 s; from the smoothed copy's lattice 402
  // quads, 100 parts, none unresolved, the strips closer to the target (Hausdorff 3.75 ->
  // 1.47 % of the diagonal). Only then the safe net, on the target as given.
  const TriangleMesh& mesh = target.mesh();
  const TriangleMesh smooth = taubin_smoothed(mesh, kDenoiseRounds);
  double moved = 0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    moved = std::max(moved, (smooth.vertices[i] - mesh.vertices[i]).norm());
  if (progress)
    progress("no lattice on the target as given; meshing a copy smoothed by " + fmt(moved) +
             " mm at most (" + std::to_string(kDenoiseRounds) + " Taubin rounds)");
  try {
    const TargetSurface copy(smooth);
    QuadMeshResult r = make_quad_mesh_on(copy, material, o, progress, false);
    // Onto the target, as every quad mesh kerfab makes, where that leaves the quads sound.
    PolyMesh onto = r.quads;
    for (auto v : onto.vertices())
      onto.set_point(v, to_openmesh(target.closest(to_eigen(onto.point(v))).point));
    std::string problem = check(onto, mesh, target, r.size.size);
    const bool projected = problem.empty();
    if (projected)
      r.quads = std::move(onto);
    else
      problem = check(r.quads, mesh, target, r.size.size);
    if (problem.empty()) {
      r.method += ", of the target smoothed by " + fmt(moved) + " mm at most" +
                  (projected ? ", corners put back onto the target" : "");
      r.max_distance = vertex_distances(r.quads, target).max;
      if (progress)
        progress("the smoothed copy's lattice taken: " + std::to_string(r.quads.n_faces()) +
                 " quads, " + std::to_string(r.irregular_vertices) + " irregular vertices");
      return r;
    }
    if (progress) progress("the smoothed copy's lattice not taken: on the target, " + problem);
  } catch (const SolverError&) {
    if (progress) progress("no lattice on the smoothed copy either");
  } catch (const InvalidInput&) {  // a triangle of no area in the copy
  }
  return make_quad_mesh_on(target, material, o, progress, true);
}

namespace {

/// Puts the border of \p cap (quads of the extrusion \p e's cap) onto the cap's outline: each
/// corner of the outline where a feature line of the wall (\p features, edges of \p mesh that
/// climb the wall) meets it takes the nearest border vertex, every other border vertex goes to
/// the nearest point of the outline (the lattice's border vertices are means of the remeshed
/// ones, and a split lattice's new ones are chords' middles: a disc's cap of 22 mm quads lay up
/// to 4 % of its radius inside the rim). False where two corners want the same vertex.
bool onto_outline(PolyMesh& cap, const quads::Extrusion& e, const TriangleMesh& mesh,
                  const std::vector<std::array<int, 2>>& features) {
  std::vector<std::array<Vec3, 2>> outline;  // the cap's border edges
  for (const auto& [a, b] : border_edges(e.cap))
    outline.push_back({e.cap.vertices[a], e.cap.vertices[b]});
  const double height = e.cap_on_top ? e.top : e.bottom;
  const double same = quads::kSameHeight * bounding_box(mesh).diagonal();
  std::vector<Vec3> corners;  // where the wall's feature lines reach the cap's plane
  for (const auto& [a, b] : features) {
    const Vec3 pa = mesh.vertices[a], pb = mesh.vertices[b];
    if (std::abs((pb - pa).dot(e.axis)) <= same) continue;  // along a rim, not up the wall
    for (const Vec3& p : {pa, pb})
      if (std::abs(p.dot(e.axis) - height) <= same &&
          std::none_of(corners.begin(), corners.end(),
                       [&](const Vec3& c) { return (c - p).norm() <= same; }))
        corners.push_back(p);
  }
  std::vector<OpenMesh::VertexHandle> border;
  for (auto v : cap.vertices())
    if (cap.is_boundary(v)) border.push_back(v);
  std::vector<char> taken(border.size(), 0);
  for (const Vec3& c : corners) {
    std::size_t best = border.size();
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < border.size(); ++i) {
      const double d = (to_eigen(cap.point(border[i])) - c).norm();
      if (d < best_d) best = i, best_d = d;
    }
    if (best == border.size() || taken[best]) return false;
    taken[best] = 1;
    cap.set_point(border[best], to_openmesh(c));
  }
  for (std::size_t i = 0; i < border.size(); ++i) {
    if (taken[i]) continue;
    const Vec3 p = to_eigen(cap.point(border[i]));
    Vec3 best = p;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : outline) {
      const Vec3 q = closest_on_segment(p, a, b);
      if ((q - p).norm() < best_d) best = q, best_d = (q - p).norm();
    }
    cap.set_point(border[i], to_openmesh(best));
  }
  return true;
}

/// \p swept, a target's sweep with a dome, or its lattice (\p lattice_of()) where the sweep has
/// more than \p share of the lattice's irregular vertices (QuadMeshOptions::domed_sweep_share);
/// the sweep where no lattice pairs every triangle. The method says which and why.
/// What a sweep gives is strips without singularities; where a dome's cap brings its own, as
/// many as the lattice has, the lattice is as good a start and came out better downstream on
/// round shapes. From their triangles at 300 mm in 3 mm MDF (docs/quad-meshing.md, "Domes"): a
/// capsule, an OpenSCAD capsule, a bowl, an open dome and a bullet swept with 0.27-0.66 of the
/// lattice's irregular vertices, and all came out with fewer parts and critical regions (the
/// capsule 51 parts against 82); an egg, a UV sphere and an OpenSCAD sphere with 0.87-1.11: the
/// egg 51 parts against the lattice's 46, the OpenSCAD sphere 52 against 39 (the UV sphere 37
/// against 40).
QuadMeshResult swept_or_lattice(QuadMeshResult swept, double share,
                                const std::function<QuadMeshResult()>& lattice_of,
                                const std::function<void(const std::string&)>& progress) {
  if (std::isinf(share)) return swept;
  if (progress)
    progress("the sweep with its dome has " + std::to_string(swept.irregular_vertices) +
             " irregular vertices; meshing the lattice to compare");
  std::optional<QuadMeshResult> lattice;
  try {
    lattice = lattice_of();
  } catch (const SolverError&) {
  } catch (const InvalidInput&) {
  }
  if (!lattice || lattice->unpaired_triangles > 0 || lattice->quads.n_faces() == 0) {
    swept.method += " (the lattice not made whole)";
    return swept;
  }
  const std::string counts = std::to_string(swept.irregular_vertices) +
                             " irregular vertices swept, " +
                             std::to_string(lattice->irregular_vertices) + " on the lattice";
  if (swept.irregular_vertices <= share * lattice->irregular_vertices) {
    swept.method += " (" + counts + ")";
    return swept;
  }
  if (progress) progress("the lattice kept: " + counts);
  lattice->method += " (a loft with a dome, not swept: " + counts + ")";
  return std::move(*lattice);
}

/// The cap's quad size tried, as factors on the first (swept_extrusion) [-].
constexpr std::array<double, 4> kCapSizeTries = {1.0, 0.9, 1.1, 0.8};

/// The target as an extrusion (quads/sweep.h), meshed so: its cap at \p sized's quad size by
/// make_quad_mesh (a flat patch), the wall swept from the cap's border in rows about as high
/// as the quads are wide, and the other cap a copy. nullopt where the target is no extrusion,
/// its cap finds no quads, or the swept quads fail the check.
/// \p domed: set to whether the target ends in a dome (its sweep then competes with the
/// lattice, swept_or_lattice).
std::optional<QuadMeshResult> swept_extrusion(
    const TargetSurface& target, const Material& material, const QuadMeshOptions& o,
    const QuadMeshResult& sized, const FeatureTriangleMesh& features,
    const std::vector<double>& raisable, const std::function<void(const std::string&)>& progress,
    bool* domed) {
  const TriangleMesh& mesh = target.mesh();
  const std::optional<quads::Extrusion> e = quads::find_extrusion(mesh);
  if (!e) return std::nullopt;
  *domed = !e->cap_dome.empty() || !e->other_dome.empty();
  const double size = sized.size.size, height = e->top - e->bottom;
  const std::vector<quads::RowBorder> borders = quads::row_borders(*e, size);
  const int rows = static_cast<int>(borders.size()) - 1;
  const bool loft = !e->profile.empty();
  // A loft's outline widest where its scale is largest: the cap's quads that much smaller, so
  // that the wall's columns are nowhere wider than the quad size. A dome's cap (lifted, so
  // stretched across its rim by up to that much) by the square root of it: its middle's quads
  // and the widest columns off the quad size by one factor. Measured on six shapes from their
  // triangles at 300 mm (UV sphere, egg, bullet, open dome, capsule, bowl): 293 parts in all
  // with the cap's quads smaller by the whole factor, 217 with no factor but Hausdorff worse
  // than with its square root on four (a capsule's 2.3 -> 5.2 mm, the sphere's 1.6 -> 4.5),
  // 247 with the square root; the lattice alone had 317 (docs/quad-meshing.md, "Domes").
  double widest = 1;
  for (const auto& [h, s] : e->profile) widest = std::max(widest, s);
  if (progress) {
    double least = 1;
    for (const auto& [h, s] : e->profile) least = std::min(least, s);
    progress(loft ? "a loft: a flat outline swept " + fmt(height) + " mm along an axis, scaled " +
                        fmt(least) + " to " + fmt(widest) + " times; meshing " +
                        (e->cap_made            ? "its rim"
                         : !e->cap_dome.empty() ? "its dome (flat, then lifted)"
                                                : "its cap") +
                        (e->other_dome.empty() ? "" : ", a copy lifted onto the other dome") +
                        ", then the wall in " + std::to_string(rows) + " rows of quads"
                  : "an extrusion: a flat outline swept " + fmt(height) +
                        " mm along an axis; meshing its cap, then the wall in " +
                        std::to_string(rows) + " rows of quads");
  }
  QuadMeshOptions cap_options = o;
  cap_options.quad_size_from = "the model's: " + sized.size.reason;
  cap_options.quads.reset();
  // A lattice quad with three corners on the cap's border can come out flat at the middle one
  // once the border is put onto the outline (two of them on one straight edge of a polygon
  // circle: a bullet's 48-gon bottom, a dome's ring): the cap is meshed again at quads a tenth
  // finer or coarser, whose border falls otherwise, before the lattice is left to do it all.
  QuadMeshResult cap, r;
  std::vector<std::array<int, 2>> along_rims, along_axis;
  for (const double factor : kCapSizeTries) {
    cap_options.quad_size = factor * size / (e->cap_dome.empty() ? widest : std::sqrt(widest));
    try {
      const TargetSurface cap_target(e->cap);
      cap = make_quad_mesh(cap_target, material, cap_options, [&](const std::string& line) {
        if (progress) progress("cap: " + line);
      });
    } catch (const SolverError& error) {
      if (progress) progress(std::string("no quads on the cap (") + error.what() + ")");
      return std::nullopt;
    } catch (const InvalidInput& error) {
      if (progress) progress(std::string("no quads on the cap (") + error.what() + ")");
      return std::nullopt;
    }
    if (!onto_outline(cap.quads, *e, mesh, features.features)) {
      if (progress) progress("the cap's quads miss a corner of its outline; not swept");
      continue;
    }
    r = sized;
    along_rims.clear();
    along_axis.clear();
    r.quads = quads::sweep_extrusion(cap.quads, *e, borders, &along_rims, &along_axis);
    r.problem = r.quads.n_faces() == 0 ? "the swept quads make no consistent surface"
                                       : check(r.quads, mesh, target, size);
    if (r.problem.empty()) break;
    if (progress) progress("the swept quads not taken: " + r.problem);
  }
  if (!r.problem.empty() || r.quads.n_faces() == 0) return std::nullopt;
  for (const auto& [a, b] : along_rims) r.bending.push_back({a, b, true});
  for (const auto& [a, b] : along_axis) r.bending.push_back({a, b, false});
  const bool both = e->top_cap && e->bottom_cap;
  const std::string kind = loft ? "loft" : "extrusion";
  r.method =
      kind +
      (e->cap_made            ? ": its rim's border from quads on its outline (" + cap.method + ")"
       : !e->cap_dome.empty() ? ": its dome meshed flat and lifted onto it (" + cap.method + ")"
                              : ": its cap meshed (" + cap.method + ")") +
      (both ? (!e->other_dome.empty() ? ", a scaled copy lifted onto the dome at the other end,"
               : loft                 ? ", a scaled copy at the other end,"
                                      : ", copied to the other end,")
            : ",") +
      " the wall swept in " + std::to_string(rows) + (rows == 1 ? " row" : " rows");
  r.remeshed_vertices = cap.remeshed_vertices;
  r.lattice_quads = cap.lattice_quads;
  r.lattice_triangles = cap.lattice_triangles;
  r.triangle_rows = cap.triangle_rows;
  r.dislocations = cap.dislocations;
  r.dislocations_left = cap.dislocations_left;
  // The sharp edges and the borders (an open end's rim), as the lattice counts them.
  FeatureTriangleMesh lines = features;
  for (const auto& edge : border_edges(mesh)) lines.features.push_back(edge);
  r.feature_edges = static_cast<int>(lines.features.size());
  r.feature_length = edges_length(mesh, lines.features);
  describe(r, target, lines, o.feature_angle, raisable);
  return r;
}

QuadMeshResult make_quad_mesh_on(const TargetSurface& target, const Material& material,
                                 const QuadMeshOptions& o,
                                 const std::function<void(const std::string&)>& progress,
                                 bool safe_net, bool sweep) {
  if (o.quads && (*o.quads < 20 || *o.quads > kMaxQuads))
    throw InvalidInput("--quads must be between 20 and " + std::to_string(kMaxQuads) + ", got " +
                       std::to_string(*o.quads));
  if (o.quad_size && !(*o.quad_size > 0 && std::isfinite(*o.quad_size)))
    throw InvalidInput("--quad-size must be > 0 mm");
  if (!(o.domed_sweep_share >= 0)) throw InvalidInput("quads: domed_sweep_share must be >= 0");
  if (!(o.feature_angle > 0 && o.feature_angle < kPi))
    throw InvalidInput("--quad-feature-angle must be between 0 and 180 degrees");
  const TriangleMesh& mesh = target.mesh();
  const double diagonal = bounding_box(mesh).diagonal();
  QuadMeshResult sized;
  sized.size = choose_size(target, diagonal, material, o);
  const double count = sized.size.area / (sized.size.size * sized.size.size);
  if (count > kMaxQuads)
    throw InvalidInput("a quad size of " + fmt(sized.size.size) + " mm would make about " +
                       fmt(count) + " quads on " + fmt(sized.size.area) + " mm^2 (at most " +
                       std::to_string(kMaxQuads) + "): pass a larger --quad-size");
  if (count < 4)
    throw InvalidInput("a quad size of " + fmt(sized.size.size) +
                       " mm leaves fewer than 4 quads on " +
                       "this model: pass a smaller --quad-size");
  // What comes next takes seconds per lattice on a large mesh (a 1M-triangle target: about 10).
  if (progress)
    progress("quad size " + fmt(sized.size.size) + " mm (" + sized.size.reason + "), about " +
             fmt(count) + " quads; remeshing the " + std::to_string(mesh.triangles.size()) +
             " triangles and fitting the fields for each lattice tried");

  // First the lattice at the quad size, every triangle paired; where some triangle finds no
  // partner, the lattice at twice the size with every face split (quads into 4, triangles
  // into 3), which is all quads by construction.
  const Folds folds(mesh);
  std::vector<double> raisable;  // QuadMeshResult::folds_over_feature_angle
  for (const auto& [edge, fold] : folds.fold)
    if (fold > o.feature_angle && fold <= kMostRaisedFeatureAngle + 1e-9) raisable.push_back(fold);
  std::sort(raisable.begin(), raisable.end());
  const auto features_at = [&](double size) {
    std::vector<std::array<int, 2>> features = sharp_edges(folds, o.feature_angle);
    for (const auto& e : drop_short_features(mesh, shallow_creases(folds, o.feature_angle, size),
                                             kCreaseLine * size))
      features.push_back(e);
    return FeatureTriangleMesh{mesh, drop_short_features(mesh, std::move(features), 0.5 * size),
                               border_corners(folds, kBorderCornerReach * size)};
  };
  FeatureTriangleMesh input = features_at(sized.size.size);
  bool domed = false;
  if (!safe_net && sweep)
    if (std::optional<QuadMeshResult> swept =
            swept_extrusion(target, material, o, sized, input, raisable, progress, &domed)) {
      if (!domed) return std::move(*swept);
      return swept_or_lattice(
          std::move(*swept), o.domed_sweep_share,
          [&] { return make_quad_mesh_on(target, material, o, progress, false, false); }, progress);
    }
  // Sharp edges the quads must follow, against the quads' own edges (about 2 area / size long
  // in all): past a quarter of those the lattice is mostly constraint. Spot from its triangles
  // at 250 mm with --quad-feature-angle 20 marks 5.0 m of its edges (0.69 of area / size) and
  // ran for over 10 minutes; at 25, 2.7 m (0.37) took 28 s; fandisk's 3.2 m at the default
  // 60 deg are 0.44, a cube's 3 m 0.24. Where the size rule chose the size (no --quad-size or
  // --quads), it is made finer until they can (an icosahedron at 250 mm: 4.64 m of edges,
  // quads of 22.7 mm follow 4.55 m; refused until 2026-12-03).
  double feature_length = edges_length(mesh, input.features);
  const auto most = [&] { return kMaxFeatureShare * sized.size.area / sized.size.size; };
  const auto finer = [&] {
    return kMaxFeatureShare * sized.size.area / std::max(feature_length, 1e-9);
  };
  const auto finer_fits = [&] { return finer() * finer() * kMaxQuads >= sized.size.area; };
  for (int round = 0;
       round < 4 && feature_length > most() && !o.quad_size && !o.quads && finer_fits(); ++round) {
    sized.size.size = kFinerForFeatures * finer();
    if (round == 0) sized.size.reason += "; finer, for the quads to follow the sharp edges";
    input = features_at(sized.size.size);
    feature_length = edges_length(mesh, input.features);
    if (progress)
      progress("quad size " + fmt(sized.size.size) + " mm, for the quads to follow the " +
               fmt(feature_length) + " mm of sharp edges");
  }
  if (feature_length > most())
    throw InvalidInput(
        "--quad-feature-angle " + fmt(o.feature_angle * 180 / kPi) + " deg marks " +
        fmt(feature_length) + " mm of the target's edges as sharp, more than quads of " +
        fmt(sized.size.size) + " mm can follow (" + fmt(most()) +
        " mm, a quarter of their edges): raise --quad-feature-angle" +
        (finer_fits() ? ", or pass --quad-size " + fmt(finer()) + " or less" : std::string()));
  // The whole search, once as the fields come and, where its quads leave feature lines
  // crossing them, once with the lattice lines held on the feature lines (constrained).
  auto mesh_lattices = [&](bool constrained) {
    using Mode = quads::LatticeInput::Mode;
    // The safe net tries finer triangles until every face is sound (each edge becomes two quad
    // edges, so 1.6 x the quad size gives quads of about the size wanted).
    // A split lattice is tried once more at 1.4 x the size (quads of 0.7 x) where the first
    // bridged a thin part.
    struct Attempt {
      Mode mode;
      double spacing, edge;  // lattice spacing and remeshing edge, per quad size
    };
    const Attempt attempts[] = {{Mode::kPure, 1.0, 1.0 / 3.5},  {Mode::kSplit, 2.0, 2.0 / 3.5},
                                {Mode::kSplit, 1.4, 1.4 / 3.5}, {Mode::kTriangles, 2.0, 1.6},
                                {Mode::kTriangles, 2.0, 1.1},   {Mode::kTriangles, 2.0, 0.8},
                                {Mode::kTriangles, 2.0, 0.4}};
    // A sound pure lattice competes with the split one of twice the spacing (its quads are as
    // large): on smooth closed shapes the coarser lattice has fewer dislocations (sphere 44
    // irregular vertices against 68), where it bridges a thin part the pure one is kept.
    // One attempt: the surface remeshed, its fields fitted and the lattice extracted, from \p r
    // (the result so far: what the attempt does not set, it keeps).
    auto attempt_at = [&](const Attempt& at, QuadMeshResult r) {
      const auto& [mode, spacing_factor, edge] = at;
      FeatureTriangleMesh remeshed;
      const double spacing = spacing_factor * r.size.size;
      remeshed = isotropic_remesh(input, edge * r.size.size, 5);
      const quads::Surface surface = quads::make_surface(remeshed.mesh);
      const int n = static_cast<int>(remeshed.mesh.vertices.size());
      r.remeshed_vertices = n;
      r.feature_edges = static_cast<int>(remeshed.features.size());

      // Alignment: features and borders firmly, curvature where clearly anisotropic.
      const quads::Curvatures k = quads::principal_curvatures(surface, 0.5 * spacing);
      std::vector<Vec3> direction(n, Vec3::Zero());
      std::vector<double> weight(n, 0.0);
      for (int i = 0; i < n; ++i) {
        const double diff = k.larger[i] - k.smaller[i];
        const double anisotropy = k.larger[i] > 0 ? diff / k.larger[i] : 0.0;
        weight[i] = 0.3 * smoothstep(anisotropy, 0.3, 0.8) * smoothstep(diff * diagonal, 2.0, 6.0);
        direction[i] = k.weak_direction[i];
      }
      std::vector<std::vector<int>> feature_nb(n);
      for (const auto& [a, b] : remeshed.features) {
        feature_nb[a].push_back(b);
        feature_nb[b].push_back(a);
      }
      r.feature_length = edges_length(remeshed.mesh, remeshed.features);
      for (int i = 0; i < n; ++i) {
        if (feature_nb[i].size() != 2) continue;
        const Vec3 t =
            remeshed.mesh.vertices[feature_nb[i][1]] - remeshed.mesh.vertices[feature_nb[i][0]];
        direction[i] = (t - surface.normals[i] * surface.normals[i].dot(t)).normalized();
        weight[i] = 10.0;
      }
      const std::vector<Vec3> cross = quads::cross_field(surface, direction, weight);
      // Lattice lines on the feature lines, lattice points on their corners.
      quads::PositionConstraints on_features{std::vector<Vec3>(n, Vec3::Zero()),
                                             std::vector<char>(n, 0)};
      for (int i = 0; i < n; ++i) {
        if (feature_nb[i].size() == 2)
          on_features.line[i] = direction[i];
        else if (!feature_nb[i].empty())
          on_features.corner[i] = 1;
      }
      for (int v : remeshed.corners) on_features.corner[v] = 1;
      const std::vector<Vec3> positions = quads::position_field(
          surface, cross, spacing, o.smoothing_iterations, constrained ? &on_features : nullptr);
      const quads::DislocationResult step = quads::remove_dislocations(
          surface, cross, positions, spacing, remeshed.features, kMaxDislocationPath);

      // Where the dislocations were paired off, the lattice they leave is extracted by its own
      // offsets and, where those measured again agree, as rounded lattice points; the field as
      // smoothed competes with both (a stretched lattice can collapse worse than the
      // dislocations it lost): the sound one with the fewest irregular vertices is kept.
      struct Candidate {
        const std::vector<Vec3>* positions;
        const quads::IntegerLattice* offsets;
        int dislocations_left;
      };
      std::vector<Candidate> candidates;
      if (step.applied) {
        candidates.push_back({&step.positions, &*step.lattice, 0});
        if (step.rounded_clean) candidates.push_back({&step.rounded, nullptr, 0});
      }
      candidates.push_back({&positions, nullptr, step.charges_before});
      std::optional<QuadMeshResult> best;
      for (const Candidate& candidate : candidates) {
        QuadMeshResult c = r;
        c.dislocations = step.charges_before;
        c.dislocations_left = candidate.dislocations_left;
        // Polished quads first; where polishing moved a thin part's tip out of reach (the
        // check's gap), the quads as untangled.
        for (const auto& [on_surface, polish] : {std::pair{true, true}, std::pair{true, false},
                                                 std::pair{false, true}, std::pair{false, false}}) {
          quads::LatticeInput li{&surface,
                                 cross,
                                 *candidate.positions,
                                 remeshed.features,
                                 spacing,
                                 mode,
                                 on_surface,
                                 [&](const Vec3& p) { return target.closest(p).point; },
                                 [&](const Vec3& p) { return target.closest(p).normal; },
                                 polish,
                                 candidate.offsets,
                                 remeshed.corners};
          quads::LatticeResult lattice = quads::extract_quads(li);
          c.lattice_quads = lattice.lattice_quads;
          c.lattice_triangles = lattice.lattice_triangles;
          c.triangle_rows = lattice.rows;
          c.quads = std::move(lattice.quads);
          c.method = mode == Mode::kTriangles ? "triangles split into quads (no lattice)"
                     : lattice.split          ? "lattice, faces split"
                     : lattice.rows > 0       ? "lattice, triangles paired by rows"
                                              : "lattice";
          if (!on_surface) c.method += ", new points not projected";
          if (c.quads.n_faces() > 0)
            quads::untangle(
                c.quads,
                [&](const PolyMesh& m, OpenMesh::FaceHandle f) {
                  return sound_face(m, f, target, c.size.size);
                },
                [&](const Vec3& p) { return target.closest(p).point; });
          c.problem = c.quads.n_faces() == 0
                          ? std::to_string(c.lattice_triangles) + " triangles found no partner"
                          : check(c.quads, mesh, target, c.size.size);
          if (mode == Mode::kPure)
            c.unpaired_triangles = c.quads.n_faces() == 0 ? c.lattice_triangles : 0;
          if (c.quads.n_faces() == 0) break;  // the pairing does not depend on on_surface
          if (c.problem.empty()) break;
        }
        const bool better = !best || (c.problem.empty() && !best->problem.empty()) ||
                            (c.problem.empty() == best->problem.empty() && c.quads.n_faces() > 0 &&
                             (best->quads.n_faces() == 0 ||
                              irregular_vertices(c.quads) < irregular_vertices(best->quads)));
        if (better) best = std::move(c);
      }
      return std::pair{std::move(*best), std::move(remeshed)};
    };
    // The pure lattice's attempt and the split one's after it are made side by side: the split
    // one is made after every pure one (it competes with a sound one, and replaces one that is
    // not), and each is most of the stage's time. Each is a function of the target alone; the
    // split one keeps the pure one's count of unpaired triangles, as made after it.
    QuadMeshResult r = sized;
    FeatureTriangleMesh remeshed;
    std::future<std::pair<QuadMeshResult, FeatureTriangleMesh>> split_ahead;
    if (!safe_net) split_ahead = std::async(std::launch::async, attempt_at, attempts[1], r);
    std::optional<std::pair<QuadMeshResult, FeatureTriangleMesh>> pure;
    for (std::size_t i = 0; i < std::size(attempts); ++i) {
      const auto& [mode, spacing_factor, edge] = attempts[i];
      if (pure && mode != Mode::kSplit) break;
      if ((mode == Mode::kTriangles) != safe_net) continue;
      const double spacing = spacing_factor * r.size.size;
      auto made = i == 1 && split_ahead.valid() ? split_ahead.get() : attempt_at(attempts[i], r);
      if (i == 1) made.first.unpaired_triangles = r.unpaired_triangles;
      remeshed = std::move(made.second);
      r = std::move(made.first);
      if (progress)
        progress((mode == Mode::kPure    ? "lattice of "
                  : mode == Mode::kSplit ? "split lattice of "
                                         : "triangles split into quads, remeshed at ") +
                 fmt(mode == Mode::kTriangles ? edge * r.size.size : spacing) + " mm: " +
                 (r.problem.empty()
                      ? std::to_string(r.quads.n_faces()) + " quads, " +
                            std::to_string(irregular_vertices(r.quads)) + " irregular vertices"
                      : "not used, " + r.problem));
      if (pure) {  // this split lattice competed with the sound pure one
        bool keep_pure = !r.problem.empty();
        // A count asked for (--quads) first: the one within kCountMargin of it (the bunny asked
        // for 400: the pure lattice 413 quads, the split one 542, with 105 and 100 irregular
        // vertices).
        const auto off = [&](const PolyMesh& m) {
          return std::abs(static_cast<double>(m.n_faces()) - *o.quads) / *o.quads;
        };
        const bool by_count =
            !keep_pure && o.quads && !o.quad_size &&
            (off(r.quads) > kCountMargin) != (off(pure->first.quads) > kCountMargin);
        if (by_count) keep_pure = off(r.quads) > kCountMargin;
        if (!keep_pure && !by_count) {
          // Sharp features first: the lattice of twice the spacing merges lines closer than it
          // (fandisk: 46 % of the feature length on quad edges against 70 %); then the closer
          // to the target by kCloserMargin; then the fewer irregular vertices.
          const double on_pure =
              feature_length_on_edges(pure->first.quads, pure->second, r.size.size) /
              std::max(pure->first.feature_length, 1e-9);
          const double on_split = feature_length_on_edges(r.quads, remeshed, r.size.size) /
                                  std::max(r.feature_length, 1e-9);
          const double off_pure = vertex_distances(pure->first.quads, target).mean;
          const double off_split = vertex_distances(r.quads, target).mean;
          keep_pure =
              std::abs(on_pure - on_split) > kFeatureMargin
                  ? on_pure > on_split
                  : off_split - off_pure > kCloserMargin * r.size.size ||
                        irregular_vertices(r.quads) >= irregular_vertices(pure->first.quads);
        }
        if (keep_pure) {
          r = std::move(pure->first);
          remeshed = std::move(pure->second);
        }
        break;
      }
      if (r.problem.empty() && mode == Mode::kPure) {
        pure.emplace(r, remeshed);
        continue;
      }
      if (r.problem.empty()) break;
    }
    if (!r.problem.empty())
      throw SolverError("quad meshing failed on this target (" + r.problem +
                        "); pass a quad mesh with --quad or another --quad-size");
    {  // corners near a feature line onto it, unless that unsettles the check
      PolyMesh snapped = r.quads;
      if (snap_to_features(snapped, input, r.size.size) > 0 &&
          check(snapped, mesh, target, r.size.size).empty())
        r.quads = std::move(snapped);
    }
    return std::pair{std::move(r), std::move(remeshed)};
  };
  auto [meshed, meshed_on] = mesh_lattices(false);
  QuadMeshResult r = std::move(meshed);
  FeatureTriangleMesh remeshed = std::move(meshed_on);
  // Feature lines through quads rather than on their edges fold those quads across them, and a
  // flat face cut by such a quad is no plate (a star prism at 200 mm: 9 quads straddling its
  // rims, 127 parts; held on the lines: none, 12 plates). The lattice held on the feature lines
  // is taken where it leaves at most kHeldShare of that length off quad edges, and at least one
  // quad size less. It is tried only where the lattice follows most of the feature length
  // already (kFollowedShare): scattered short creases, a scan's or a bust's, mostly off the
  // lattice's edges (55-85 % on bunny_closed, demosthenes and stanford-bunny), held on lines
  // gave no such lattice, and a quads stage twice as long.
  const double off_edges =
      r.feature_length - feature_length_on_edges(r.quads, remeshed, r.size.size);
  if (off_edges >= r.size.size && off_edges <= kFollowedShare * r.feature_length) {
    try {
      auto [held, held_on] = mesh_lattices(true);
      const double held_off =
          held.feature_length - feature_length_on_edges(held.quads, held_on, held.size.size);
      const bool take = held_off <= kHeldShare * off_edges && off_edges - held_off >= r.size.size;
      if (progress)
        progress("with lattice lines held on the feature lines: " +
                 std::to_string(held.quads.n_faces()) + " quads, " + fmt(held_off) + " mm of " +
                 fmt(held.feature_length) + " off quad edges (as the fields came: " +
                 fmt(off_edges) + ")" + (take ? "; taken" : "; not taken"));
      if (take) {
        r = std::move(held);
        remeshed = std::move(held_on);
      }
    } catch (const SolverError&) {  // no sound lattice held so: the first one stays
    }
  }

  describe(r, target, remeshed, o.feature_angle, std::move(raisable));
  return r;
}

}  // namespace

}  // namespace kerfab

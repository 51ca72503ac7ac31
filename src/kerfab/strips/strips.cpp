#include "kerfab/strips/strips.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

constexpr int kNone = -1;

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

/// Local index (0..3) of edge \p e in quad \p f, or kNone.
int local_edge(const std::array<int, 4>& edges, int e) {
  for (int k = 0; k < 4; ++k)
    if (edges[k] == e) return k;
  return kNone;
}

bool in_bending_pair(const QuadBending& q, int local) {
  return q.axis >= 0 && (local % 2) == q.axis;
}

/// Largest angle between the sector normals of faces \p a and \p b at the two ends of the
/// ruling (x, y) they share [rad].
double fold_across(const std::vector<Vec3>& pts, const std::array<int, 4>& a,
                   const std::array<int, 4>& b, int x, int y) {
  double fold = 0;
  for (int v : {x, y}) {
    const Vec3 na = corner_normal(pts, a, v), nb = corner_normal(pts, b, v);
    if (na.isZero() || nb.isZero()) continue;
    fold = std::max(fold, angle_between(na, nb));
  }
  return fold;
}

/// Sharp feature curves of the target: edges whose dihedral angle exceeds a threshold, and
/// boundary edges. Closest-point queries by brute force over a uniform grid of buckets.
class FeatureCurves {
 public:
  FeatureCurves(const TriangleMesh& mesh, double angle) {
    std::map<std::pair<int, int>, std::vector<int>> edge_faces;
    std::vector<Vec3> normals;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 n = (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                         .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
      normals.push_back(n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero());
      for (int k = 0; k < 3; ++k) {
        const int a = tri[k], b = tri[(k + 1) % 3];
        edge_faces[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
      }
    }
    for (const auto& [key, faces] : edge_faces) {
      const bool sharp =
          faces.size() != 2 || angle_between(normals[faces[0]], normals[faces[1]]) > angle;
      if (sharp) segments_.push_back({mesh.vertices[key.first], mesh.vertices[key.second]});
    }
  }
  bool empty() const { return segments_.empty(); }
  std::size_t size() const { return segments_.size(); }

  Vec3 closest(const Vec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    Vec3 out = p;
    for (const auto& [a, b] : segments_) {
      const Vec3 d = b - a;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
      const Vec3 q = a + t * d;
      const double dist = (p - q).squaredNorm();
      if (dist < best) best = dist, out = q;
    }
    return out;
  }

 private:
  std::vector<std::pair<Vec3, Vec3>> segments_;
};

/// The typical facet size of a triangle mesh: the median over triangles of sqrt(2 area) (the leg
/// of a right isosceles triangle of that area; the edge length for regular meshes, the short
/// side for long thin triangles) [mm].
double median_facet_size(const TriangleMesh& mesh) {
  std::vector<double> lengths;
  lengths.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const auto& v = mesh.vertices;
    lengths.push_back(std::sqrt((v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).norm()));
  }
  if (lengths.empty()) return 0.0;
  const auto mid = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), mid, lengths.end());
  return *mid;
}

class Builder {
 public:
  Builder(const PolyMesh& quads, const BendingResult& bending, const TargetSurface& target,
          const StripsOptions& options)
      : m_(quads),
        bending_(bending),
        target_(target),
        opt_(options),
        target_diagonal_(bounding_box(target.mesh()).diagonal()) {}

  Strips run() {
    const int nf = static_cast<int>(m_.n_faces());
    face_edges_.resize(nf);
    face_verts_.resize(nf);
    for (auto f : m_.faces()) {
      face_edges_[f.idx()] = quad_edges(m_, f);
      face_verts_[f.idx()] = quad_vertices(m_, f);
    }
    out_.quads = bending_.quads;
    mark_facets();
    assign_rigid_axes();
    choose_segment_counts();
    project_corners();
    make_edge_points();
    make_sub_quads();
    link_chains();
    build_patches();
    out_.edge_vertices = std::move(edge_points_);
    out_.target_facet_size = median_facet_size(target_.mesh());
    return std::move(out_);
  }

 private:
  const PolyMesh& m_;
  const BendingResult& bending_;
  const TargetSurface& target_;
  const StripsOptions& opt_;
  const double target_diagonal_;  // [mm]
  Strips out_;
  std::vector<std::array<int, 4>> face_edges_, face_verts_;
  std::vector<Vec3> coarse_normals_;
  std::optional<FeatureCurves> features_;
  std::vector<char> feature_edge_;                // per coarse edge
  std::vector<std::vector<int>> edge_points_;     // per coarse edge, from halfedge 0's start
  std::vector<std::vector<int>> face_first_sub_;  // per coarse quad: its sub-quad ids
  std::vector<std::array<int, 2>> ruling_side_neighbour_;  // per quad, side 0/1: neighbour
  std::vector<std::array<int, 2>> ruling_side_entry_;      // side by which the neighbour is
                                                           // entered
  std::vector<int> facet_of_;  // per coarse quad: its facet group, or kNone

  /// Facet groups of the options, checked: quads exist, each in one group.
  void mark_facets() {
    facet_of_.assign(m_.n_faces(), kNone);
    for (std::size_t g = 0; g < opt_.facets.size(); ++g)
      for (int q : opt_.facets[g]) {
        if (q < 0 || q >= static_cast<int>(m_.n_faces()))
          throw InvalidInput("facet quad " + std::to_string(q) + " is not a face of the quad mesh");
        if (facet_of_[q] != kNone)
          throw InvalidInput("quad " + std::to_string(q) + " is in two facets");
        facet_of_[q] = static_cast<int>(g);
      }
  }
  bool facet(int q) const { return facet_of_[q] != kNone; }

  int other_face(int e, int f) const {
    const auto eh = m_.edge_handle(e);
    for (int s = 0; s < 2; ++s) {
      const auto fh = m_.face_handle(m_.halfedge_handle(eh, s));
      if (fh.is_valid() && fh.idx() != f) return fh.idx();
    }
    return kNone;
  }

  /// Local edge index of ruling side s (0: the edge before corner `axis`, 1: after `axis + 1`).
  int ruling_local(int f, int side) const {
    const int a = out_.quads[f].axis;
    return side == 0 ? (a + 3) % 4 : (a + 1) % 4;
  }

  /// Rigid quads have no bending direction; give each the axis that lets the most neighbours
  /// continue a strip through it (ties: axis 0). Repeated until stable so chains of rigid
  /// quads line up.
  void assign_rigid_axes() {
    std::vector<int> rigid;
    for (std::size_t f = 0; f < out_.quads.size(); ++f)
      if (out_.quads[f].kind == QuadKind::kRigid) rigid.push_back(static_cast<int>(f));
    for (int f : rigid) out_.quads[f].axis = kNone;
    for (int round = 0; round < 8; ++round) {
      bool changed = false;
      for (int f : rigid) {
        int best_axis = 0, best_score = -1;
        for (int axis = 0; axis < 2; ++axis) {
          int score = 0;
          for (int k : {axis + 1, (axis + 3) % 4}) {
            const int g = other_face(face_edges_[f][k], f);
            if (g == kNone || out_.quads[g].axis < 0) continue;
            const int lg = local_edge(face_edges_[g], face_edges_[f][k]);
            score += in_bending_pair(out_.quads[g], lg) ? 0 : 1;
          }
          if (score > best_score) best_score = score, best_axis = axis;
        }
        if (out_.quads[f].axis != best_axis) changed = true;
        out_.quads[f].axis = best_axis;
      }
      if (!changed) break;
    }
  }

  /// Segment counts: each quad needs max(rulings_per_quad, ceil(longest bending edge /
  /// max_ruling_spacing)); quads sharing an edge that both subdivide take the largest need of
  /// their group, so the shared edge has one set of vertices.
  void choose_segment_counts() {
    const int nf = static_cast<int>(m_.n_faces());
    UnionFind groups(nf);
    std::vector<int> need(nf, 1);
    for (int f = 0; f < nf; ++f) {
      if (facet(f)) continue;  // a facet quad is one flat piece
      const int a = out_.quads[f].axis;
      double longest = 0;
      for (int k : {a, a + 2}) {
        const auto h = m_.halfedge_handle(m_.edge_handle(face_edges_[f][k]), 0);
        longest = std::max(
            longest,
            (m_.point(m_.to_vertex_handle(h)) - m_.point(m_.from_vertex_handle(h))).norm());
        const int g = other_face(face_edges_[f][k], f);
        if (g != kNone && !facet(g) &&
            in_bending_pair(out_.quads[g], local_edge(face_edges_[g], face_edges_[f][k])))
          groups.unite(f, g);
      }
      // In double first: a spacing of 1e-9 mm would overflow an int.
      const double by_spacing = std::ceil(longest / opt_.max_ruling_spacing - 1e-9);
      need[f] = std::max(opt_.rulings_per_quad,
                         static_cast<int>(std::min(by_spacing, double{kMaxSubQuads})));
    }
    std::vector<int> group_need(nf, 1);
    for (int f = 0; f < nf; ++f)
      group_need[groups.find(f)] = std::max(group_need[groups.find(f)], need[f]);
    out_.quad_segments.resize(nf);
    double total = 0;
    for (int f = 0; f < nf; ++f) {
      out_.quad_segments[f] = facet(f) ? 1 : group_need[groups.find(f)];
      total += out_.quad_segments[f];
    }
    // The work and memory that follow grow with the sub-quads: refuse before, not after hours.
    const auto mb = [](double x) { return std::to_string(std::llround(x)) + " MB"; };
    const bool over_memory = total <= kMaxSubQuads && opt_.max_memory_mb > 0 &&
                             total > sub_quads_within(opt_.max_memory_mb);
    if (over_memory || total > kMaxSubQuads)
      throw InvalidInput(
          "the strips would have " + std::to_string(std::llround(total)) +
          " sub-quads, needing about " + mb(sub_quads_memory_mb(total)) +
          (over_memory ? " (over --max-memory " + mb(opt_.max_memory_mb) + ")"
                       : " (at most " + std::to_string(kMaxSubQuads) + ")") +
          (over_memory ? ": raise --max-memory or" : ":") + " raise --max-ruling-spacing (now " +
          std::to_string(opt_.max_ruling_spacing) + " mm) or lower --rulings-per-quad (now " +
          std::to_string(opt_.rulings_per_quad) + "), or use a coarser quad mesh");
  }

  /// Area-weighted vertex normals of the coarse quad mesh.
  void compute_coarse_normals() {
    coarse_normals_.assign(m_.n_vertices(), Vec3::Zero());
    for (auto f : m_.faces()) {
      const auto& v = face_verts_[f.idx()];
      const Vec3 n =
          (to_eigen(m_.point(m_.vertex_handle(v[2]))) - to_eigen(m_.point(m_.vertex_handle(v[0]))))
              .cross(to_eigen(m_.point(m_.vertex_handle(v[3]))) -
                     to_eigen(m_.point(m_.vertex_handle(v[1]))));
      for (int c : v) coarse_normals_[c] += n;
    }
    for (auto& n : coarse_normals_)
      if (n.norm() > 0) n.normalize();
  }

  /// Projects \p p onto the target along \p normal (or to the closest point).
  Vec3 project(const Vec3& p, const Vec3& normal) {
    const SurfacePoint c = target_.closest(p);
    if (opt_.projection == Projection::kClosest || normal.isZero()) return c.point;
    const double reach = 3.0 * c.distance + 0.005 * target_diagonal_;
    const auto hit = target_.nearest_hit_along_line(p, normal, reach);
    // A hit on a part of the surface facing away from the quad mesh (the far side of a thin
    // part) is no projection: use the closest point then.
    bool facing = false;
    if (hit) {
      const auto& t = target_.mesh().triangles[hit->triangle];
      const auto& v = target_.mesh().vertices;
      const Vec3 n = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]);
      facing = n.dot(normal) > 0.3 * n.norm();
    }
    if (!hit || !facing) {
      ++out_.ray_fallbacks;
      return c.point;
    }
    return hit->point;
  }

  void mark_feature_edges() {
    feature_edge_.assign(m_.n_edges(), 0);
    if (!opt_.features) return;
    features_.emplace(target_.mesh(), *opt_.features);
    if (features_->empty()) return;
    for (auto e : m_.edges()) {
      if (m_.is_boundary(e)) {
        feature_edge_[e.idx()] = 1;
        continue;
      }
      const auto n0 = m_.calc_face_normal(m_.face_handle(m_.halfedge_handle(e, 0)));
      const auto n1 = m_.calc_face_normal(m_.face_handle(m_.halfedge_handle(e, 1)));
      if (angle_between(to_eigen(n0).normalized(), to_eigen(n1).normalized()) > *opt_.features)
        feature_edge_[e.idx()] = 1;
    }
  }

  void project_corners() {
    compute_coarse_normals();
    mark_feature_edges();
    const int nv = static_cast<int>(m_.n_vertices());
    out_.vertices.resize(nv);
    out_.vertex_on_straight_edge.assign(nv, 0);
    for (auto v : m_.vertices()) {
      const Vec3 p = to_eigen(m_.point(v));
      bool on_feature = false;
      if (features_ && !features_->empty())
        for (auto e : m_.ve_range(v)) on_feature = on_feature || feature_edge_[e.idx()];
      if (on_feature) {
        out_.vertices[v.idx()] = features_->closest(p);
        ++out_.feature_vertices;
      } else {
        out_.vertices[v.idx()] = project(p, coarse_normals_[v.idx()]);
      }
    }
    flatten_facet_corners();
  }

  /// A facet is a flat plate: its corners move onto its best-fit plane (a corner of two facets
  /// to the mean of its two places), before any edge between them is subdivided.
  void flatten_facet_corners() {
    std::map<int, std::pair<Vec3, int>> moved;  // vertex -> sum of projections, count
    for (const auto& group : opt_.facets) {
      std::set<int> corners;
      for (int q : group)
        for (int v : face_verts_[q]) corners.insert(v);
      Vec3 mean = Vec3::Zero();
      for (int v : corners) mean += out_.vertices[v];
      mean /= static_cast<double>(corners.size());
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (int v : corners)
        cov += (out_.vertices[v] - mean) * (out_.vertices[v] - mean).transpose();
      const Vec3 n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
      for (int v : corners) {
        auto& [sum, count] = moved[v];
        if (count == 0) sum = Vec3::Zero();
        sum += out_.vertices[v] - (out_.vertices[v] - mean).dot(n) * n;
        ++count;
      }
    }
    for (const auto& [v, pc] : moved) out_.vertices[v] = pc.first / pc.second;
  }

  /// Vertices along every edge that a quad subdivides: projected on bendable edges, kept on the
  /// straight edge otherwise (T-junctions and stiff edges of one-sided or rigid quads).
  void make_edge_points() {
    edge_points_.resize(m_.n_edges());
    for (auto e : m_.edges()) {
      const auto h = m_.halfedge_handle(e, 0);
      const int a = m_.from_vertex_handle(h).idx(), b = m_.to_vertex_handle(h).idx();
      int segments = 1, subdividing_sides = 0, sides = 0;
      bool next_to_facet = false;
      for (int s = 0; s < 2; ++s) {
        const auto fh = m_.face_handle(m_.halfedge_handle(e, s));
        if (!fh.is_valid()) continue;
        ++sides;
        const int f = fh.idx();
        if (facet(f)) {
          next_to_facet = true;
          continue;  // a facet quad takes only the edge's ends
        }
        if (in_bending_pair(out_.quads[f], local_edge(face_edges_[f], e.idx()))) {
          segments = out_.quad_segments[f];
          ++subdividing_sides;
        }
      }
      auto& pts = edge_points_[e.idx()];
      pts.push_back(a);
      if (subdividing_sides > 0) {
        // Beside a facet the edge stays straight: the facet is flat along it.
        const bool bendable = bending_.bendable[e.idx()] != 0 && !next_to_facet;
        const Vec3 pa = out_.vertices[a], pb = out_.vertices[b];
        for (int i = 1; i < segments; ++i) {
          const double t = static_cast<double>(i) / segments;
          const Vec3 p = (1 - t) * pa + t * pb;
          Vec3 q = p;
          bool straight = !bendable;
          if (!straight && features_ && !features_->empty() && feature_edge_[e.idx()]) {
            q = features_->closest(p);
            ++out_.feature_vertices;
          } else if (!straight) {
            Vec3 n = (1 - t) * coarse_normals_[a] + t * coarse_normals_[b];
            if (n.norm() > 0) n.normalize();
            q = project(p, n);
          }
          pts.push_back(static_cast<int>(out_.vertices.size()));
          out_.vertices.push_back(q);
          out_.vertex_on_straight_edge.push_back(straight ? 1 : 0);
        }
        if (subdividing_sides < sides) out_.t_junctions += segments - 1;
      }
      pts.push_back(b);
    }
  }

  /// Vertex ids along the edge from corner \p from to corner \p to.
  std::vector<int> points_from(int e, int from) const {
    std::vector<int> pts = edge_points_[e];
    if (pts.front() != from) std::reverse(pts.begin(), pts.end());
    return pts;
  }

  void make_sub_quads() {
    const int nf = static_cast<int>(m_.n_faces());
    face_first_sub_.resize(nf);
    for (int f = 0; f < nf; ++f) {
      const int a = out_.quads[f].axis, k = out_.quad_segments[f];
      const auto& c = face_verts_[f];
      const int c0 = c[a], c1 = c[(a + 1) % 4], c2 = c[(a + 2) % 4], c3 = c[(a + 3) % 4];
      if (facet(f)) {  // one sub-quad on the corners, edge j on coarse edge (a + j) % 4
        face_first_sub_[f].push_back(static_cast<int>(out_.faces.size()));
        out_.faces.push_back({c0, c1, c2, c3});
        out_.face_quad.push_back(f);
        continue;
      }
      const auto p = points_from(face_edges_[f][a], c0);            // c0 -> c1
      const auto q = points_from(face_edges_[f][(a + 2) % 4], c3);  // c3 -> c2
      if (static_cast<int>(p.size()) != k + 1 || static_cast<int>(q.size()) != k + 1)
        throw Error("strips: inconsistent subdivision of quad " + std::to_string(f));
      for (int i = 0; i < k; ++i) {
        face_first_sub_[f].push_back(static_cast<int>(out_.faces.size()));
        out_.faces.push_back({p[i], p[i + 1], q[i + 1], q[i]});
        out_.face_quad.push_back(f);
      }
      (void)c1;
      (void)c2;
    }
  }

  /// Neighbours across ruling sides: two quads continue one strip across an edge that is a
  /// ruling of both.
  void link_chains() {
    const int nf = static_cast<int>(m_.n_faces());
    ruling_side_neighbour_.assign(nf, {kNone, kNone});
    ruling_side_entry_.assign(nf, {kNone, kNone});
    for (int f = 0; f < nf; ++f)
      for (int side = 0; side < 2; ++side) {
        const int e = face_edges_[f][ruling_local(f, side)];
        const int g = other_face(e, f);
        if (g == kNone || facet(f) || facet(g)) continue;
        const int lg = local_edge(face_edges_[g], e);
        if (in_bending_pair(out_.quads[g], lg)) continue;
        ruling_side_neighbour_[f][side] = g;
        ruling_side_entry_[f][side] = lg == ruling_local(g, 0) ? 0 : 1;
      }
  }

  struct ChainQuad {
    int quad;
    int entry;  // side by which the chain enters the quad
  };

  std::vector<std::vector<ChainQuad>> chains(std::vector<char>& closed) {
    const int nf = static_cast<int>(m_.n_faces());
    std::vector<char> seen(nf, 0);
    std::vector<std::vector<ChainQuad>> out;
    for (int f0 = 0; f0 < nf; ++f0) {
      if (seen[f0] || facet(f0)) continue;
      // Walk backwards to the start of the chain, or around the loop.
      int cur = f0, exit_side = 0;
      bool loop = false;
      for (;;) {
        const int n = ruling_side_neighbour_[cur][exit_side];
        if (n == kNone) break;
        if (n == f0) {
          loop = true;
          break;
        }
        exit_side = 1 - ruling_side_entry_[cur][exit_side];
        cur = n;
      }
      const int start = loop ? f0 : cur;
      int entry = loop ? 0 : exit_side;
      std::vector<ChainQuad> chain;
      cur = start;
      for (;;) {
        chain.push_back({cur, entry});
        seen[cur] = 1;
        const int n = ruling_side_neighbour_[cur][1 - entry];
        if (n == kNone || n == start) break;
        entry = ruling_side_entry_[cur][1 - entry];
        cur = n;
      }
      out.push_back(std::move(chain));
      closed.push_back(loop ? 1 : 0);
    }
    return out;
  }

  /// Rulings and sub-quads of one quad, in chain order. \p rail0 is the vertex of the entry
  /// ruling that continues rail 0 (kNone for the first quad of a patch).
  void append_quad(Patch& patch, const ChainQuad& cq, bool first) {
    const int f = cq.quad, a = out_.quads[f].axis, k = out_.quad_segments[f];
    const auto& subs = face_first_sub_[f];
    // Rulings of the quad in its own order: ruling i = (P_i, Q_i) = (face[i][0], face[i][3]).
    std::vector<std::array<int, 2>> rul(k + 1);
    for (int i = 0; i < k; ++i) rul[i] = {out_.faces[subs[i]][0], out_.faces[subs[i]][3]};
    rul[k] = {out_.faces[subs[k - 1]][1], out_.faces[subs[k - 1]][2]};
    const bool reversed = cq.entry == 1;
    if (reversed) std::reverse(rul.begin(), rul.end());
    bool swapped = false;
    if (!first) {
      const auto& last = patch.rulings.back();
      swapped = rul[0][0] != last[0];
      if (swapped && (rul[0][1] != last[0] || rul[0][0] != last[1]))
        throw Error("strips: chain rulings do not match at quad " + std::to_string(f));
    }
    if (swapped)
      for (auto& r : rul) std::swap(r[0], r[1]);
    for (int i = first ? 0 : 1; i <= k; ++i) patch.rulings.push_back(rul[i]);
    const int p_side = face_edges_[f][a], q_side = face_edges_[f][(a + 2) % 4];
    for (int i = 0; i < k; ++i) {
      const int sub = subs[reversed ? k - 1 - i : i];
      patch.faces.push_back(sub);
      patch.face_flipped.push_back(reversed != swapped ? 1 : 0);
      patch.rail_edges.push_back(swapped ? std::array<int, 2>{q_side, p_side}
                                         : std::array<int, 2>{p_side, q_side});
    }
    const int entry_edge = face_edges_[f][reversed ? (a + 1) % 4 : (a + 3) % 4];
    const int exit_edge = face_edges_[f][reversed ? (a + 3) % 4 : (a + 1) % 4];
    if (first) patch.end_edges[0] = entry_edge, patch.ruling_edges.push_back(entry_edge);
    for (int i = 1; i < k; ++i) patch.ruling_edges.push_back(kNone);
    patch.ruling_edges.push_back(exit_edge);
    patch.end_edges[1] = exit_edge;
    patch.quads.push_back(f);
  }

  /// Quads of one strip side by side: rows[r][i] is row r's quad in column i; all rows run over
  /// the same columns (a single strip has one row).
  struct Bundle {
    std::vector<std::vector<ChainQuad>> rows;
    bool closed = false;
    int chain = -1;  ///< the maximal chain of row 0
  };

  /// The quad-mesh edge between vertex indices \p v (from the options), with a message naming
  /// the option where it is none.
  int resolve_edge(const std::array<int, 2>& v, const char* what) const {
    const int nv = static_cast<int>(m_.n_vertices());
    std::string name = "(";
    name.append(std::to_string(v[0])).append(", ").append(std::to_string(v[1])).append(")");
    if (v[0] < 0 || v[1] < 0 || v[0] >= nv || v[1] >= nv)
      throw InvalidInput(std::string(what) + " edge " + name + ": vertex index out of range 0.." +
                         std::to_string(nv - 1));
    const auto h = m_.find_halfedge(m_.vertex_handle(v[0]), m_.vertex_handle(v[1]));
    if (!h.is_valid())
      throw InvalidInput(std::string(what) + " edge " + name + " is not an edge of the quad mesh");
    return m_.edge_handle(h).idx();
  }

  static std::string edge_name(const std::array<int, 2>& v) {
    return "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ")";
  }

  /// The edge by which the chain leaves quad \p cq.
  int exit_edge(const ChainQuad& cq) const {
    const int a = out_.quads[cq.quad].axis;
    return face_edges_[cq.quad][cq.entry == 1 ? (a + 3) % 4 : (a + 1) % 4];
  }

  /// Chains grouped into bundles by the merge edges of the options: every chain position linked
  /// to another across a merge edge shares a column with it; runs of columns with the same
  /// chains, each advancing one way, form a bundle; what is left of each chain forms
  /// single-row bundles. \throw InvalidInput merge edges that are not rails of both sides, that
  /// would merge a strip with itself, or that would close a tube or branch.
  std::vector<Bundle> make_bundles(const std::vector<std::vector<ChainQuad>>& chains,
                                   const std::vector<char>& closed) {
    const int nc = static_cast<int>(chains.size());
    std::vector<int> offset(nc + 1, 0);
    for (int c = 0; c < nc; ++c) offset[c + 1] = offset[c] + static_cast<int>(chains[c].size());
    std::vector<std::pair<int, int>> where(m_.n_faces(), {kNone, kNone});  // quad -> chain, pos
    for (int c = 0; c < nc; ++c)
      for (std::size_t i = 0; i < chains[c].size(); ++i)
        where[chains[c][i].quad] = {c, static_cast<int>(i)};
    UnionFind columns(offset[nc]);
    std::set<std::pair<int, int>> linked;  // chain pairs joined by a merge edge
    // A merged run passes a vertex where two of its merge edges meet; a singularity of the quad
    // mesh there would lie inside the merged patch (paper Sec. 3.5: bending two ways at once).
    std::map<int, std::vector<std::array<int, 2>>> at_vertex;
    // The soft merge edges (the resolve stage's) that still apply, after the given ones.
    std::vector<std::array<int, 2>> merges = opt_.merge_edges;
    for (const auto& v : opt_.soft_merge_edges) {
      const auto eh = m_.edge_handle(resolve_edge(v, "merge"));
      const auto f0 = m_.face_handle(m_.halfedge_handle(eh, 0));
      const auto f1 = m_.face_handle(m_.halfedge_handle(eh, 1));
      if (!f0.is_valid() || !f1.is_valid() || where[f0.idx()].first == kNone ||
          where[f0.idx()].first == where[f1.idx()].first || where[f1.idx()].first == kNone)
        continue;
      bool rails = true;
      for (const auto f : {f0, f1})
        rails = rails && in_bending_pair(out_.quads[f.idx()],
                                         local_edge(face_edges_[f.idx()], eh.idx()));
      if (rails) merges.push_back(v);
    }
    for (const auto& v : merges) {
      resolve_edge(v, "merge");
      for (int x : v) at_vertex[x].push_back(v);
    }
    for (const auto& [x, list] : at_vertex) {
      const auto vh = m_.vertex_handle(x);
      if (list.size() < 2 || m_.is_boundary(vh) || m_.valence(vh) == 4) continue;
      throw InvalidInput("merge edges " + edge_name(list[0]) + " and " + edge_name(list[1]) +
                         " meet at vertex " + std::to_string(x) + " of valence " +
                         std::to_string(m_.valence(vh)) +
                         ", a singularity of the quad mesh that would lie inside the merged "
                         "patch");
    }
    for (std::size_t k = 0; k < merges.size(); ++k) {
      const auto& v = merges[k];
      const int e = resolve_edge(v, "merge");
      const auto eh = m_.edge_handle(e);
      const auto f0 = m_.face_handle(m_.halfedge_handle(eh, 0));
      const auto f1 = m_.face_handle(m_.halfedge_handle(eh, 1));
      if (!f0.is_valid() || !f1.is_valid())
        throw InvalidInput("merge edge " + edge_name(v) + " lies on the boundary: no strip beyond");
      for (const auto f : {f0, f1})
        if (!in_bending_pair(out_.quads[f.idx()], local_edge(face_edges_[f.idx()], e)))
          throw InvalidInput("merge edge " + edge_name(v) +
                             ": the strips on its two sides are not aligned (it is a ruling, "
                             "not a rail, of quad " +
                             std::to_string(f.idx()) + ")");
      const auto [ca, ia] = where[f0.idx()];
      const auto [cb, ib] = where[f1.idx()];
      if (ca == kNone || cb == kNone)
        throw InvalidInput("merge edge " + edge_name(v) +
                           ": a flat facet lies on one side, no strip to merge with");
      if (ca == cb)
        throw InvalidInput("merge edge " + edge_name(v) +
                           ": both sides belong to one strip, which cannot merge with itself");
      columns.unite(offset[ca] + ia, offset[cb] + ib);
      linked.insert({std::min(ca, cb), std::max(ca, cb)});
    }
    auto node = [&](int c, int i) { return offset[c] + i; };
    // Members of each column: chain -> position.
    std::map<int, std::map<int, int>> members;
    for (int c = 0; c < nc; ++c)
      for (int i = 0; i < static_cast<int>(chains[c].size()); ++i) {
        auto& m = members[columns.find(node(c, i))];
        if (m.count(c))
          throw InvalidInput("merge edges would merge strip " + std::to_string(c) +
                             " with itself (it runs beside itself)");
        m[c] = i;
      }
    std::vector<char> used(offset[nc], 0);
    std::vector<Bundle> out;
    auto step = [&](int c, int i, int d) {  // neighbour position along chain c, or kNone
      const int n = static_cast<int>(chains[c].size());
      const int j = i + d;
      if (j >= 0 && j < n) return j;
      return closed[c] ? (j + n) % n : kNone;
    };
    for (int c = 0; c < nc; ++c)
      for (int i = 0; i < static_cast<int>(chains[c].size()); ++i) {
        if (used[node(c, i)]) continue;
        const auto& m0 = members[columns.find(node(c, i))];
        if (m0.size() == 1) continue;  // single rows are collected below
        // Walk the columns both ways from here while the same chains advance one way each.
        std::map<int, int> dir;  // chain -> +1 / -1 relative to chain c
        auto next_column = [&](const std::map<int, int>& col, int d) -> const std::map<int, int>* {
          const int j = step(c, col.at(c), d);
          if (j == kNone || used[node(c, j)]) return nullptr;
          const auto& next = members[columns.find(node(c, j))];
          if (next.size() != col.size()) return nullptr;
          for (const auto& [x, pos] : col) {
            const auto it = next.find(x);
            if (it == next.end()) return nullptr;
            int dx = 0;
            for (int s : {1, -1})
              if (step(x, pos, s * d) == it->second) dx = s;
            if (dx == 0) return nullptr;
            if (dir.count(x) && dir[x] != dx) return nullptr;
          }
          for (const auto& [x, pos] : col)
            for (int s : {1, -1})
              if (step(x, pos, s * d) == next.at(x)) dir[x] = s;
          return &next;
        };
        std::vector<const std::map<int, int>*> cols = {&m0};
        for (const auto* col = next_column(m0, 1); col && col != &m0; col = next_column(*col, 1))
          cols.push_back(col);
        bool ring = false;
        if (cols.size() > 1) {
          const int j = step(c, cols.back()->at(c), 1);
          ring = j != kNone && &members[columns.find(node(c, j))] == &m0;
        }
        if (!ring) {
          std::vector<const std::map<int, int>*> back;
          for (const auto* col = next_column(m0, -1); col; col = next_column(*col, -1))
            back.push_back(col);
          cols.insert(cols.begin(), back.rbegin(), back.rend());
        }
        for (const auto* col : cols)
          for (const auto& [x, pos] : *col) used[node(x, pos)] = 1;
        // Row order: the chains form a path of merge links.
        std::map<int, std::vector<int>> adjacent;
        for (const auto& [x, pos] : m0)
          for (const auto& [y, pos2] : m0)
            if (x < y && linked.count({x, y})) adjacent[x].push_back(y), adjacent[y].push_back(x);
        int start = kNone, ends = 0;
        for (const auto& [x, pos] : m0) {
          const std::size_t degree = adjacent[x].size();
          if (degree > 2)
            throw InvalidInput("merge edges join more than two strips along one strip's side");
          if (degree == 1) ++ends, start = start == kNone ? x : std::min(start, x);
        }
        if (ends != 2) throw InvalidInput("merge edges would close the merged strips into a tube");
        std::vector<int> order = {start};
        while (order.size() < m0.size()) {
          const int last = order.back();
          for (int y : adjacent[last])
            if (order.size() < 2 || y != order[order.size() - 2]) {
              order.push_back(y);
              break;
            }
        }
        Bundle b;
        b.closed = ring;
        b.chain = order.front();
        const int sign = dir.count(c) ? dir.at(c) : 1;
        for (int x : order) {
          std::vector<ChainQuad> row;
          const int d = (dir.count(x) ? dir.at(x) : 1) * sign;
          for (const auto* col : cols) {
            ChainQuad q = chains[x][col->at(x)];
            if (d < 0) q.entry = 1 - q.entry;  // traversed the other way
            row.push_back(q);
          }
          b.rows.push_back(std::move(row));
        }
        out.push_back(std::move(b));
      }
    // What is left of every chain: maximal runs of unmerged positions.
    for (int c = 0; c < nc; ++c) {
      const int n = static_cast<int>(chains[c].size());
      int free = 0;
      for (int i = 0; i < n; ++i) free += used[node(c, i)] ? 0 : 1;
      if (free == n) {
        out.push_back({{chains[c]}, closed[c] != 0, c});
        continue;
      }
      // Start each run right after a used position (for closed chains, wrap around).
      for (int i = 0; i < n; ++i) {
        const int prev = i - 1 >= 0 ? i - 1 : (closed[c] ? n - 1 : kNone);
        if (used[node(c, i)] || (prev != kNone && !used[node(c, prev)])) continue;
        Bundle b;
        b.chain = c;
        std::vector<ChainQuad> row;
        for (int j = i; j != kNone && !used[node(c, j)]; j = step(c, j, 1)) {
          row.push_back(chains[c][j]);
          used[node(c, j)] = 1;
        }
        b.rows.push_back(std::move(row));
        out.push_back(std::move(b));
      }
    }
    return out;
  }

  /// Split edges of the options as coarse edge ids. \throw InvalidInput an edge that is not an
  /// edge, or lies between two merged rows.
  std::set<int> forced_splits(const std::vector<Bundle>& bundles) const {
    std::set<int> split;
    for (const auto& v : opt_.split_edges) split.insert(resolve_edge(v, "split"));
    for (const Bundle& b : bundles)
      for (std::size_t r = 0; r + 1 < b.rows.size(); ++r)
        for (const ChainQuad& q : b.rows[r])
          for (int k = 0; k < 4; ++k) {
            const int e = face_edges_[q.quad][k];
            if (!split.count(e)) continue;
            for (const ChainQuad& o : b.rows[r + 1])
              if (local_edge(face_edges_[o.quad], e) != kNone)
                throw InvalidInput("split edge " + std::to_string(e) +
                                   " lies between two strips that are also merged there");
          }
    return split;
  }

  void build_patches() {
    std::vector<char> closed;
    const auto all = chains(closed);
    out_.chains = static_cast<int>(all.size());
    out_.quad_patch.assign(m_.n_faces(), kNone);
    const auto bundles = make_bundles(all, closed);
    const std::set<int> forced = forced_splits(bundles);
    for (const Bundle& b : bundles) {
      const int n = static_cast<int>(b.rows.front().size());
      // fold[j]: fold across the junction after column j (wrapping for loops), over all rows.
      std::vector<double> fold(n, 0.0);
      std::vector<char> cut(n, 0);
      const int junctions = b.closed ? n : n - 1;
      int cuts = 0;
      for (int j = 0; j < junctions; ++j) {
        bool split = false;
        for (const auto& row : b.rows) {
          fold[j] = std::max(fold[j], junction_fold(row[j], row[(j + 1) % n]));
          split = split || forced.count(exit_edge(row[j]));
        }
        if (fold[j] > opt_.split_angle || split) cut[j] = 1, ++cuts;
      }
      out_.split_borders += cuts;
      int first = 0;
      bool loop_cut = false;
      if (b.closed) {
        ++out_.closed_loops;
        int at = 0;
        if (cuts == 0) {  // cut the loop where it folds most
          at = static_cast<int>(std::max_element(fold.begin(), fold.end()) - fold.begin());
          cut[at] = 1;
          loop_cut = true;
        } else {
          at = static_cast<int>(std::find(cut.begin(), cut.end(), 1) - cut.begin());
        }
        first = (at + 1) % n;
      }
      // Walk the columns from `first`, starting a new patch after every cut.
      std::vector<Patch> rows(b.rows.size());
      for (int step = 0; step < n; ++step) {
        const int j = (first + step) % n;
        for (std::size_t r = 0; r < b.rows.size(); ++r)
          append_quad(rows[r], b.rows[r][j], rows[r].quads.empty());
        if (cut[j] || step == n - 1) {
          Patch patch = assemble(rows);
          patch.chain = b.chain;
          patch.loop_cut = loop_cut;
          finish_patch(std::move(patch));
          rows.assign(b.rows.size(), Patch{});
        }
      }
    }
    for (const auto& group : opt_.facets) build_facet(group);
    straighten_inner_rails();
    // Largest fold kept inside a patch, over every junction of consecutive sub-quads.
    for (const Patch& p : out_.patches) {
      if (p.flat) continue;
      const auto lv = p.local_vertices();
      for (int r = 0; r < p.rows(); ++r)
        for (std::size_t i = 1; i < p.faces.size(); ++i)
          out_.max_fold =
              std::max(out_.max_fold,
                       fold_across(out_.vertices, out_.faces[p.face(static_cast<int>(i) - 1, r)],
                                   out_.faces[p.face(static_cast<int>(i), r)],
                                   lv[p.local(r, static_cast<int>(i))],
                                   lv[p.local(r + 1, static_cast<int>(i))]));
    }
  }

  /// One flat facet from a group of quads: their sub-quads (one each, on the corners), the
  /// union's vertices and its boundary as the outline. \throw InvalidInput the group is not a
  /// disk (its boundary is not one loop).
  void build_facet(const std::vector<int>& group) {
    Patch p;
    p.flat = true;
    p.quads = group;
    std::map<int, int> local;  // global vertex -> local
    std::map<std::pair<int, int>, OutlineEdge> directed;
    for (int q : group) {
      const int face = face_first_sub_[q].front();
      p.faces.push_back(face);
      p.face_flipped.push_back(0);
      const auto& corners = out_.faces[face];
      std::array<int, 4> lq{};
      for (int j = 0; j < 4; ++j)
        lq[j] = local.try_emplace(corners[j], static_cast<int>(local.size())).first->second;
      p.flat_quads.push_back(lq);
      const int a = out_.quads[q].axis;
      for (int j = 0; j < 4; ++j)
        directed[{corners[j], corners[(j + 1) % 4]}] = {{lq[j], lq[(j + 1) % 4]},
                                                        face_edges_[q][(a + j) % 4],
                                                        static_cast<int>(p.faces.size()) - 1,
                                                        0,
                                                        face};
    }
    p.flat_vertices.resize(local.size());
    for (const auto& [global, id] : local) p.flat_vertices[id] = global;
    // Boundary: directed edges whose reverse is not in the group, chained head to tail.
    std::map<int, OutlineEdge> from;  // local start -> edge
    for (const auto& [key, e] : directed)
      if (!directed.count({key.second, key.first})) {
        if (from.count(e.v[0]))
          throw InvalidInput("facet of quad " + std::to_string(group.front()) +
                             " touches itself at a vertex");
        from[e.v[0]] = e;
      }
    if (from.empty())
      throw InvalidInput("facet of quad " + std::to_string(group.front()) + " is closed");
    int at = from.begin()->first;
    for (std::size_t k = 0; k < from.size(); ++k) {
      const auto it = from.find(at);
      if (it == from.end()) break;
      p.flat_outline.push_back(it->second);
      at = it->second.v[1];
    }
    if (p.flat_outline.size() != from.size() || at != from.begin()->first)
      throw InvalidInput("facet of quad " + std::to_string(group.front()) +
                         " is not a disk (its boundary has more than one loop)");
    const int id = static_cast<int>(out_.patches.size());
    for (int q : group) out_.quad_patch[q] = id;
    out_.face_patch.resize(out_.faces.size(), kNone);
    for (int f : p.faces) out_.face_patch[f] = id;
    out_.patches.push_back(std::move(p));
  }

  /// Swaps a single-row ladder's rails.
  static void swap_rails(Patch& p) {
    for (auto& r : p.rulings) std::swap(r[0], r[1]);
    for (auto& f : p.face_flipped) f = f ? 0 : 1;
    for (auto& e : p.rail_edges) std::swap(e[0], e[1]);
  }

  /// Reverses a single-row ladder's direction along the strip.
  static void reverse_ladder(Patch& p) {
    std::reverse(p.quads.begin(), p.quads.end());
    std::reverse(p.rulings.begin(), p.rulings.end());
    std::reverse(p.faces.begin(), p.faces.end());
    std::reverse(p.face_flipped.begin(), p.face_flipped.end());
    for (auto& f : p.face_flipped) f = f ? 0 : 1;
    std::reverse(p.rail_edges.begin(), p.rail_edges.end());
    std::reverse(p.ruling_edges.begin(), p.ruling_edges.end());
    std::swap(p.end_edges[0], p.end_edges[1]);
  }

  /// One patch from single-row ladders over the same columns, each sharing a rail with the next.
  static Patch assemble(std::vector<Patch>& rows) {
    if (rows.size() == 1) return std::move(rows.front());
    // Every row runs the way row 0 does: its first ruling meets the previous row's first one
    // (a bundle of one column gives no step to tell).
    auto meets = [](const std::array<int, 2>& a, const std::array<int, 2>& b) {
      return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
    };
    for (std::size_t r = 1; r < rows.size(); ++r)
      if (!meets(rows[r].rulings.front(), rows[r - 1].rulings.front())) reverse_ladder(rows[r]);
    auto shares = [](const Patch& a, int rail, const Patch& b) {
      return a.rulings[0][rail] == b.rulings[0][0] || a.rulings[0][rail] == b.rulings[0][1];
    };
    if (!shares(rows[0], 1, rows[1])) swap_rails(rows[0]);
    for (std::size_t r = 1; r < rows.size(); ++r) {
      if (rows[r].rulings[0][0] != rows[r - 1].rulings[0][1]) swap_rails(rows[r]);
      for (std::size_t i = 0; i < rows[r].rulings.size(); ++i)
        if (rows[r].rulings.size() != rows[0].rulings.size() ||
            rows[r].rulings[i][0] != rows[r - 1].rulings[i][1])
          throw Error("strips: merged rows do not share their rail");
    }
    Patch out = rows.front();
    const Patch& last = rows.back();
    for (std::size_t i = 0; i < out.rulings.size(); ++i) out.rulings[i][1] = last.rulings[i][1];
    for (std::size_t i = 0; i < out.rail_edges.size(); ++i)
      out.rail_edges[i][1] = last.rail_edges[i][1];
    for (std::size_t r = 1; r < rows.size(); ++r) {
      PatchRow row;
      row.quads = rows[r].quads;
      row.faces = rows[r].faces;
      row.face_flipped = rows[r].face_flipped;
      row.ruling_edges = rows[r].ruling_edges;
      row.end_edges = rows[r].end_edges;
      for (const auto& ruling : rows[r].rulings) row.rail.push_back(ruling[0]);
      out.more_rows.push_back(std::move(row));
    }
    return out;
  }

  /// Merged patches: every inner rail vertex moves onto its straight ruling from rail 0 to the
  /// last rail, at the same fraction of the way as along the rows' rulings before.
  void straighten_inner_rails() {
    for (const Patch& p : out_.patches) {
      if (p.rows() == 1) continue;
      const auto lv = p.local_vertices();
      for (std::size_t i = 0; i < p.rulings.size(); ++i) {
        std::vector<double> along = {0.0};
        for (int k = 1; k <= p.rows(); ++k)
          along.push_back(along.back() + (out_.vertices[lv[p.local(k, static_cast<int>(i))]] -
                                          out_.vertices[lv[p.local(k - 1, static_cast<int>(i))]])
                                             .norm());
        const Vec3 a = out_.vertices[p.rulings[i][0]], b = out_.vertices[p.rulings[i][1]];
        for (int k = 1; k < p.rows(); ++k) {
          const int v = lv[p.local(k, static_cast<int>(i))];
          const double t = along.back() > 0 ? along[k] / along.back() : double(k) / p.rows();
          out_.vertices[v] = a + t * (b - a);
          out_.vertex_on_straight_edge[v] = 1;
        }
      }
    }
  }

  double junction_fold(const ChainQuad& a, const ChainQuad& b) const {
    const auto& sa = face_first_sub_[a.quad];
    const auto& sb = face_first_sub_[b.quad];
    const int fa = a.entry == 0 ? sa.back() : sa.front();  // sub-quad at a's exit
    const int fb = b.entry == 0 ? sb.front() : sb.back();  // sub-quad at b's entry
    const auto& qa = out_.faces[fa];
    // The shared ruling: a's exit ruling.
    const int x = a.entry == 0 ? qa[1] : qa[0];
    const int y = a.entry == 0 ? qa[2] : qa[3];
    return fold_across(out_.vertices, qa, out_.faces[fb], x, y);
  }

  void finish_patch(Patch&& p) {
    // A patch may meet itself: a loop cut open, or a strip whose end runs into its own side.
    // Every later occurrence of a vertex at another ladder position gets its own copy, so the
    // patch is a disk and the contact is a border like any other.
    std::set<int> seen;
    std::map<int, int> original;  // copy -> the vertex it copies
    bool changed = false;
    auto visit = [&](int& v) {
      if (seen.insert(v).second) return;
      const int copy = static_cast<int>(out_.vertices.size());
      original[copy] = v;
      out_.vertices.push_back(out_.vertices[v]);
      out_.vertex_on_straight_edge.push_back(out_.vertex_on_straight_edge[v]);
      v = copy;
      seen.insert(copy);
      changed = true;
      ++out_.self_contacts;
    };
    for (std::size_t i = 0; i < p.rulings.size(); ++i) {
      visit(p.rulings[i][0]);
      for (PatchRow& row : p.more_rows) visit(row.rail[i]);
      visit(p.rulings[i][1]);
    }
    auto source = [&](int v) {  // the vertex a copy stands for
      const auto it = original.find(v);
      return it == original.end() ? v : it->second;
    };
    if (changed) {
      const auto lv = p.local_vertices();
      for (int r = 0; r < p.rows(); ++r)
        for (std::size_t i = 0; i < p.faces.size(); ++i) {
          // The face's cycle from its two rulings, then turned so that it starts where the face
          // did (face[0] -> face[1] runs along the bending edge; later stages rely on that).
          const int k = static_cast<int>(i);
          const int a0 = lv[p.local(r, k)], a1 = lv[p.local(r + 1, k)], b0 = lv[p.local(r, k + 1)],
                    b1 = lv[p.local(r + 1, k + 1)];
          const bool flipped = r == 0 ? p.face_flipped[i] : p.more_rows[r - 1].face_flipped[i];
          const std::array<int, 4> cycle =
              flipped ? std::array<int, 4>{a0, a1, b1, b0} : std::array<int, 4>{a0, b0, b1, a1};
          auto& face = out_.faces[p.face(k, r)];
          for (int t = 0; t < 4; ++t) {
            bool match = true;
            for (int j = 0; j < 4; ++j) match = match && source(cycle[(j + t) % 4]) == face[j];
            if (match) {
              face = {cycle[t], cycle[(t + 1) % 4], cycle[(t + 2) % 4], cycle[(t + 3) % 4]};
              break;
            }
            assert(t < 3 && "a rebuilt face must be a turn of the original");
          }
        }
    }
    const int id = static_cast<int>(out_.patches.size());
    for (int q : p.all_quads()) out_.quad_patch[q] = id;
    out_.face_patch.resize(out_.faces.size(), kNone);
    for (int f : p.all_faces()) out_.face_patch[f] = id;
    out_.patches.push_back(std::move(p));
  }
};

}  // namespace

std::vector<int> Patch::all_quads() const {
  std::vector<int> out = quads;
  for (const PatchRow& r : more_rows) out.insert(out.end(), r.quads.begin(), r.quads.end());
  return out;
}

std::vector<int> Patch::all_faces() const {
  std::vector<int> out = faces;
  for (const PatchRow& r : more_rows) out.insert(out.end(), r.faces.begin(), r.faces.end());
  return out;
}

int Patch::local(int k, int i) const {
  const int n1 = static_cast<int>(rulings.size());
  if (k == 0) return 2 * i;
  if (k == rows()) return 2 * i + 1;
  return 2 * n1 + (k - 1) * n1 + i;
}

std::vector<int> Patch::local_vertices() const {
  if (flat) return flat_vertices;
  const int n1 = static_cast<int>(rulings.size());
  std::vector<int> out(static_cast<std::size_t>((rows() + 1) * n1));
  for (int i = 0; i < n1; ++i) out[2 * i] = rulings[i][0], out[2 * i + 1] = rulings[i][1];
  for (int k = 1; k < rows(); ++k)
    for (int i = 0; i < n1; ++i) out[local(k, i)] = more_rows[k - 1].rail[i];
  return out;
}

std::vector<std::array<int, 4>> Patch::local_quads() const {
  if (flat) return flat_quads;
  std::vector<std::array<int, 4>> out;
  for (int r = 0; r < rows(); ++r) {
    const auto& flipped = r == 0 ? face_flipped : more_rows[r - 1].face_flipped;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const int k = static_cast<int>(i);
      const int a0 = local(r, k), a1 = local(r, k + 1), b0 = local(r + 1, k),
                b1 = local(r + 1, k + 1);
      out.push_back(flipped[i] ? std::array<int, 4>{a0, b0, b1, a1}
                               : std::array<int, 4>{a0, a1, b1, b0});
    }
  }
  return out;
}

std::vector<OutlineEdge> Patch::outline() const {
  if (flat) return flat_outline;
  std::vector<OutlineEdge> out;
  const int n = static_cast<int>(rulings.size()) - 1, rr = rows();
  auto end_edge = [&](int row, int which) {
    return row == 0 ? end_edges[which] : more_rows[row - 1].end_edges[which];
  };
  for (int i = 0; i < n; ++i)
    out.push_back({{local(0, i), local(0, i + 1)}, rail_edges[i][0], i, 0, face(i, 0)});
  for (int k = 0; k < rr; ++k)
    out.push_back({{local(k, n), local(k + 1, n)}, end_edge(k, 1), n - 1, 3, face(n - 1, k)});
  for (int i = n; i > 0; --i)
    out.push_back(
        {{local(rr, i), local(rr, i - 1)}, rail_edges[i - 1][1], i - 1, 1, face(i - 1, rr - 1)});
  for (int k = rr; k > 0; --k)
    out.push_back({{local(k, 0), local(k - 1, 0)}, end_edge(k - 1, 0), 0, 2, face(0, k - 1)});
  return out;
}

Strips build_strips(const PolyMesh& quads, const BendingResult& bending,
                    const TargetSurface& target, const StripsOptions& options) {
  if (options.rulings_per_quad < 1 || options.rulings_per_quad > 64)
    throw InvalidInput("--rulings-per-quad must be in 1..64, got " +
                       std::to_string(options.rulings_per_quad));
  if (!(options.max_ruling_spacing > 0) || !std::isfinite(options.max_ruling_spacing))
    throw InvalidInput("--max-ruling-spacing must be a positive length in mm");
  if (!(options.split_angle > 0) || options.split_angle > M_PI + 1e-12)
    throw InvalidInput("--split-angle must be in (0, 180] degrees");
  if (options.features && !(*options.features > 0 && *options.features < M_PI))
    throw InvalidInput("--features must be in (0, 180) degrees");
  if (!is_all_quads(quads)) throw InvalidInput("strips need an all-quad mesh");
  if (bending.quads.size() != quads.n_faces() || bending.bendable.size() != quads.n_edges())
    throw InvalidInput("strips: bending result does not belong to this quad mesh");
  return Builder(quads, bending, target, options).run();
}

std::vector<int> column_starts(const Strips& s, const Patch& p) {
  std::vector<int> starts = {0};
  for (int q : p.quads) starts.push_back(starts.back() + s.quad_segments[q]);
  return starts;
}

Strips split_patch(const Strips& strips, int patch, int at) {
  if (patch < 0 || patch >= static_cast<int>(strips.patches.size()))
    throw InvalidInput("split_patch: no patch " + std::to_string(patch));
  const Patch& old = strips.patches[patch];
  if (old.flat) throw InvalidInput("split_patch: patch " + std::to_string(patch) + " is a facet");
  if (at < 1 || at >= static_cast<int>(old.quads.size()))
    throw InvalidInput("split_patch: patch " + std::to_string(patch) + " has no quad boundary " +
                       std::to_string(at));
  int r = 0;  // ruling between the quads (the same in every row: rows are aligned)
  for (int j = 0; j < at; ++j) r += strips.quad_segments[old.quads[j]];
  Strips out = strips;
  Patch first, second;
  auto cut = [&](Patch& p, int q0, int q1, int r0, int r1) {
    auto range = [](const auto& v, int a, int b) {
      return std::decay_t<decltype(v)>(v.begin() + a, v.begin() + b);
    };
    p.quads = range(old.quads, q0, q1);
    p.rulings = range(old.rulings, r0, r1 + 1);
    p.ruling_edges = range(old.ruling_edges, r0, r1 + 1);
    p.faces = range(old.faces, r0, r1);
    p.face_flipped = range(old.face_flipped, r0, r1);
    p.rail_edges = range(old.rail_edges, r0, r1);
    p.end_edges = {p.ruling_edges.front(), p.ruling_edges.back()};
    p.chain = old.chain;
    p.loop_cut = old.loop_cut;
    for (const PatchRow& row : old.more_rows) {
      PatchRow cut_row;
      cut_row.quads = range(row.quads, q0, q1);
      cut_row.faces = range(row.faces, r0, r1);
      cut_row.face_flipped = range(row.face_flipped, r0, r1);
      cut_row.ruling_edges = range(row.ruling_edges, r0, r1 + 1);
      cut_row.end_edges = {cut_row.ruling_edges.front(), cut_row.ruling_edges.back()};
      cut_row.rail = range(row.rail, r0, r1 + 1);
      p.more_rows.push_back(std::move(cut_row));
    }
  };
  const int n = static_cast<int>(old.faces.size());
  cut(first, 0, at, 0, r);
  cut(second, at, static_cast<int>(old.quads.size()), r, n);
  const int id = static_cast<int>(out.patches.size());
  for (int q : second.all_quads()) out.quad_patch[q] = id;
  for (int f : second.all_faces()) out.face_patch[f] = id;
  out.patches[patch] = std::move(first);
  out.patches.push_back(std::move(second));
  return out;
}

int quad_rows(const PolyMesh& quads) {
  // Nodes (quad, pair); a row crosses a quad through one opposite pair of edges.
  const int nf = static_cast<int>(quads.n_faces());
  UnionFind rows(2 * nf);
  for (auto f : quads.faces()) {
    const auto e = quad_edges(quads, f);
    for (int k = 0; k < 4; ++k) {
      const auto eh = quads.edge_handle(e[k]);
      for (int s = 0; s < 2; ++s) {
        const auto g = quads.face_handle(quads.halfedge_handle(eh, s));
        if (!g.is_valid() || g == f) continue;
        const int lg = local_edge(quad_edges(quads, g), e[k]);
        rows.unite(2 * f.idx() + k % 2, 2 * g.idx() + lg % 2);
      }
    }
  }
  int count = 0;
  for (int i = 0; i < 2 * nf; ++i) count += rows.find(i) == i ? 1 : 0;
  return count;
}

BendingResult naive_row_bending(const PolyMesh& quads) {
  const int nf = static_cast<int>(quads.n_faces());
  std::vector<std::array<int, 4>> edges(nf);
  for (auto f : quads.faces()) edges[f.idx()] = quad_edges(quads, f);
  // Crossing quad f through local edge k leads to (g, local edge of g).
  auto across = [&](int f, int k) -> std::pair<int, int> {
    const auto eh = quads.edge_handle(edges[f][k]);
    for (int s = 0; s < 2; ++s) {
      const auto g = quads.face_handle(quads.halfedge_handle(eh, s));
      if (g.is_valid() && g.idx() != f) return {g.idx(), local_edge(edges[g.idx()], edges[f][k])};
    }
    return {kNone, kNone};
  };
  // Rows as sequences of quads, node (quad, pair) visited once.
  std::vector<char> seen(2 * nf, 0);
  std::vector<std::vector<std::pair<int, int>>> rows;
  for (int f = 0; f < nf; ++f)
    for (int pair = 0; pair < 2; ++pair) {
      if (seen[2 * f + pair]) continue;
      auto walk = [&](int k, bool& closed) {
        std::vector<std::pair<int, int>> out;
        int cur = f;
        closed = false;
        for (int steps = 0; steps <= 2 * nf; ++steps) {
          const auto [g, l] = across(cur, k);
          if (g == kNone) break;
          if (g == f && l % 2 == pair) {
            closed = true;
            break;
          }
          seen[2 * g + l % 2] = 1;
          out.push_back({g, l % 2});
          cur = g, k = (l + 2) % 4;
        }
        return out;
      };
      seen[2 * f + pair] = 1;
      bool closed = false;
      const auto forward = walk(pair + 2, closed);
      std::vector<std::pair<int, int>> row;
      if (!closed) {
        bool unused = false;
        row = walk(pair, unused);
        std::reverse(row.begin(), row.end());
      }
      row.push_back({f, pair});
      row.insert(row.end(), forward.begin(), forward.end());
      rows.push_back(std::move(row));
    }
  // Greedy: take the row with the most quads not yet taken; they bend across it.
  std::vector<int> axis(nf, kNone);
  std::vector<char> row_used(rows.size(), 0);
  int left = nf;
  while (left > 0) {
    std::size_t best = rows.size();
    int best_free = 0;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      if (row_used[r]) continue;
      int free = 0;
      for (auto [f, pair] : rows[r]) free += axis[f] == kNone ? 1 : 0;
      if (free > best_free) best = r, best_free = free;
    }
    if (best == rows.size()) break;
    row_used[best] = 1;
    for (auto [f, pair] : rows[best])
      if (axis[f] == kNone) axis[f] = 1 - pair, --left;  // the row crosses the rulings
  }
  BendingResult out;
  out.quads.resize(nf);
  for (int f = 0; f < nf; ++f) out.quads[f] = {QuadKind::kBending, axis[f]};
  // An edge bends where every quad beside it has it in its bending pair.
  out.bendable.assign(quads.n_edges(), 1);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 4; ++k)
      if (k % 2 != axis[f]) out.bendable[edges[f][k]] = 0;
  for (char b : out.bendable) out.bendable_count += b;
  return out;
}

RowBaseline row_baseline(const PolyMesh& quads, const TargetSurface& target,
                         const StripsOptions& options) {
  return {quad_rows(quads),
          static_cast<int>(
              build_strips(quads, naive_row_bending(quads), target, options).patches.size())};
}

TriangleMesh triangulate(const Strips& strips) {
  TriangleMesh out;
  out.vertices = strips.vertices;
  for (const auto& q : strips.faces) {
    const auto& v = strips.vertices;
    // Split along the shorter diagonal.
    if ((v[q[0]] - v[q[2]]).squaredNorm() <= (v[q[1]] - v[q[3]]).squaredNorm()) {
      out.triangles.push_back({q[0], q[1], q[2]});
      out.triangles.push_back({q[0], q[2], q[3]});
    } else {
      out.triangles.push_back({q[0], q[1], q[3]});
      out.triangles.push_back({q[1], q[2], q[3]});
    }
  }
  return out;
}

}  // namespace kerfab

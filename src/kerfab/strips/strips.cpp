#include "kerfab/strips/strips.h"

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
      const int a = out_.quads[f].axis;
      double longest = 0;
      for (int k : {a, a + 2}) {
        const auto h = m_.halfedge_handle(m_.edge_handle(face_edges_[f][k]), 0);
        longest = std::max(
            longest,
            (m_.point(m_.to_vertex_handle(h)) - m_.point(m_.from_vertex_handle(h))).norm());
        const int g = other_face(face_edges_[f][k], f);
        if (g != kNone &&
            in_bending_pair(out_.quads[g], local_edge(face_edges_[g], face_edges_[f][k])))
          groups.unite(f, g);
      }
      need[f] = std::max(opt_.rulings_per_quad,
                         static_cast<int>(std::ceil(longest / opt_.max_ruling_spacing - 1e-9)));
    }
    std::vector<int> group_need(nf, 1);
    for (int f = 0; f < nf; ++f)
      group_need[groups.find(f)] = std::max(group_need[groups.find(f)], need[f]);
    out_.quad_segments.resize(nf);
    for (int f = 0; f < nf; ++f) out_.quad_segments[f] = group_need[groups.find(f)];
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
  }

  /// Vertices along every edge that a quad subdivides: projected on bendable edges, kept on the
  /// straight edge otherwise (T-junctions and stiff edges of one-sided or rigid quads).
  void make_edge_points() {
    edge_points_.resize(m_.n_edges());
    for (auto e : m_.edges()) {
      const auto h = m_.halfedge_handle(e, 0);
      const int a = m_.from_vertex_handle(h).idx(), b = m_.to_vertex_handle(h).idx();
      int segments = 1, subdividing_sides = 0, sides = 0;
      for (int s = 0; s < 2; ++s) {
        const auto fh = m_.face_handle(m_.halfedge_handle(e, s));
        if (!fh.is_valid()) continue;
        ++sides;
        const int f = fh.idx();
        if (in_bending_pair(out_.quads[f], local_edge(face_edges_[f], e.idx()))) {
          segments = out_.quad_segments[f];
          ++subdividing_sides;
        }
      }
      auto& pts = edge_points_[e.idx()];
      pts.push_back(a);
      if (subdividing_sides > 0) {
        const bool bendable = bending_.bendable[e.idx()] != 0;
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
        if (g == kNone) continue;
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
      if (seen[f0]) continue;
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

  void build_patches() {
    std::vector<char> closed;
    const auto all = chains(closed);
    out_.chains = static_cast<int>(all.size());
    out_.quad_patch.assign(m_.n_faces(), kNone);
    for (std::size_t c = 0; c < all.size(); ++c) {
      const auto& chain = all[c];
      const int n = static_cast<int>(chain.size());
      // fold[j]: fold across the junction after chain[j] (wrapping for loops).
      std::vector<double> fold(n, 0.0);
      const int junctions = closed[c] ? n : n - 1;
      for (int j = 0; j < junctions; ++j) fold[j] = junction_fold(chain[j], chain[(j + 1) % n]);
      std::vector<char> cut(n, 0);
      int cuts = 0;
      for (int j = 0; j < junctions; ++j)
        if (fold[j] > opt_.split_angle) cut[j] = 1, ++cuts;
      out_.split_borders += cuts;
      int first = 0;
      bool loop_cut = false;
      if (closed[c]) {
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
      // Walk the chain from `first`, starting a new patch after every cut.
      Patch patch;
      for (int s = 0; s < n; ++s) {
        const int j = (first + s) % n;
        append_quad(patch, chain[j], patch.quads.empty());
        if (cut[j] || s == n - 1) {
          patch.chain = static_cast<int>(c);
          patch.loop_cut = loop_cut;
          finish_patch(std::move(patch));
          patch = Patch{};
        }
      }
    }
    // Largest fold kept inside a patch, over every junction of consecutive sub-quads.
    for (const Patch& p : out_.patches)
      for (std::size_t i = 1; i < p.faces.size(); ++i)
        out_.max_fold = std::max(
            out_.max_fold, fold_across(out_.vertices, out_.faces[p.faces[i - 1]],
                                       out_.faces[p.faces[i]], p.rulings[i][0], p.rulings[i][1]));
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
    for (auto& ruling : p.rulings)
      for (int& v : ruling) {
        if (seen.insert(v).second) continue;
        const int copy = static_cast<int>(out_.vertices.size());
        original[copy] = v;
        out_.vertices.push_back(out_.vertices[v]);
        out_.vertex_on_straight_edge.push_back(out_.vertex_on_straight_edge[v]);
        v = copy;
        seen.insert(copy);
        changed = true;
        ++out_.self_contacts;
      }
    auto source = [&](int v) {  // the vertex a copy stands for
      const auto it = original.find(v);
      return it == original.end() ? v : it->second;
    };
    if (changed)
      for (std::size_t i = 0; i < p.faces.size(); ++i) {
        // The face's cycle from its two rulings, then turned so that it starts where the face
        // did (face[0] -> face[1] runs along the bending edge; later stages rely on that).
        const auto &a = p.rulings[i], &b = p.rulings[i + 1];
        const std::array<int, 4> cycle = p.face_flipped[i]
                                             ? std::array<int, 4>{a[0], a[1], b[1], b[0]}
                                             : std::array<int, 4>{a[0], b[0], b[1], a[1]};
        auto& face = out_.faces[p.faces[i]];
        for (int r = 0; r < 4; ++r) {
          bool match = true;
          for (int j = 0; j < 4; ++j) match = match && source(cycle[(j + r) % 4]) == face[j];
          if (match) {
            face = {cycle[r], cycle[(r + 1) % 4], cycle[(r + 2) % 4], cycle[(r + 3) % 4]};
            break;
          }
          assert(r < 3 && "a rebuilt face must be a turn of the original");
        }
      }
    const int id = static_cast<int>(out_.patches.size());
    for (int q : p.quads) out_.quad_patch[q] = id;
    out_.face_patch.resize(out_.faces.size(), kNone);
    for (int f : p.faces) out_.face_patch[f] = id;
    out_.patches.push_back(std::move(p));
  }
};

}  // namespace

std::vector<std::array<int, 4>> Patch::local_quads() const {
  std::vector<std::array<int, 4>> out;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const int a0 = 2 * static_cast<int>(i), a1 = a0 + 2, b0 = a0 + 1, b1 = a0 + 3;
    if (face_flipped[i])
      out.push_back({a0, b0, b1, a1});
    else
      out.push_back({a0, a1, b1, b0});
  }
  return out;
}

std::vector<OutlineEdge> Patch::outline() const {
  std::vector<OutlineEdge> out;
  const int n = static_cast<int>(rulings.size()) - 1;
  for (int i = 0; i < n; ++i) out.push_back({{2 * i, 2 * (i + 1)}, rail_edges[i][0], i, 0});
  out.push_back({{2 * n, 2 * n + 1}, end_edges[1], n - 1, 3});
  for (int i = n; i > 0; --i)
    out.push_back({{2 * i + 1, 2 * (i - 1) + 1}, rail_edges[i - 1][1], i - 1, 1});
  out.push_back({{1, 0}, end_edges[0], 0, 2});
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

Strips split_patch(const Strips& strips, int patch, int at) {
  if (patch < 0 || patch >= static_cast<int>(strips.patches.size()))
    throw InvalidInput("split_patch: no patch " + std::to_string(patch));
  const Patch& old = strips.patches[patch];
  if (at < 1 || at >= static_cast<int>(old.quads.size()))
    throw InvalidInput("split_patch: patch " + std::to_string(patch) + " has no quad boundary " +
                       std::to_string(at));
  int r = 0;  // ruling between the quads
  for (int j = 0; j < at; ++j) r += strips.quad_segments[old.quads[j]];
  Strips out = strips;
  Patch first, second;
  auto cut = [&](Patch& p, int q0, int q1, int r0, int r1) {
    p.quads.assign(old.quads.begin() + q0, old.quads.begin() + q1);
    p.rulings.assign(old.rulings.begin() + r0, old.rulings.begin() + r1 + 1);
    p.ruling_edges.assign(old.ruling_edges.begin() + r0, old.ruling_edges.begin() + r1 + 1);
    p.faces.assign(old.faces.begin() + r0, old.faces.begin() + r1);
    p.face_flipped.assign(old.face_flipped.begin() + r0, old.face_flipped.begin() + r1);
    p.rail_edges.assign(old.rail_edges.begin() + r0, old.rail_edges.begin() + r1);
    p.end_edges = {p.ruling_edges.front(), p.ruling_edges.back()};
    p.chain = old.chain;
    p.loop_cut = old.loop_cut;
  };
  const int n = static_cast<int>(old.faces.size());
  cut(first, 0, at, 0, r);
  cut(second, at, static_cast<int>(old.quads.size()), r, n);
  const int id = static_cast<int>(out.patches.size());
  for (int q : second.quads) out.quad_patch[q] = id;
  for (int f : second.faces) out.face_patch[f] = id;
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

#include "kerfab/quads/lattice.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

#include "kerfab/adapters/matching_program.h"
#include "kerfab/quads/bridges.h"
#include "kerfab/quads/cleanup.h"

namespace kerfab::quads {
namespace {

/// The same traits as the project's polygon mesh (core/mesh.h), as a triangle mesh: collapses
/// and edge splits need the triangle kernel.
using WorkMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;
using VH = OpenMesh::VertexHandle;
using HH = OpenMesh::HalfedgeHandle;

constexpr double kPi = 3.14159265358979323846;
/// A lattice whose quads start folded, flat or inverted in more than this share is not
/// untangled: past mending (the shared meshes' lattices start with at most 8 %) [-].
constexpr double kPastMending = 0.5;

/// Vertex roles: free vertices move to their lattice point, feature vertices slide along
/// their feature line, corners (where feature lines meet or end) stay.
enum Rank : int { kFree = 0, kFeature = 1, kCorner = 2 };

Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a); }

double corner_angle(const Vec3& at, const Vec3& prev, const Vec3& next) {
  return angle_between(prev - at, next - at);
}

class Extractor {
 public:
  explicit Extractor(const LatticeInput& in)
      : in_(in), s_(*in.surface), pos_(in.positions), cross_(in.cross), normal_(s_.normals) {
    if (in.offsets) offsets_ = *in.offsets;
    const auto& m = *s_.mesh;
    mesh_.reserve(m.vertices.size(), 3 * m.vertices.size(), m.triangles.size());
    for (const Vec3& p : m.vertices) mesh_.add_vertex(to_openmesh(p));
    for (const auto& t : m.triangles) mesh_.add_face(VH(t[0]), VH(t[1]), VH(t[2]));
    const std::size_t n = m.vertices.size();
    feature_nb_.assign(n, {});
    for (const auto& [a, b] : in.features) {
      feature_nb_[a].push_back(b);
      feature_nb_[b].push_back(a);
    }
    rank_.assign(n, kFree);
    for (std::size_t v = 0; v < n; ++v) {
      auto& nb = feature_nb_[v];
      std::sort(nb.begin(), nb.end());
      nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
      rank_[v] = nb.empty() ? kFree : nb.size() == 2 ? kFeature : kCorner;
    }
    for (int v : in.corners)
      if (v >= 0 && v < static_cast<int>(n)) rank_[v] = kCorner;
  }

  LatticeResult run() {
    using Mode = LatticeInput::Mode;
    collapse_short_edges();
    if (in_.mode != Mode::kTriangles) {
      collapse_same_lattice_points();
      move_to_lattice_points();
    }
    // A split lattice needs every piece between features even (its pairs cannot cross them);
    // the pure one leaves an odd piece's last triangle to a row of quads (bridged()), which
    // may cross a feature or end on the border: splitting those edges instead would leave a
    // flat corner on the line that no quad there can mend.
    if (in_.mode == Mode::kSplit) make_triangle_count_even();
    pair_triangles(in_.mode == Mode::kPure ? 0.0 : in_.mode == Mode::kSplit ? 0.25 : 2.0);
    if (in_.mode != Mode::kPure) return split();
    if (triangles_.empty()) return quads_only();
    return bridged();
  }

 private:
  Vec3 point(VH v) const { return to_eigen(mesh_.point(v)); }

  bool is_feature(int a, int b) const {
    const auto& nb = feature_nb_[a];
    return std::binary_search(nb.begin(), nb.end(), b);
  }

  LatticeOffset offset(int a, int b) const {
    if (offsets_ && offsets_->has(a, b)) return {offsets_->offset(a, b), 0.0, {}};
    return lattice_offset(point(VH(a)), normal_[a], cross_[a], pos_[a], point(VH(b)), normal_[b],
                          cross_[b], pos_[b], in_.spacing);
  }

  /// Faces around \p v keep their orientation (and some area) when \p v moves to \p to, or,
  /// with \p removed set, when \p removed is merged into \p v placed at \p to.
  /// \p lenient: only no face turned inside out or to nothing (for moves far shorter than
  /// the faces, where slivers' normals say nothing).
  bool keeps_faces(VH v, const Vec3& to, std::optional<VH> other = std::nullopt,
                   bool lenient = false) const {
    const double min_area2 = std::pow(1e-3 * in_.spacing * in_.spacing, 2);
    for (auto f : mesh_.vf_range(v)) {
      std::array<Vec3, 3> before, after;
      int k = 0;
      bool has_other = false;
      for (auto w : mesh_.fv_range(f)) {
        before[k] = point(w);
        after[k] = w == v ? to : point(w);
        if (other && w == *other) has_other = true;
        ++k;
      }
      if (has_other) continue;  // this face goes away with the collapse
      const Vec3 nb = triangle_normal(before[0], before[1], before[2]);
      const Vec3 na = triangle_normal(after[0], after[1], after[2]);
      if (!lenient && na.squaredNorm() < min_area2) return false;
      if (!lenient && na.normalized().dot(nb.normalized()) < 0.3) return false;
      // Small turns add up: the face must also face the way the surface does at its corners.
      Vec3 surface_n = Vec3::Zero();
      for (auto w : mesh_.fv_range(f)) surface_n += normal_[w.idx()];
      if (!(na.dot(surface_n) > 0)) return false;
    }
    return true;
  }

  /// \p tiny: the edge is far shorter than the faces; its ends may be on two feature lines
  /// (which then meet there) and only inside-out faces stop it.
  bool may_collapse(HH h, bool tiny = false) {
    const VH from = mesh_.from_vertex_handle(h), to = mesh_.to_vertex_handle(h);
    const int rf = rank_[from.idx()], rt = rank_[to.idx()];
    if (rf == kCorner) return false;
    if (rf == kFeature && rt == kFree) return false;
    if (rf == kFeature && !tiny && !is_feature(from.idx(), to.idx())) return false;
    if (!mesh_.is_collapse_ok(h)) return false;
    return keeps_faces(from, point(to), to, tiny);
  }

  void collapse(HH h) {
    const int from = mesh_.from_vertex_handle(h).idx(), to = mesh_.to_vertex_handle(h).idx();
    for (int y : feature_nb_[from]) {
      if (y == to) continue;
      auto& ny = feature_nb_[y];
      std::replace(ny.begin(), ny.end(), from, to);
      std::sort(ny.begin(), ny.end());
      ny.erase(std::unique(ny.begin(), ny.end()), ny.end());
      feature_nb_[to].push_back(y);
    }
    auto& nt = feature_nb_[to];
    nt.erase(std::remove(nt.begin(), nt.end(), from), nt.end());
    std::sort(nt.begin(), nt.end());
    nt.erase(std::unique(nt.begin(), nt.end()), nt.end());
    feature_nb_[from].clear();
    if (offsets_ && offsets_->has(to, from)) {
      std::vector<int> around;
      for (auto v : mesh_.vv_range(VH(from))) around.push_back(v.idx());
      offsets_->merge(to, from, around);
    }
    // Two feature lines that met here make a corner.
    const int rank = nt.empty() ? kFree : nt.size() == 2 ? kFeature : kCorner;
    rank_[to] = std::max(rank_[to], rank);
    mesh_.collapse(h);
  }

  /// Rounds of edge collapses, until one collapses nothing or \p rounds are done: an edge
  /// goes where \p keep(a, b) says which end stays (true: a, false: b, nullopt: not this
  /// edge); the other end is tried where the first may not collapse. \p tiny as in
  /// may_collapse.
  template <typename Keep>
  void collapse_edges(int rounds, bool tiny, Keep keep) {
    for (int round = 0; round < rounds; ++round) {
      int collapsed = 0;
      for (auto e : mesh_.edges()) {
        if (mesh_.status(e).deleted()) continue;
        const HH h0 = mesh_.halfedge_handle(e, 0), h1 = mesh_.halfedge_handle(e, 1);
        const int a = mesh_.to_vertex_handle(h0).idx(), b = mesh_.to_vertex_handle(h1).idx();
        const std::optional<bool> keep_a = keep(a, b);
        if (!keep_a) continue;
        // h0 runs from b to a: collapsing it keeps a; h1 keeps b.
        for (HH h : {*keep_a ? h0 : h1, *keep_a ? h1 : h0})
          if (may_collapse(h, tiny)) {
            collapse(h);
            ++collapsed;
            break;
          }
      }
      if (collapsed == 0) break;
    }
  }

  /// Edges far shorter than the lattice spacing (the remesher leaves a few where it may not
  /// collapse) become points, so no face is a speck; the end of higher rank stays.
  void collapse_short_edges() {
    const double min_length = 0.05 * in_.spacing;
    collapse_edges(5, true, [&](int a, int b) -> std::optional<bool> {
      if ((point(VH(a)) - point(VH(b))).norm() >= min_length) return std::nullopt;
      return rank_[a] >= rank_[b];
    });
  }

  /// Vertices at the same lattice point become one; the end of higher rank stays, then the
  /// one nearer its lattice point.
  void collapse_same_lattice_points() {
    auto score = [&](int v) { return rank_[v] * 1e9 - (point(VH(v)) - pos_[v]).norm(); };
    collapse_edges(20, false, [&](int a, int b) -> std::optional<bool> {
      const LatticeOffset off = offset(a, b);
      if (off.offset != Eigen::Vector2i::Zero() || off.gap > 0.35) return std::nullopt;
      return score(a) >= score(b);
    });
  }

  Vec3 lattice_target(VH v) const {
    const int i = v.idx();
    if (rank_[i] == kCorner) return point(v);
    if (rank_[i] == kFeature) {
      Vec3 best = point(v);
      double best_d = std::numeric_limits<double>::infinity();
      for (int y : feature_nb_[i]) {
        const Vec3 c = closest_on_segment(pos_[i], point(v), point(VH(y)));
        const double d = (c - pos_[i]).norm();
        if (d < best_d) {
          best_d = d;
          best = c;
        }
      }
      return best;
    }
    return in_.project(pos_[i]);
  }

  void move_to_lattice_points() {
    for (int pass = 0; pass < 2; ++pass)
      for (auto v : mesh_.vertices()) {
        if (mesh_.status(v).deleted() || mesh_.is_isolated(v)) continue;
        const Vec3 p = point(v), target = lattice_target(v);
        for (double t : {1.0, 0.5, 0.25}) {
          const Vec3 q = p + t * (target - p);
          if (keeps_faces(v, q)) {
            mesh_.set_point(v, to_openmesh(q));
            break;
          }
        }
      }
  }

  /// Pairs triangles into quads: best-shaped pairs across lattice diagonals first, then
  /// augmenting paths so that as few triangles as possible are left.
  void pair_triangles(double min_quality) {
    std::vector<int> face_id(mesh_.n_faces(), -1);
    for (auto f : mesh_.faces()) {
      face_id[f.idx()] = static_cast<int>(faces_.size());
      std::array<int, 3> c{};
      int k = 0;
      for (auto v : mesh_.fv_range(f)) c[k++] = v.idx();
      faces_.push_back(c);
    }
    const int nf = static_cast<int>(faces_.size());
    struct Candidate {
      double weight;
      int a, b;  // faces
      std::array<int, 4> quad;
    };
    std::vector<Candidate> candidates;
    for (auto e : mesh_.edges()) {
      if (mesh_.status(e).deleted() || mesh_.is_boundary(e)) continue;
      const HH h = mesh_.halfedge_handle(e, 0), o = mesh_.opposite_halfedge_handle(h);
      const int a = mesh_.from_vertex_handle(h).idx(), b = mesh_.to_vertex_handle(h).idx();
      if (is_feature(a, b)) continue;
      const int ca = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h)).idx();
      const int cb = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(o)).idx();
      const Vec3 pa = point(VH(a)), pb = point(VH(b)), pca = point(VH(ca)), pcb = point(VH(cb));
      const Vec3 na = triangle_normal(pa, pb, pca), nb = triangle_normal(pb, pa, pcb);
      const bool folded = angle_between(na, nb) > kPi / 2;
      const double angles[4] = {
          corner_angle(pa, pca, pb) + corner_angle(pa, pb, pcb), corner_angle(pcb, pa, pb),
          corner_angle(pb, pcb, pa) + corner_angle(pb, pa, pca), corner_angle(pca, pb, pa)};
      double quality = 1.0;
      for (double t : angles) quality = std::min(quality, 1.0 - std::abs(t - kPi / 2) / (kPi / 2));
      if (folded || quality <= min_quality) continue;
      double bonus = 0;
      const Eigen::Vector2i d = offset(a, b).offset.cwiseAbs();
      if (d == Eigen::Vector2i(1, 1)) bonus += 1.0;
      for (auto [x, y] : {std::pair{a, cb}, {cb, b}, {b, ca}, {ca, a}})
        if (offset(x, y).offset.cwiseAbs().sum() == 1) bonus += 0.25;
      candidates.push_back({quality + bonus,
                            face_id[mesh_.face_handle(h).idx()],
                            face_id[mesh_.face_handle(o).idx()],
                            {a, cb, b, ca}});
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& x, const Candidate& y) { return x.weight > y.weight; });
    std::vector<int> mate(nf, -1);
    {
      // The best perfect pairing where one exists: least cost, cost = best weight - weight.
      std::vector<MatchingPair> pairs;
      const double top = candidates.empty() ? 0.0 : candidates.front().weight;
      for (const Candidate& c : candidates) pairs.push_back({c.a, c.b, top - c.weight + 0.01});
      // In a pure lattice a piece (between features and borders) of odd count leaves one
      // triangle: it pairs with a node of its own at a cost above any real pair's.
      int nodes = nf;
      if (in_.mode == LatticeInput::Mode::kPure) {
        const Pieces p = pieces();
        std::vector<int> dummy(p.count.size(), -1);
        for (std::size_t id = 0; id < p.count.size(); ++id)
          if (p.count[id] % 2 == 1) dummy[id] = nodes++;
        for (auto f : mesh_.faces())
          if (dummy[p.of[f.idx()]] >= 0)
            pairs.push_back({face_id[f.idx()], dummy[p.of[f.idx()]], top + 2.0});
      }
      if (nodes % 2 == 0 && !pairs.empty()) {
        const MatchingResult m = min_cost_perfect_matching(nodes, pairs, 10.0);
        if (!m.mate.empty()) {
          mate.assign(m.mate.begin(), m.mate.begin() + nf);
          for (int& x : mate) x = x >= nf ? -1 : x;
        }
      }
    }
    std::vector<std::vector<int>> adjacent(nf);  // candidate indices per face
    for (int c = 0; c < static_cast<int>(candidates.size()); ++c) {
      adjacent[candidates[c].a].push_back(c);
      adjacent[candidates[c].b].push_back(c);
      if (mate[candidates[c].a] < 0 && mate[candidates[c].b] < 0 && mate[candidates[c].a] != -2) {
        mate[candidates[c].a] = candidates[c].b;
        mate[candidates[c].b] = candidates[c].a;
      }
    }
    // Augmenting paths (alternating, any length) from each unpaired triangle.
    auto other = [&](int c, int f) {
      return candidates[c].a == f ? candidates[c].b : candidates[c].a;
    };
    std::vector<int> parent(nf, -1), seen(nf, -1);
    for (int round = 0; round < 3; ++round)
      for (int u = 0; u < nf; ++u) {
        if (mate[u] >= 0) continue;
        std::deque<std::pair<int, int>> queue{{u, 0}};
        seen[u] = u + round * nf;
        parent[u] = -1;
        int end = -1, end_from = -1;
        while (!queue.empty() && end < 0) {
          const auto [x, depth] = queue.front();
          queue.pop_front();
          for (int c : adjacent[x]) {
            const int y = other(c, x);
            if (y == u || y == mate[x]) continue;
            if (mate[y] < 0) {
              end = y;
              end_from = x;
              break;
            }
            const int z = mate[y];
            if (seen[z] == u + round * nf) continue;
            seen[z] = u + round * nf;
            parent[z] = x;  // z reached from x over the free edge x-y and the pair y-z
            queue.push_back({z, depth + 1});
          }
        }
        if (end < 0) continue;
        // Flip the path: end - end_from, then end_from's old mate with its parent, and so on.
        int y = end, x = end_from;
        while (true) {
          const int old_mate = mate[x];  // x was reached through it (none for u)
          const int from = parent[x];
          mate[x] = y;
          mate[y] = x;
          if (x == u) break;
          y = old_mate;
          x = from;
        }
      }
    std::vector<char> used(nf, 0);
    for (const Candidate& c : candidates)
      if (mate[c.a] == c.b && !used[c.a] && !used[c.b]) {
        used[c.a] = used[c.b] = 1;
        quads_.push_back(c.quad);
      }
    for (int f = 0; f < nf; ++f)
      if (!used[f]) triangles_.push_back(faces_[f]);
  }

  /// The paired quads as they are (every triangle found a partner).
  LatticeResult quads_only() {
    LatticeResult r;
    r.lattice_quads = static_cast<int>(quads_.size());
    std::vector<std::vector<int>> faces;
    for (const auto& q : quads_) faces.emplace_back(q.begin(), q.end());
    std::vector<Vec3> at(mesh_.n_vertices());
    std::vector<char> pinned(mesh_.n_vertices(), 0);
    for (std::size_t v = 0; v < at.size(); ++v) {
      at[v] = point(VH(static_cast<int>(v)));
      pinned[v] = rank_[v] != kFree;
    }
    build(r, std::move(faces), std::move(at), std::move(pinned));
    return r;
  }

  /// The paired quads with the triangles left over made quads in pairs, each pair by
  /// splitting the row of quads between them (bridges.h); none where some triangle is left.
  LatticeResult bridged() {
    LatticeResult r;
    r.lattice_quads = static_cast<int>(quads_.size());
    r.lattice_triangles = static_cast<int>(triangles_.size());
    std::vector<std::vector<int>> faces;
    for (const auto& q : quads_) faces.emplace_back(q.begin(), q.end());
    for (const auto& t : triangles_) faces.emplace_back(t.begin(), t.end());
    const int n = static_cast<int>(mesh_.n_vertices());
    BridgeResult b =
        bridge_triangles(std::move(faces), n, [&](int x, int y) { return is_feature(x, y); });
    if (!b.complete) return r;
    r.rows = b.rows;
    std::vector<Vec3> at(n);
    std::vector<char> pinned(n, 0);  // feature vertices and feature-edge middles stay put
    for (int v = 0; v < n; ++v) {
      at[v] = point(VH(v));
      pinned[v] = rank_[v] != kFree;
    }
    for (const BridgeVertex& v : b.added) {
      Vec3 mean = Vec3::Zero();
      for (int i = 0; i < v.count; ++i) mean += at[v.from[i]];
      mean /= v.count;
      at.push_back(v.feature || !in_.on_surface ? mean : in_.project(mean));
      pinned.push_back(v.feature);
    }
    build(r, std::move(b.faces), std::move(at), std::move(pinned));
    return r;
  }

  /// \p r's quads from all-quad \p faces on \p at: irregular vertices cleaned up
  /// (cleanup.h), then made good (finish). Feature edges are the input's and, among new
  /// vertices, those joining two pinned ones.
  void build(LatticeResult& r, std::vector<std::vector<int>> faces, std::vector<Vec3> at,
             std::vector<char> pinned) const {
    const int n = static_cast<int>(mesh_.n_vertices());
    const auto feature = [&](int x, int y) {
      return x < n && y < n ? is_feature(x, y) : pinned[x] && pinned[y];
    };
    CleanupResult c =
        clean_up_valences(std::move(faces), std::move(at), pinned, feature, in_.normal_at);
    r.rotations = c.rotations;
    r.collapses = c.collapses;
    PolyMesh& out = r.quads;
    std::map<int, OpenMesh::SmartVertexHandle> handle;
    std::vector<char> out_pinned;
    for (const auto& f : c.faces) {
      std::vector<OpenMesh::VertexHandle> vs;
      for (int v : f) {
        auto it = handle.find(v);
        if (it == handle.end()) {
          it = handle.emplace(v, out.add_vertex(to_openmesh(c.points[v]))).first;
          out_pinned.push_back(pinned[v]);
        }
        vs.push_back(it->second);
      }
      out.add_face(vs);
    }
    finish(out, out_pinned);
  }

  /// Pieces of the surface between borders and features, each face's piece; per piece its
  /// face count, a border halfedge (if any) and the feature halfedges on its rim.
  struct Pieces {
    std::vector<int> of;
    std::vector<int> count;
    std::vector<HH> border;
    std::vector<std::vector<HH>> rim;
  };

  Pieces pieces() const {
    Pieces p;
    p.of.assign(mesh_.n_faces(), -1);
    for (auto f : mesh_.faces()) {
      if (p.of[f.idx()] >= 0) continue;
      const int id = static_cast<int>(p.count.size());
      p.count.push_back(0);
      p.border.push_back(HH());
      p.rim.emplace_back();
      std::vector<OpenMesh::FaceHandle> stack{f};
      p.of[f.idx()] = id;
      while (!stack.empty()) {
        const auto g = stack.back();
        stack.pop_back();
        ++p.count[id];
        for (auto h : mesh_.fh_range(g)) {
          const auto o = mesh_.opposite_halfedge_handle(h);
          if (mesh_.is_boundary(o)) {
            if (!p.border[id].is_valid()) p.border[id] = h;
            continue;
          }
          const int a = mesh_.from_vertex_handle(h).idx(), b = mesh_.to_vertex_handle(h).idx();
          if (is_feature(a, b)) {
            p.rim[id].push_back(h);
            continue;
          }
          const auto nf = mesh_.face_handle(o);
          if (p.of[nf.idx()] < 0) {
            p.of[nf.idx()] = id;
            stack.push_back(nf);
          }
        }
      }
    }
    return p;
  }

  /// A piece with an odd number of triangles has no perfect pairing. One of its border edges
  /// is split at its middle (its triangle becomes two); a piece without a border splits a
  /// feature edge on its rim, which changes the count of the piece across it too: another odd
  /// one where there is one, else the parity moves on and is mended there.
  void make_triangle_count_even() {
    for (int round = 0; round < 200; ++round) {
      const Pieces p = pieces();
      bool changed = false;
      std::vector<char> touched(p.count.size(), 0);
      for (std::size_t id = 0; id < p.count.size(); ++id) {
        if (p.count[id] % 2 == 0 || touched[id]) continue;
        if (p.border[id].is_valid()) {
          split_edge(p.border[id]);
          touched[id] = 1;
          changed = true;
          continue;
        }
        // The piece across each rim edge, as the round began: a split earlier in this round
        // may have put a new face there, which no piece of this round holds (read past the
        // pieces, it wrote past the touched marks and crashed the run: Spot from its triangles
        // with --quad-feature-angle 20 --quad-size 9.5); that edge waits for the next round.
        const auto across = [&](HH h) {
          const int f = mesh_.face_handle(mesh_.opposite_halfedge_handle(h)).idx();
          return f >= 0 && f < static_cast<int>(p.of.size()) ? p.of[f] : -1;
        };
        HH pick;
        int picked = -1;
        for (HH h : p.rim[id]) {
          const int other = across(h);
          if (other < 0 || touched[other]) continue;
          if (!pick.is_valid() || p.count[other] % 2 == 1) pick = h, picked = other;
          if (p.count[other] % 2 == 1) break;
        }
        if (!pick.is_valid()) continue;
        touched[id] = 1;
        touched[picked] = 1;
        split_edge(pick);
        changed = true;
      }
      if (!changed) break;
    }
  }

  /// Splits the (border or feature) edge of \p h at its middle, which stays on the feature.
  void split_edge(OpenMesh::HalfedgeHandle h) {
    const int a = mesh_.from_vertex_handle(h).idx(), b = mesh_.to_vertex_handle(h).idx();
    const Vec3 m = 0.5 * (point(VH(a)) + point(VH(b)));
    const VH v = mesh_.add_vertex(to_openmesh(m));
    mesh_.split(mesh_.edge_handle(h), v);
    feature_nb_.push_back({});
    rank_.push_back(kFeature);
    for (auto [x, y] : {std::pair{a, b}, {b, a}}) {
      auto& nb = feature_nb_[x];
      std::replace(nb.begin(), nb.end(), y, v.idx());
      std::sort(nb.begin(), nb.end());
    }
    feature_nb_[v.idx()] = {std::min(a, b), std::max(a, b)};
    pos_.push_back(m);
    cross_.push_back(cross_[a]);
    normal_.push_back(normal_[a]);
  }

  LatticeResult split() {
    LatticeResult r;
    r.lattice_quads = static_cast<int>(quads_.size());
    r.lattice_triangles = static_cast<int>(triangles_.size());
    r.split = true;
    const int n = static_cast<int>(mesh_.n_vertices());
    std::vector<Vec3> at(n);
    std::vector<char> pinned(n, 0);  // feature vertices and feature-edge midpoints stay put
    for (int v = 0; v < n; ++v) {
      at[v] = point(VH(v));
      pinned[v] = rank_[v] != kFree;
    }
    auto add = [&](const Vec3& p, bool pin) {
      at.push_back(p);
      pinned.push_back(pin);
      return static_cast<int>(at.size()) - 1;
    };
    std::map<std::pair<int, int>, int> middle;
    auto middle_of = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      const Vec3 m = 0.5 * (point(VH(a)) + point(VH(b)));
      const bool feature = is_feature(a, b);
      const int id = add(feature || !in_.on_surface ? m : in_.project(m), feature);
      middle.emplace(key, id);
      return id;
    };
    std::vector<std::vector<int>> faces;
    auto add_split = [&](const auto& corners) {
      const int k = static_cast<int>(corners.size());
      Vec3 centre = Vec3::Zero();
      for (int c : corners) centre += point(VH(c));
      centre /= k;
      const int hc = add(in_.on_surface ? in_.project(centre) : centre, false);
      for (int i = 0; i < k; ++i) {
        const int prev = corners[(i + k - 1) % k], cur = corners[i], next = corners[(i + 1) % k];
        faces.push_back({cur, middle_of(cur, next), hc, middle_of(prev, cur)});
      }
    };
    for (const auto& q : quads_) add_split(q);
    for (const auto& t : triangles_) add_split(t);
    build(r, std::move(faces), std::move(at), std::move(pinned));
    return r;
  }

  /// The quads made good: smoothed and untangled (every quad brought above a corner of about
  /// 3 degrees where it can be); polished if asked (LatticeInput::polish): doublets removed
  /// first, then a second untangling toward corners of 30 to 150 degrees and no collapsed edge,
  /// which never lowers the worst quad around a vertex, so never undoes the first. On Spot's
  /// triangle mesh polishing takes the corners under 30 degrees from 94 to none and those over
  /// 150 from 96 to none (of 4168), the shortest edge from 0.4 to 1.4 mm.
  void finish(PolyMesh& out, std::vector<char>& pinned) const {
    if (in_.polish) remove_doublets(out, pinned);
    relax(out, pinned);
    if (!untangle(out, pinned, 0.05, std::numeric_limits<double>::infinity(), false, kPastMending))
      return;
    if (!in_.polish) return;
    // A vertex that stands out of its neighbours' plane (the tip of an ear or a horn) stays:
    // moved toward their middle it would slide back along the target and the quads would no
    // longer reach the tip. (Only with the new points on the target: off it, as plain midpoints
    // and centres, nothing is held.)
    std::vector<char> held = pinned;
    if (in_.on_surface)
      for (auto v : out.vertices()) {
        const Neighbours nb = neighbours(out, v);
        const Vec3 here = to_eigen(out.point(v));
        if (nb.count > 0 && std::abs((here - nb.mean).dot(in_.normal_at(here))) > kTip * nb.edge)
          held[v.idx()] = 1;
      }
    untangle(out, held, 0.5, kPolishReach, true);
  }

  /// The vertices joined to \p v by an edge: how many, their mean, the mean edge length.
  struct Neighbours {
    int count = 0;
    Vec3 mean = Vec3::Zero();
    double edge = 0;  // [mm]
  };
  static Neighbours neighbours(const PolyMesh& out, OpenMesh::VertexHandle v) {
    Neighbours nb;
    const Vec3 here = to_eigen(out.point(v));
    for (auto w : out.vv_range(v)) {
      nb.mean += to_eigen(out.point(w));
      nb.edge += (to_eigen(out.point(w)) - here).norm();
      ++nb.count;
    }
    if (nb.count > 0) nb.mean /= nb.count, nb.edge /= nb.count;
    return nb;
  }

  /// How far out of its neighbours' plane a vertex stands before polishing leaves it where it
  /// is, in mean edges around it.
  static constexpr double kTip = 0.25;

  /// How far polishing may move a vertex, in mean edges around it: a thin part's tip (an ear)
  /// would otherwise slide back and the quads no longer reach it.
  static constexpr double kPolishReach = 0.4;

  /// How far a doublet vertex may stand off the plane of the quad it is merged into, in lattice
  /// spacings.
  static constexpr double kDoubletOffPlane = 0.1;

  /// A doublet, an inner vertex with two quads only (they share both its edges), makes both
  /// quads flat at it: the vertex goes and the two quads become one, the four other corners
  /// (the Euler characteristic stays: one vertex, two edges and one face fewer). Repeated until
  /// none is left; the mesh is rebuilt with the vertices that remain.
  void remove_doublets(PolyMesh& out, std::vector<char>& pinned) const {
    std::vector<std::vector<int>> faces;
    for (auto f : out.faces()) {
      std::vector<int> vs;
      for (auto v : f.vertices()) vs.push_back(v.idx());
      faces.push_back(vs);
    }
    const int nv = static_cast<int>(out.n_vertices());
    std::vector<char> gone_vertex(nv, 0), gone_face(faces.size(), 0), border(nv, 0);
    for (auto v : out.vertices()) border[v.idx()] = out.is_boundary(v) ? 1 : 0;
    bool any = false;
    for (bool changed = true; changed;) {
      changed = false;
      std::vector<std::vector<int>> around(nv);
      for (std::size_t f = 0; f < faces.size(); ++f)
        if (!gone_face[f])
          for (int v : faces[f]) around[v].push_back(static_cast<int>(f));
      for (int d = 0; d < nv; ++d) {
        if (gone_vertex[d] || border[d] || around[d].size() != 2) continue;
        const int f1 = around[d][0], f2 = around[d][1];
        if (gone_face[f1] || gone_face[f2] || faces[f1].size() != 4 || faces[f2].size() != 4)
          continue;
        auto from_d = [&](const std::vector<int>& f) {
          std::vector<int> r(4);
          const int at = static_cast<int>(std::find(f.begin(), f.end(), d) - f.begin());
          for (int i = 0; i < 4; ++i) r[i] = f[(at + i) % 4];
          return r;
        };
        const std::vector<int> a = from_d(faces[f1]), b = from_d(faces[f2]);
        if (b[1] != a[3] || b[3] != a[1] || a[2] == b[2]) continue;
        // Not where the vertex stands off the merged quad's plane (a thin part's tip, which
        // the quads would no longer reach): there the two quads stay.
        auto at = [&](int v) { return to_eigen(out.point(OpenMesh::VertexHandle(v))); };
        const Vec3 n = (at(a[3]) - at(a[1])).cross(at(b[2]) - at(a[2]));
        if (!(n.norm() > 0) ||
            std::abs((at(d) - at(a[1])).dot(n.normalized())) > kDoubletOffPlane * in_.spacing)
          continue;
        // Nor where the merged quad would not be convex.
        const std::array<int, 4> m = {a[1], a[2], a[3], b[2]};
        bool convex = true;
        for (int i = 0; i < 4; ++i)
          convex = convex &&
                   (at(m[(i + 1) % 4]) - at(m[i])).cross(at(m[(i + 3) % 4]) - at(m[i])).dot(n) > 0;
        if (!convex) continue;
        faces[f1] = {a[1], a[2], a[3], b[2]};
        gone_face[f2] = 1;
        gone_vertex[d] = 1;
        changed = any = true;
        break;  // the faces around the others changed
      }
    }
    if (!any) return;
    PolyMesh rebuilt;
    std::vector<OpenMesh::VertexHandle> handle(nv);
    std::vector<char> kept_pinned;
    for (int v = 0; v < nv; ++v)
      if (!gone_vertex[v]) {
        handle[v] = rebuilt.add_vertex(out.point(OpenMesh::VertexHandle(v)));
        kept_pinned.push_back(pinned[v]);
      }
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (gone_face[f]) continue;
      std::vector<OpenMesh::VertexHandle> vs;
      for (int v : faces[f]) vs.push_back(handle[v]);
      rebuilt.add_face(vs);
    }
    out = std::move(rebuilt);
    pinned = std::move(kept_pinned);
  }

  /// A few rounds of tangential smoothing of the free vertices (each moves to the mean of its
  /// neighbours, projected back onto the target), where no face folds by it.
  void relax(PolyMesh& out, const std::vector<char>& pinned) const {
    if (!in_.on_surface) return;
    auto face_normal = [&](OpenMesh::FaceHandle f, OpenMesh::VertexHandle moved, const Vec3& at) {
      std::array<Vec3, 4> c;
      int k = 0;
      for (auto w : out.fv_range(f)) c[k++ & 3] = w == moved ? at : to_eigen(out.point(w));
      return Vec3((c[2] - c[0]).cross(c[3] - c[1]));
    };
    for (int it = 0; it < 3; ++it)
      for (auto v : out.vertices()) {
        if (pinned[v.idx()] || out.is_boundary(v)) continue;
        const Neighbours nb = neighbours(out, v);
        if (nb.count == 0) continue;
        const Vec3 target = in_.project(nb.mean);
        const Vec3 here = to_eigen(out.point(v));
        bool ok = true;
        for (auto f : v.faces()) {
          const Vec3 before = face_normal(f, v, here), after = face_normal(f, v, target);
          if (after.norm() < 1e-3 * in_.spacing * in_.spacing ||
              after.normalized().dot(before.normalized()) < 0.5)
            ok = false;
        }
        if (ok) out.set_point(v, to_openmesh(target));
      }
  }

  /// How well the quad \p f is shaped with \p moved at \p at: the smallest sine of its corner
  /// angles, signed against the target's normal (negative: reflex or inside out); with \p edges
  /// twice its shortest edge over its mean edge if less.
  double quality(const PolyMesh& out, OpenMesh::FaceHandle f, OpenMesh::VertexHandle moved,
                 const Vec3& at, bool edges) const {
    std::array<Vec3, 4> c;
    std::array<int, 4> id{-1, -1, -1, -1};
    int k = 0;
    for (auto w : out.fv_range(f)) {
      if (k < 4) id[k] = w.idx();
      c[k++ & 3] = w == moved ? at : to_eigen(out.point(w));
    }
    if (k != 4) return -1;
    std::array<Vec3, 4> corner_n;
    Vec3 n = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      corner_n[i] = (c[(i + 1) % 4] - c[i]).cross(c[(i + 3) % 4] - c[i]);
      n += corner_n[i];
    }
    if (!(n.norm() > 0)) return -1;
    n.normalize();
    double q = 1;
    for (int i = 0; i < 4; ++i) {
      const double d = (c[(i + 1) % 4] - c[i]).norm() * (c[(i + 3) % 4] - c[i]).norm();
      if (!(d > 0)) return -1;
      q = std::min(q, corner_n[i].dot(n) / d);
    }
    // An edge that shrinks to nothing leaves fine angles (the quad becomes a triangle): the
    // shortest edge counts too, twice its ratio to the mean edge.
    if (edges) {
      double shortest = std::numeric_limits<double>::infinity(), mean = 0;
      for (int i = 0; i < 4; ++i) {
        const double e = (c[(i + 1) % 4] - c[i]).norm();
        shortest = std::min(shortest, e);
        mean += 0.25 * e;
      }
      q = std::min(q, 2 * shortest / mean);
    }
    // Facing the way the target does at one of its corners at least (near a thin part the
    // nearest facet of some corner may be the other side's).
    double agree = -1;
    for (int i = 0; i < 4; ++i) agree = std::max(agree, n.dot(normal_at(id[i], c[i])));
    return std::min(q, agree);
  }

  /// The target's normal near \p p (LatticeInput::normal_at), kept per vertex \p v for as long
  /// as it is asked at the same point: untangle() asks for the corners of the same quads over
  /// and over, and each answer is a query of the target (a block with a round hole, of long
  /// thin triangles: 124 s in the quads stage, nearly all of it in those queries).
  Vec3 normal_at(int v, const Vec3& p) const {
    if (v < 0) return in_.normal_at(p);
    if (normals_at_.size() <= static_cast<std::size_t>(v)) normals_at_.resize(v + 1);
    auto& [where, normal] = normals_at_[v];
    if (!where || *where != p) {
      where = p;
      normal = in_.normal_at(p);
    }
    return normal;
  }

  /// Free vertices of quads whose quality() is under \p good (0.05: a corner under about 3
  /// degrees, reflex, or inside out) move to where the worst quad around them is best: the mean
  /// of their neighbours, the mean of the faces' centres, halfway to either, then a pattern
  /// search around the best of those, at most a mean edge away per round and \p reach mean edges
  /// from where the pass found them (all on the target, unless on_surface is false).
  /// Returns false where it gave up at once: more than \p give_up_share of the quads started
  /// below \p good.
  bool untangle(PolyMesh& out, const std::vector<char>& pinned, double good, double reach,
                bool edges, double give_up_share = 1) const {
    const OpenMesh::VertexHandle none;
    std::vector<Vec3> origin;
    for (auto v : out.vertices()) origin.push_back(to_eigen(out.point(v)));
    for (int round = 0; round < 30; ++round) {
      std::vector<char> involved(out.n_vertices(), 0);
      int bad = 0;
      for (auto f : out.faces())
        if (quality(out, f, none, Vec3::Zero(), edges) < good) {
          ++bad;
          for (auto v : out.fv_range(f)) involved[v.idx()] = 1;
        }
      if (bad == 0) return true;
      // A lattice that starts with most of its quads folded, flat or inverted is past mending
      // (on the shared meshes at most 8 % start so; a star prism's split lattice 82 %, and 30
      // rounds on it, four times over, took 17 s to leave 80 %): it fails the check as it is.
      if (round == 0 && bad > give_up_share * static_cast<double>(out.n_faces())) return false;
      bool moved = false;
      for (auto v : out.vertices()) {
        if (!involved[v.idx()] || pinned[v.idx()] || out.is_boundary(v)) continue;
        auto worst = [&](const Vec3& at) {
          double q = 1;
          for (auto f : v.faces()) q = std::min(q, quality(out, f, v, at, edges));
          return q;
        };
        const Vec3 here = to_eigen(out.point(v));
        const Neighbours nb = neighbours(out, v);
        const Vec3& mean = nb.mean;
        const double edge = nb.edge;
        Vec3 centres = Vec3::Zero();
        int m = 0;
        for (auto f : v.faces())
          for (auto w : f.vertices())
            if (w != v) {
              centres += to_eigen(out.point(w));
              ++m;
            }
        if (nb.count == 0 || m == 0) continue;
        centres /= m;
        std::vector<Vec3> options{mean, centres, 0.5 * (here + mean), 0.5 * (here + centres)};
        if (in_.on_surface)
          for (Vec3& p : options) p = in_.project(p);
        // How far from where it started this pass the vertex may go.
        auto within = [&](const Vec3& p) { return (p - origin[v.idx()]).norm() <= reach * edge; };
        double best = worst(here);
        Vec3 at = here;
        for (const Vec3& p : options) {
          if (!within(p)) continue;
          const double q = worst(p);
          if (q > best + 1e-9) {
            best = q;
            at = p;
          }
        }
        // Then a pattern search in the tangent plane, steps from half the mean edge down.
        const Vec3 normal = in_.normal_at(at);
        const Vec3 t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
        for (double step = 0.5 * edge; step > 0.01 * edge && best < good;) {
          bool better = false;
          for (int d = 0; d < 8; ++d) {
            const double a = d * kPi / 4;
            Vec3 p = at + step * (std::cos(a) * t1 + std::sin(a) * t2);
            if (in_.on_surface) p = in_.project(p);
            if ((p - here).norm() > edge || !within(p)) continue;
            const double q = worst(p);
            if (q > best + 1e-9) {
              best = q;
              at = p;
              better = true;
            }
          }
          if (!better) step *= 0.5;
        }
        if (at != here) {
          out.set_point(v, to_openmesh(at));
          moved = true;
        }
      }
      if (!moved) return true;
    }
    return true;
  }

  const LatticeInput& in_;
  const Surface& s_;
  WorkMesh mesh_;
  std::optional<IntegerLattice> offsets_;   ///< as given, kept through the collapses
  std::vector<Vec3> pos_, cross_, normal_;  // per vertex, growing with border splits
  std::vector<std::vector<int>> feature_nb_;
  std::vector<int> rank_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<std::array<int, 4>> quads_;
  std::vector<std::array<int, 3>> triangles_;
  /// normal_at(v, p): per vertex, the point last asked and the normal there.
  mutable std::vector<std::pair<std::optional<Vec3>, Vec3>> normals_at_;
};

}  // namespace

LatticeResult extract_quads(const LatticeInput& input) { return Extractor(input).run(); }

}  // namespace kerfab::quads

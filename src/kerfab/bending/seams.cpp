#include "kerfab/bending/seams.h"

#include <algorithm>
#include <cassert>
#include <cstdlib>
#include <limits>
#include <queue>
#include <set>
#include <tuple>

#include "kerfab/adapters/matching_program.h"

namespace kerfab {
namespace {

constexpr int kFar = std::numeric_limits<int>::max() / 4;
constexpr int kMaxSeamEnds = 1000;                 // odd vertices: the pairing is quadratic in them
constexpr long long kMaxTreeEntries = 20'000'000;  // odd vertices x vertices: seams planned
constexpr int kMaxExactMatchingNodes = 400;        // matching program up to this many nodes

// Distances from the given sources over the mesh's vertex graph, and for each reached vertex
// the edge it was reached by (-1 at a source).
struct Tree {
  std::vector<int> dist, via;
};

// Interior vertices of odd valence: the ends of seams.
std::vector<int> odd_valence_vertices(const PolyMesh& m) {
  std::vector<int> odd;
  for (auto v : m.vertices())
    if (!m.is_isolated(v) && !m.is_boundary(v) && m.valence(v) % 2 == 1) odd.push_back(v.idx());
  return odd;
}

// Shortest paths from the given sources with integer edge costs (Dijkstra); dist in cost units.
Tree shortest_paths(const PolyMesh& m, const std::vector<int>& sources,
                    const std::vector<int>& edge_cost) {
  Tree t{std::vector<int>(m.n_vertices(), kFar), std::vector<int>(m.n_vertices(), -1)};
  using Item = std::pair<int, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  for (int s : sources) {
    t.dist[s] = 0;
    heap.emplace(0, s);
  }
  while (!heap.empty()) {
    const auto [d, u] = heap.top();
    heap.pop();
    if (d > t.dist[u]) continue;
    for (auto h : m.voh_range(m.vertex_handle(u))) {
      const int v = m.to_vertex_handle(h).idx();
      const int e = m.edge_handle(h).idx();
      if (d + edge_cost[e] < t.dist[v]) {
        t.dist[v] = d + edge_cost[e];
        t.via[v] = e;
        heap.emplace(t.dist[v], v);
      }
    }
  }
  return t;
}

// Edges where the quad mesh folds sharply: the dihedral angle between the two quads' normals
// exceeds 30 degrees.
std::vector<char> sharp_edges(const PolyMesh& m) {
  std::vector<char> sharp(m.n_edges(), 0);
  for (auto e : m.edges()) {
    if (m.is_boundary(e)) continue;
    const Vec3 n0 = to_eigen(m.calc_face_normal(m.face_handle(m.halfedge_handle(e, 0))));
    const Vec3 n1 = to_eigen(m.calc_face_normal(m.face_handle(m.halfedge_handle(e, 1))));
    if (n0.norm() > 0 && n1.norm() > 0 && angle_between(n0, n1) > M_PI / 6) sharp[e.idx()] = 1;
  }
  return sharp;
}

// Flips the seam flag along the tree path from v back to the tree's source.
void flip_path(const PolyMesh& m, const Tree& t, int v, std::vector<char>& seam) {
  while (t.via[v] >= 0) {
    const int e = t.via[v];
    seam[e] ^= 1;
    const auto h = m.halfedge_handle(m.edge_handle(e), 0);
    const int a = m.from_vertex_handle(h).idx(), b = m.to_vertex_handle(h).idx();
    v = (a == v) ? b : a;
  }
}

}  // namespace

SeamSelection seam_selection(const PolyMesh& quads) {
  SeamSelection r;
  const int ne = static_cast<int>(quads.n_edges());
  r.seam.assign(ne, 0);
  r.bendable.assign(ne, 0);

  const std::vector<int> odd = odd_valence_vertices(quads);
  std::vector<int> boundary;
  for (auto v : quads.vertices())
    if (!quads.is_isolated(v) && quads.is_boundary(v)) boundary.push_back(v.idx());
  r.odd_vertices = static_cast<int>(odd.size());
  const int k = r.odd_vertices;

  // Seam length counts edges; among equally short seams, those along sharp folds win (a strip
  // never crosses a seam, so a fold there splits nothing): each edge costs kUnit, a sharp one
  // one less, and kUnit exceeds the edge count so the tie-break never lengthens a seam.
  const std::vector<char> sharp = sharp_edges(quads);
  const int unit = static_cast<int>(quads.n_edges()) + 1;
  std::vector<int> edge_cost(ne);
  for (int e = 0; e < ne; ++e) edge_cost[e] = unit - sharp[e];
  // Meshes with very many odd vertices keep the plain field (no seams planned): the per-vertex
  // path trees cost |T| x |V| memory (capped at 20 million entries, 160 MB) and the pairing
  // |T|^2 (capped at 1000 odd vertices).
  if (k <= kMaxSeamEnds &&
      static_cast<long long>(k) * static_cast<long long>(quads.n_vertices()) <= kMaxTreeEntries) {
    // Matching graph: odd vertex i (node i) and, if there is a boundary, its boundary twin (node
    // k + i): i-j costs their distance, i-twin(i) the distance to the boundary, twin-twin 0.
    std::vector<Tree> trees;
    trees.reserve(k);
    for (int v : odd) trees.push_back(shortest_paths(quads, {v}, edge_cost));
    const bool has_boundary = !boundary.empty();
    const Tree to_boundary = has_boundary ? shortest_paths(quads, boundary, edge_cost) : Tree{};
    const int nodes = has_boundary ? 2 * k : k;
    auto cost = [&](int a, int b) -> long long {
      if (a > b) std::swap(a, b);
      if (b < k) return trees[a].dist[odd[b]];
      if (a >= k) return 0;                             // twin - twin
      if (b - k == a) return to_boundary.dist[odd[a]];  // vertex - own twin
      return kFar;                                      // vertex - other's twin: unused
    };

    // Greedy by cost, then 2-opt exchanges between pairs until none shortens the total.
    std::vector<int> mate(nodes, -1);
    {
      std::vector<std::tuple<long long, int, int>> pairs;
      for (int a = 0; a < nodes; ++a)
        for (int b = a + 1; b < nodes; ++b)
          if (cost(a, b) < kFar) pairs.emplace_back(cost(a, b), a, b);
      std::sort(pairs.begin(), pairs.end());
      for (const auto& [c, a, b] : pairs)
        if (mate[a] < 0 && mate[b] < 0) {
          mate[a] = b;
          mate[b] = a;
        }
    }
    // Nodes left unmatched (a component without boundary and an odd count cannot happen on a
    // closed component: the odd-valence count there is even) would only arise from kFar costs.
    for (bool improved = true; improved;) {
      improved = false;
      for (int a = 0; a < nodes; ++a) {
        for (int c = a + 1; c < nodes; ++c) {
          const int b = mate[a], d = mate[c];
          if (b < 0 || d < 0 || c == b) continue;
          const long long now = cost(a, b) + cost(c, d);
          if (cost(a, c) + cost(b, d) < now) {
            mate[a] = c, mate[c] = a, mate[b] = d, mate[d] = b;
            improved = true;
          } else if (cost(a, d) + cost(b, c) < now) {
            mate[a] = d, mate[d] = a, mate[b] = c, mate[c] = b;
            improved = true;
          }
        }
      }
    }
    // The exact pairing: the matching program over all pairs at finite cost, started from nothing
    // but usually closed at CBC's root (its zero-half cuts are the blossom inequalities).
    if (nodes <= kMaxExactMatchingNodes) {
      std::vector<MatchingPair> candidates;
      long long heuristic = 0;
      for (int a = 0; a < nodes; ++a) {
        if (mate[a] > a) heuristic += cost(a, mate[a]);
        for (int b = a + 1; b < nodes; ++b)
          if (cost(a, b) < kFar) candidates.push_back({a, b, static_cast<double>(cost(a, b))});
      }
      const MatchingResult exact = min_cost_perfect_matching(nodes, candidates, 20.0);
      r.pairing_optimal = exact.optimal;
      if (!exact.mate.empty() && exact.cost < heuristic - 0.5) mate = exact.mate;
    }
    for (int a = 0; a < k; ++a) {
      const int b = mate[a];
      if (b < 0) continue;
      if (b < k) {
        if (a < b) flip_path(quads, trees[a], odd[b], r.seam);
      } else if (b - k == a) {
        flip_path(quads, to_boundary, odd[a], r.seam);
      }
    }
  }

  // Axis field: propagate over the quads; across an edge off the seams the edge keeps its role
  // (axis or ruling), across a seam edge it changes role.
  const int nf = static_cast<int>(quads.n_faces());
  std::vector<int> axis(nf, -1), component(nf, -1);
  for (int root = 0; root < nf; ++root) {
    if (axis[root] >= 0) continue;
    axis[root] = 0;
    component[root] = root;
    std::queue<int> q;
    q.push(root);
    while (!q.empty()) {
      const auto f = quads.face_handle(q.front());
      q.pop();
      const auto ef = quad_edges(quads, f);
      for (int i = 0; i < 4; ++i) {
        const auto h = quads.halfedge_handle(quads.edge_handle(ef[i]), 0);
        auto g = quads.face_handle(h);
        if (g == f) g = quads.face_handle(quads.opposite_halfedge_handle(h));
        if (!g.is_valid() || axis[g.idx()] >= 0) continue;
        const auto eg = quad_edges(quads, g);
        const int j = static_cast<int>(std::find(eg.begin(), eg.end(), ef[i]) - eg.begin());
        const bool on_axis_f = axis[f.idx()] == i % 2;
        const bool on_axis_g = on_axis_f != static_cast<bool>(r.seam[ef[i]]);
        axis[g.idx()] = on_axis_g ? j % 2 : 1 - j % 2;
        component[g.idx()] = root;
        q.push(g.idx());
      }
    }
  }
  // Turning every axis of a component keeps its seams; turn it if more sharp edges would then
  // be rails (on both quads' axes) than rulings a strip must fold across.
  {
    std::vector<int> balance(nf, 0);  // per component root: rulings minus rails at sharp edges
    for (auto e : quads.edges()) {
      if (!sharp[e.idx()] || r.seam[e.idx()]) continue;
      const auto f = quads.face_handle(quads.halfedge_handle(e, 0));
      const auto ef = quad_edges(quads, f);
      const int i = static_cast<int>(std::find(ef.begin(), ef.end(), e.idx()) - ef.begin());
      balance[component[f.idx()]] += axis[f.idx()] == i % 2 ? -1 : 1;
    }
    for (int f = 0; f < nf; ++f)
      if (balance[component[f]] > 0) axis[f] = 1 - axis[f];
  }
  // Bendable where every bordering quad has the edge on its axis.
  std::vector<char> refused(ne, 0);
  for (auto f : quads.faces()) {
    const auto ef = quad_edges(quads, f);
    for (int i = 0; i < 4; ++i)
      if (axis[f.idx()] != i % 2) refused[ef[i]] = 1;
  }
  for (int e = 0; e < ne; ++e) {
    r.bendable[e] = !refused[e];
    r.seam_edges += r.seam[e];
  }
  return r;
}

namespace {

// The edges of `layer` split into groups connected by conflicts (consecutive in a quad); the
// groups that are simple cycles of odd length and miss the boundary, as sorted edge lists.
// `mark` is a zeroed per-edge buffer, returned zeroed.
std::vector<std::vector<int>> odd_cycle_groups(const PolyMesh& quads, const std::vector<int>& layer,
                                               std::vector<char>& mark) {
  std::vector<std::vector<int>> out;
  for (int e : layer) mark[e] = 1;
  auto neighbours = [&](int e) {  // ring edges consecutive to e in its quads (with repeats)
    std::vector<int> nb;
    for (int side = 0; side < 2; ++side) {
      const auto f = quads.face_handle(quads.halfedge_handle(quads.edge_handle(e), side));
      if (!f.is_valid()) continue;
      const auto ef = quad_edges(quads, f);
      const int i = static_cast<int>(std::find(ef.begin(), ef.end(), e) - ef.begin());
      for (int j : {ef[(i + 1) % 4], ef[(i + 3) % 4]})
        if (mark[j]) nb.push_back(j);
    }
    return nb;
  };
  // mark: 1 on the layer, 2 once grouped (no per-call array over all edges: this runs for every
  // ball of every odd vertex).
  for (int seed : layer) {
    if (mark[seed] == 2) continue;
    std::vector<int> group{seed}, stack{seed};
    mark[seed] = 2;
    bool simple = true;
    while (!stack.empty()) {
      const int e = stack.back();
      stack.pop_back();
      const auto nb = neighbours(e);
      simple =
          simple && nb.size() == 2 && nb[0] != nb[1] && !quads.is_boundary(quads.edge_handle(e));
      for (int j : nb)
        if (mark[j] != 2) {
          mark[j] = 2;
          group.push_back(j);
          stack.push_back(j);
        }
    }
    if (simple && group.size() % 2 == 1) {
      std::sort(group.begin(), group.end());
      out.push_back(std::move(group));
    }
  }
  for (int e : layer) mark[e] = 0;
  return out;
}

}  // namespace

std::vector<std::vector<int>> odd_rings(const PolyMesh& quads, int ball_radius, int moat_steps) {
  std::vector<std::vector<int>> rings;
  std::set<std::vector<int>> seen;
  std::vector<char> mark(quads.n_edges(), 0);
  auto keep_odd_cycles = [&](const std::vector<int>& layer) {
    for (auto& ring : odd_cycle_groups(quads, layer, mark))
      if (seen.insert(ring).second) rings.push_back(std::move(ring));
  };
  const std::vector<int> odd = odd_valence_vertices(quads);
  // Balls around each odd vertex (distances in edges): a breadth-first search that stops at
  // the ball, and only its edges, so the work per odd vertex is the ball's size, not the mesh's
  // (4000 odd vertices on a 12 000-quad prism took minutes with a search over the whole mesh).
  {
    constexpr std::size_t kMaxBall = 2000;  // vertices; a regular ball of radius 4 has 61
    std::vector<int> dist(quads.n_vertices(), kFar);
    for (int v : odd) {
      std::vector<int> visited = {v};
      dist[v] = 0;
      for (std::size_t i = 0; i < visited.size() && visited.size() <= kMaxBall; ++i) {
        const int u = visited[i];
        if (dist[u] > ball_radius) continue;
        for (auto w : quads.vv_range(quads.vertex_handle(u)))
          if (dist[w.idx()] == kFar) dist[w.idx()] = dist[u] + 1, visited.push_back(w.idx());
      }
      if (visited.size() > kMaxBall) {  // a ball over a high-valence vertex: its rings are long
        for (int u : visited) dist[u] = kFar;  // and optional (cuts), so it is left out
        continue;
      }
      std::vector<std::vector<int>> layer(ball_radius + 1);
      for (int u : visited)
        for (auto h : quads.voh_range(quads.vertex_handle(u))) {
          const int a = dist[u], b = dist[quads.to_vertex_handle(h).idx()];
          if (b == a + 1 && a <= ball_radius) layer[a].push_back(quads.edge_handle(h).idx());
        }
      for (auto& l : layer) {
        std::sort(l.begin(), l.end());
        keep_odd_cycles(l);
      }
      for (int u : visited) dist[u] = kFar;
    }
  }
  // Moats (the primal-dual growth for T-joins): every group of vertices holding an odd number
  // of odd vertices grows by one edge layer per step; groups that touch merge; a group with an
  // even count, or one that reached the boundary, stops. The boundary of each growing group
  // after each step is a ring around an odd cluster.
  const int nv = static_cast<int>(quads.n_vertices());
  std::vector<int> owner(nv, -1), parent;
  std::vector<int> odd_count;
  std::vector<char> frozen;
  auto find = [&](int c) {
    while (parent[c] != c) c = parent[c] = parent[parent[c]];
    return c;
  };
  auto unite = [&](int a, int b) {
    a = find(a), b = find(b);
    if (a == b) return;
    parent[b] = a;
    odd_count[a] += odd_count[b];
    frozen[a] = frozen[a] || frozen[b];
  };
  for (int v : odd) {
    owner[v] = static_cast<int>(parent.size());
    parent.push_back(owner[v]);
    odd_count.push_back(1);
    frozen.push_back(0);
  }
  auto growing = [&](int c) {
    c = find(c);
    return odd_count[c] % 2 == 1 && !frozen[c];
  };
  for (int step = 0; step < moat_steps; ++step) {
    // Merge touching groups, freeze those on the boundary.
    for (auto e : quads.edges()) {
      const auto h = quads.halfedge_handle(e, 0);
      const int a = owner[quads.from_vertex_handle(h).idx()];
      const int b = owner[quads.to_vertex_handle(h).idx()];
      if (a >= 0 && b >= 0) unite(a, b);
    }
    for (int v = 0; v < nv; ++v)
      if (owner[v] >= 0 && quads.is_boundary(quads.vertex_handle(v))) frozen[find(owner[v])] = 1;
    // Rings of the growing groups.
    std::vector<int> layer;
    bool any = false;
    for (auto e : quads.edges()) {
      const auto h = quads.halfedge_handle(e, 0);
      const int a = owner[quads.from_vertex_handle(h).idx()];
      const int b = owner[quads.to_vertex_handle(h).idx()];
      if ((a >= 0) != (b >= 0) && growing(a >= 0 ? a : b)) layer.push_back(e.idx());
    }
    keep_odd_cycles(layer);
    // Grow every growing group by one layer.
    std::vector<std::pair<int, int>> claims;
    for (int v = 0; v < nv; ++v) {
      if (owner[v] < 0 || !growing(owner[v])) continue;
      for (auto w : quads.vv_range(quads.vertex_handle(v)))
        if (owner[w.idx()] < 0) claims.emplace_back(w.idx(), owner[v]);
    }
    for (const auto& [w, c] : claims) {
      if (owner[w] < 0) {
        owner[w] = find(c);
        any = true;
      } else {
        unite(owner[w], c);
      }
    }
    if (!any) break;
  }
  return rings;
}

}  // namespace kerfab

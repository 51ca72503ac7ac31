#pragma once
/// \file Global integer step of the position field (internal to src/kerfab/quads), after
/// QuadriFlow's flow step (Huang et al. 2018, Sec. 4): per edge of the remeshed triangles the
/// integer lattice offset between its ends' lattice points; round a triangle where the cross
/// field does not turn, these offsets sum to zero unless the lattice has a dislocation there
/// (a position singularity, which extraction turns into a pair of valence 3 and 5). Such
/// charges are cancelled in pairs by adding one lattice step to the offsets of the edges
/// crossed by the shortest path between them (Dijkstra over the triangles; QuadriFlow solves
/// the same pairing as one min-cost flow), then the lattice points are solved again, in one
/// sparse least-squares solve, to follow the changed offsets: where the lattice cannot keep
/// one spacing (a torus's inner circle is shorter than its outer one) it stretches instead of
/// breaking. Taken only where the cross field has no singularity of its own and every charge
/// is paired off; round a field singularity the offsets cannot all agree, and on the sphere
/// and ten shared meshes no extraction came out better for the step (docs/quad-meshing.md).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "kerfab/core/mesh.h"
#include "kerfab/quads/fields.h"

namespace kerfab::quads {

/// The integer lattice of the remeshed triangles: per undirected edge (a < b) the quarter
/// turns k from a's cross to b's and the offset t from a's lattice point to b's in a's axes.
/// Coordinates in b's axes c_b become R^-k c_b in a's; t seen from b is -R^k t.
class IntegerLattice {
 public:
  /// The offsets as the position field \p pos gives them (lattice_offset per edge).
  IntegerLattice(const Surface& s, const std::vector<Vec3>& cross, const std::vector<Vec3>& pos,
                 double spacing);

  /// Coordinates turned by m quarter turns: R^m (x, y), R (x, y) = (-y, x).
  static Eigen::Vector2i rotate(const Eigen::Vector2i& c, int m) {
    switch (((m % 4) + 4) % 4) {
      case 1:
        return {-c.y(), c.x()};
      case 2:
        return {-c.x(), -c.y()};
      case 3:
        return {c.y(), -c.x()};
      default:
        return c;
    }
  }

  int edge(int a, int b) const { return index_.at(key(std::min(a, b), std::max(a, b))); }
  bool has(int a, int b) const { return index_.count(key(std::min(a, b), std::max(a, b))) > 0; }
  /// \p gone merges into \p keep (an edge between them): each of gone's edges to a vertex in
  /// \p neighbours that keep has no edge to becomes keep's, through the edge keep -> gone.
  void merge(int keep, int gone, const std::vector<int>& neighbours);
  /// Quarter turns from x's cross to y's.
  int turns(int x, int y) const {
    const auto& e = edges_[edge(x, y)];
    return x == e.a ? e.k : -e.k;
  }
  /// Offset from x's lattice point to y's, in x's axes.
  Eigen::Vector2i offset(int x, int y) const {
    const auto& e = edges_[edge(x, y)];
    return x == e.a ? e.t : Eigen::Vector2i(-rotate(e.t, e.k));
  }
  /// Adds \p d (in x's axes) to the offset from x to y.
  void add(int x, int y, const Eigen::Vector2i& d) {
    auto& e = edges_[edge(x, y)];
    e.t += x == e.a ? d : Eigen::Vector2i(-rotate(d, -e.k));
  }
  /// How far (in cells, squared) the offset x -> y plus \p d (in x's axes) is from the
  /// continuous way between their lattices, against today's offset: 0 where the lattices
  /// meet halfway, 1 for a step across an edge where they agree.
  double cost(int x, int y, const Eigen::Vector2i& d) const {
    const auto& e = edges_[edge(x, y)];
    const Eigen::Vector2i da =
        x == e.a ? d : Eigen::Vector2i(-rotate(d, -e.k));  // the change in a's axes
    const Eigen::Vector2d rest = (e.t0 - e.t).cast<double>() + e.misfit;
    return (rest - da.cast<double>()).squaredNorm() - rest.squaredNorm();
  }
  /// Coordinates in y's axes seen in x's (x, y neighbours).
  Eigen::Vector2i to(int x, int y, const Eigen::Vector2i& c) const {
    return rotate(c, -turns(x, y));
  }

  /// Round triangle t: whether the cross turns, and the offsets' sum in its first corner's axes.
  bool singular(const std::array<int, 3>& t) const {
    return ((turns(t[0], t[1]) + turns(t[1], t[2]) + turns(t[2], t[0])) % 4 + 4) % 4 != 0;
  }
  Eigen::Vector2i curl(const std::array<int, 3>& t) const {
    return offset(t[0], t[1]) +
           to(t[0], t[1], offset(t[1], t[2]) + to(t[1], t[2], offset(t[2], t[0])));
  }
  /// Coordinates in corner v's axes seen in the triangle's first corner's (along its edges
  /// t[0] -> t[1] -> t[2]).
  Eigen::Vector2i to_first(const std::array<int, 3>& t, int v, const Eigen::Vector2i& c) const {
    if (v == t[0]) return c;
    if (v == t[1]) return to(t[0], t[1], c);
    return to(t[0], t[1], to(t[1], t[2], c));
  }
  /// The inverse of to_first.
  Eigen::Vector2i from_first(const std::array<int, 3>& t, int v, const Eigen::Vector2i& c) const {
    if (v == t[0]) return c;
    if (v == t[1]) return to(t[1], t[0], c);
    return to(t[2], t[1], to(t[1], t[0], c));
  }

  struct Edge {
    int a, b, k;
    Eigen::Vector2i t;
    Eigen::Vector2d misfit;  ///< in a's axes, for the offset as first measured
    Eigen::Vector2i t0;      ///< the offset as first measured
  };
  const std::vector<Edge>& edges() const { return edges_; }

 private:
  static std::int64_t key(int a, int b) { return (static_cast<std::int64_t>(a) << 32) | b; }
  std::vector<Edge> edges_;
  std::unordered_map<std::int64_t, int> index_;
};

struct DislocationResult {
  /// Per vertex its lattice point: solved to follow the offsets where the step was applied
  /// (then not on a lattice of one spacing where it had to stretch), else as given.
  std::vector<Vec3> positions;
  bool applied = false;  ///< every dislocation was paired off
  /// When applied: the offsets without dislocations, for extraction to use as they are
  /// (offsets measured again from the positions would differ where the lattice stretched).
  std::optional<IntegerLattice> lattice;
  /// When applied: each solved point moved to the lattice point (of one spacing) nearest its
  /// vertex, and whether the offsets measured from these have no dislocation either.
  std::vector<Vec3> rounded;
  bool rounded_clean = false;
  int orientation_singular = 0;  ///< triangles round which the cross field turns
  int charges_before = 0;        ///< unit lattice charges (dislocations) before the step
  int charges_after = 0;         ///< in the positions returned
};

/// \p features: edges the lattice should keep (sharp or border); paths cross them only at a
/// high cost. \p max_path: no path crosses more edges than this [-]; the cheapest is taken
/// (a step across an edge where the two lattices agree costs 1, where they meet halfway 0).
DislocationResult remove_dislocations(const Surface& surface, const std::vector<Vec3>& cross,
                                      const std::vector<Vec3>& positions, double spacing,
                                      const std::vector<std::array<int, 2>>& features,
                                      int max_path);

}  // namespace kerfab::quads

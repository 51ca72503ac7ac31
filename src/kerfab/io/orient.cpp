#include "kerfab/io/orient.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "kerfab/core/errors.h"

namespace kerfab {
namespace {

/// One face's use of an edge: the face, and whether it walks the edge from its lower vertex.
struct Use {
  int face = -1;
  bool up = false;
};

}  // namespace

OrientedFaces orient_consistently(const std::vector<Vec3>& points,
                                  std::vector<std::vector<int>> faces, const std::string& name) {
  const int n = static_cast<int>(faces.size());
  std::unordered_map<std::uint64_t, std::vector<Use>> uses;
  uses.reserve(faces.size() * 2);
  int crowded = 0;  // edges on more than two faces
  for (int f = 0; f < n; ++f) {
    const auto& c = faces[f];
    for (std::size_t k = 0; k < c.size(); ++k) {
      const int a = c[k], b = c[(k + 1) % c.size()];
      auto& list = uses[undirected_edge_key(a, b)];
      list.push_back({f, a < b});
      if (list.size() == 3) ++crowded;
    }
  }
  if (crowded > 0)
    throw InvalidInput("mesh is not manifold (" + std::to_string(crowded) +
                       " edge(s) shared by more than two faces): " + name);

  // turn[f]: whether face f is reversed; -1 not reached yet.
  std::vector<int> turn(n, -1);
  OrientedFaces out;
  out.order.reserve(faces.size());
  for (int seed = 0; seed < n; ++seed) {
    if (turn[seed] >= 0) continue;
    ++out.components;
    const std::size_t first = out.order.size();
    turn[seed] = 0;
    out.order.push_back(seed);
    bool closed = true;
    for (std::size_t at = first; at < out.order.size(); ++at) {
      const int f = out.order[at];
      const auto& c = faces[f];
      for (std::size_t k = 0; k < c.size(); ++k) {
        const int a = c[k], b = c[(k + 1) % c.size()];
        const auto& list = uses[undirected_edge_key(a, b)];
        if (list.size() < 2) {
          closed = false;
          continue;
        }
        const Use& mine = list[0].face == f ? list[0] : list[1];
        const Use& other = list[0].face == f ? list[1] : list[0];
        if (other.face == f) continue;  // a face round the same edge twice: nothing to match
        // As walked: mine.up ^ turn[f]; the other face must walk it the other way.
        const int want = (mine.up ^ (turn[f] == 1) ^ other.up) ? 0 : 1;
        if (turn[other.face] < 0) {
          turn[other.face] = want;
          out.order.push_back(other.face);
        } else if (turn[other.face] != want) {
          throw InvalidInput(
              "mesh is not orientable (a one-sided surface, like a Moebius strip: its faces "
              "cannot all turn the same way, so it has no inside and outside to cut): " +
              name);
        }
      }
    }
    // The piece's way round: outwards where it is closed, else as most of its faces came.
    int reversed = 0;
    double volume = 0;
    for (std::size_t at = first; at < out.order.size(); ++at) {
      const int f = out.order[at];
      reversed += turn[f];
      const auto& c = faces[f];
      double v = 0;
      for (std::size_t k = 1; k + 1 < c.size(); ++k)
        v += points[c[0]].dot(points[c[k]].cross(points[c[k + 1]])) / 6;
      volume += turn[f] ? -v : v;
    }
    const int count = static_cast<int>(out.order.size() - first);
    const bool flip_all = closed ? volume < 0 : 2 * reversed > count;
    if (flip_all)
      for (std::size_t at = first; at < out.order.size(); ++at) turn[out.order[at]] ^= 1;
  }
  for (int f = 0; f < n; ++f)
    if (turn[f] == 1) {
      std::reverse(faces[f].begin() + 1, faces[f].end());  // the first corner stays first
      ++out.turned;
    }
  out.faces = std::move(faces);
  return out;
}

}  // namespace kerfab

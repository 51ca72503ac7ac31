#include "kerfab/joints/corners.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <vector>

namespace kerfab {
namespace {

/// Piece ends closer than this are one corner [mm] (they come from the same strip vertex).
constexpr double kSameCorner = 1e-4;

bool has_joint(const BorderJoint& b) { return b.teeth > 0 || b.glue > 0; }

/// Distance along border \p b from its end \p end (0: its common end) to its nearest tooth, tab
/// or glue tab [mm].
double nearest_joint(const BorderJoint& b, int end) {
  double d = std::numeric_limits<double>::infinity();
  for (const JointInterval& in : b.intervals)
    if (in.owner >= 0) d = std::min(d, end == 0 ? in.s0 : b.length - in.s1);
  return std::max(d, 0.0);
}

/// A shortest chain of parts from \p from to \p to over \p links (pairs of parts), both ends
/// included; empty where there is none.
std::vector<int> chain_between(int from, int to, const std::vector<std::array<int, 2>>& links) {
  std::map<int, int> previous{{from, from}};
  std::deque<int> queue{from};
  while (!queue.empty()) {
    const int p = queue.front();
    queue.pop_front();
    if (p == to) break;
    for (const auto& l : links)
      for (int k = 0; k < 2; ++k)
        if (l[k] == p && !previous.contains(l[1 - k])) {
          previous[l[1 - k]] = p;
          queue.push_back(l[1 - k]);
        }
  }
  std::vector<int> chain;
  if (!previous.contains(to)) return chain;
  for (int p = to; p != from; p = previous.at(p)) chain.insert(chain.begin(), p);
  chain.insert(chain.begin(), from);
  return chain;
}

}  // namespace

void join_stubs_at_corners(Joints& joints, const Strips& strips, const border::Pieces& pieces,
                           double max_length) {
  const int n = static_cast<int>(joints.borders.size());
  std::vector<std::array<Vec3, 2>> ends;
  ends.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) ends.push_back(border::piece_ends(strips, pieces, i));
  for (int i = 0; i < n; ++i) {
    BorderJoint& stub = joints.borders[i];
    stub.joined_through.clear();
    stub.joined_through_far.clear();
    if (has_joint(stub) || stub.length > 2 * max_length || stub.patches[0] == stub.patches[1])
      continue;
    std::array<std::vector<int>, 2> chains;  // at each of its ends
    for (int end = 0; end < 2; ++end) {
      // The borders with a joint that end at this corner link the parts around it.
      std::vector<std::array<int, 2>> links;
      for (int k = 0; k < n; ++k) {
        const BorderJoint& b = joints.borders[k];
        if (k == i || !has_joint(b) || b.patches[0] == b.patches[1]) continue;
        for (int at = 0; at < 2; ++at)
          if ((ends[k][at] - ends[i][end]).norm() < kSameCorner &&
              nearest_joint(b, at) <= max_length) {
            links.push_back(b.patches);
            break;
          }
      }
      chains[end] = chain_between(stub.patches[0], stub.patches[1], links);
    }
    if (stub.length <= max_length) {
      // Held at one end: the shorter chain.
      const int end =
          chains[0].empty() || (!chains[1].empty() && chains[1].size() < chains[0].size());
      stub.joined_through = std::move(chains[end]);
    } else if (!chains[0].empty() && !chains[1].empty()) {
      // Held at both ends: no point of it farther than max_length from either.
      stub.joined_through = std::move(chains[0]);
      stub.joined_through_far = std::move(chains[1]);
    }
  }
  joints.borders_without_joint = joints.stubs_joined_at_corners = 0;
  for (const BorderJoint& b : joints.borders) {
    const std::string kind = b.kind();
    joints.borders_without_joint += kind == "none" ? 1 : 0;
    joints.stubs_joined_at_corners += kind == "corner" ? 1 : 0;
  }
}

}  // namespace kerfab

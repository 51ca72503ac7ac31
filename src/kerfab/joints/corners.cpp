#include "kerfab/joints/corners.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <optional>
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

/// The ends of the first \p n pieces, in 3D.
std::vector<std::array<Vec3, 2>> all_piece_ends(const Strips& strips, const border::Pieces& pieces,
                                                int n) {
  std::vector<std::array<Vec3, 2>> ends;
  ends.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) ends.push_back(border::piece_ends(strips, pieces, i));
  return ends;
}

/// A border with a joint that ends at or near a corner: which end, whether at the corner itself,
/// and how far its nearest joint is from the corner: the gap between its end and the corner
/// (straight, in 3D) plus the way along it from that end to the joint [mm].
struct Link {
  CornerEnd at;
  bool at_corner = true;
  double nearest = 0;
};

/// The borders with a joint (two parts, not \p i) that end at end \p end of border \p i, or
/// within \p reach of it [mm]: they link the parts around that corner. (horse_quad at 250 mm: a
/// 0.7 mm stub whose two parts share a border 2 mm away, across a part left out, with a tooth
/// 1.5 mm along it: no border ended at the stub's corners, and it was counted without a joint.)
std::vector<Link> links_at(const Joints& joints, const std::vector<std::array<Vec3, 2>>& ends,
                           int i, int end, double reach) {
  std::vector<Link> links;
  for (int k = 0; k < static_cast<int>(joints.borders.size()); ++k) {
    const BorderJoint& b = joints.borders[k];
    if (k == i || !has_joint(b) || b.patches[0] == b.patches[1]) continue;
    std::optional<Link> best;
    for (int at = 0; at < 2; ++at) {
      const double gap = (ends[k][at] - ends[i][end]).norm();
      if (gap < kSameCorner) {
        best = Link{{k, at}, true, nearest_joint(b, at)};
        break;
      }
      if (gap > reach) continue;
      const Link near{{k, at}, false, gap + nearest_joint(b, at)};
      if (!best || near.nearest < best->nearest) best = near;
    }
    if (best) links.push_back(*best);
  }
  return links;
}

/// Of the chains of parts from \p from to \p to over \p links, one with the fewest links whose
/// joint is farther than \p max_length from the corner: those links (empty where every link of
/// it is near); nullopt where there is no chain.
std::optional<std::vector<CornerEnd>> fewest_far(int from, int to, const std::vector<Link>& links,
                                                 const std::vector<BorderJoint>& borders,
                                                 double max_length) {
  // 0-1 breadth first: a far link costs 1, a near one 0.
  std::map<int, std::pair<int, int>> best{{from, {0, -1}}};  // part: cost, link that reached it
  std::deque<int> queue{from};
  while (!queue.empty()) {
    const int p = queue.front();
    queue.pop_front();
    for (int li = 0; li < static_cast<int>(links.size()); ++li) {
      const auto& parts = borders[links[li].at.border].patches;
      for (int k = 0; k < 2; ++k) {
        if (parts[k] != p) continue;
        const int far = links[li].nearest > max_length ? 1 : 0, q = parts[1 - k];
        const int cost = best.at(p).first + far;
        if (best.contains(q) && best.at(q).first <= cost) continue;
        best[q] = {cost, li};
        far ? queue.push_back(q) : queue.push_front(q);
      }
    }
  }
  if (!best.contains(to)) return std::nullopt;
  std::vector<CornerEnd> wanted;
  for (int p = to; p != from;) {
    const Link& l = links[best.at(p).second];
    if (l.nearest > max_length) wanted.push_back(l.at);
    const auto& parts = borders[l.at.border].patches;
    p = parts[0] == p ? parts[1] : parts[0];
  }
  return wanted;
}

}  // namespace

void join_stubs_at_corners(Joints& joints, const Strips& strips, const border::Pieces& pieces,
                           double max_length) {
  const int n = static_cast<int>(joints.borders.size());
  const std::vector<std::array<Vec3, 2>> ends = all_piece_ends(strips, pieces, n);
  for (int i = 0; i < n; ++i) {
    BorderJoint& stub = joints.borders[i];
    stub.joined_through.clear();
    stub.joined_through_far.clear();
    if (has_joint(stub) || stub.length > 2 * max_length || stub.patches[0] == stub.patches[1])
      continue;
    std::array<std::vector<int>, 2> chains;  // at each of its ends
    for (int end = 0; end < 2; ++end) {
      std::vector<std::array<int, 2>> links;
      for (const Link& l : links_at(joints, ends, i, end, max_length))
        if (l.nearest <= max_length) links.push_back(joints.borders[l.at.border].patches);
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

std::vector<std::vector<CornerEnd>> joints_wanted_at_corners(const Joints& joints,
                                                             const Strips& strips,
                                                             const border::Pieces& pieces,
                                                             double max_length) {
  const int n = static_cast<int>(joints.borders.size());
  const std::vector<std::array<Vec3, 2>> ends = all_piece_ends(strips, pieces, n);
  std::vector<std::vector<CornerEnd>> wanted;
  for (int i = 0; i < n; ++i) {
    const BorderJoint& b = joints.borders[i];
    if (has_joint(b) || b.length > 2 * max_length || b.patches[0] == b.patches[1]) continue;
    std::array<std::optional<std::vector<CornerEnd>>, 2> at;
    for (int end = 0; end < 2; ++end) {
      // A joint can be given within reach of the corner only on a border that ends there.
      std::vector<Link> links = links_at(joints, ends, i, end, max_length);
      std::erase_if(links, [&](const Link& l) { return !l.at_corner && l.nearest > max_length; });
      at[end] = fewest_far(b.patches[0], b.patches[1], links, joints.borders, max_length);
    }
    std::vector<CornerEnd> want;
    if (b.length <= max_length) {
      // Held at one end: the one that needs fewest.
      const std::optional<std::vector<CornerEnd>>* pick = nullptr;
      for (const auto& a : at)
        if (a && (!pick || a->size() < (*pick)->size())) pick = &a;
      if (!pick || (*pick)->empty()) continue;
      want = **pick;
    } else {
      // Held at both ends.
      if (!at[0] || !at[1] || (at[0]->empty() && at[1]->empty())) continue;
      want = *at[0];
      want.insert(want.end(), at[1]->begin(), at[1]->end());
    }
    wanted.push_back(std::move(want));
  }
  return wanted;
}

}  // namespace kerfab

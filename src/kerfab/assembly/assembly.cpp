#include "kerfab/assembly/assembly.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "kerfab/core/errors.h"

namespace kerfab {

std::vector<std::vector<PartContact>> part_contacts(const Joints& joints, int parts) {
  std::vector<std::map<int, PartContact>> acc(parts);
  for (const BorderJoint& b : joints.borders) {
    const int p = b.patches[0], q = b.patches[1];
    if (p == q || p < 0 || q < 0 || p >= parts || q >= parts) continue;
    double toothed = 0;
    for (const JointInterval& i : b.intervals)
      if (i.owner >= 0) toothed += i.s1 - i.s0;
    toothed = std::clamp(toothed, 0.0, b.length);
    for (const auto& [a, c] : {std::pair{p, q}, std::pair{q, p}}) {
      PartContact& k = acc[a][c];
      k.part = c;
      k.length += b.length;
      k.toothed += toothed;
    }
  }
  std::vector<std::vector<PartContact>> out(parts);
  for (int p = 0; p < parts; ++p) {
    for (const auto& [q, c] : acc[p]) out[p].push_back(c);
    std::stable_sort(out[p].begin(), out[p].end(), [](const PartContact& a, const PartContact& b) {
      return a.length > b.length;
    });
  }
  return out;
}

std::vector<double> part_perimeters(const Strips& strips) {
  std::vector<double> out;
  for (const Patch& patch : strips.patches) {
    double length = 0;
    const std::vector<int> local = patch.local_vertices();  // facets too
    for (const OutlineEdge& e : patch.outline())
      length += (strips.vertices[local[e.v[1]]] - strips.vertices[local[e.v[0]]]).norm();
    out.push_back(length);
  }
  return out;
}

AssemblyPlan plan_assembly(const Joints& joints, const std::vector<PartShape>& shapes,
                           const AssemblyOptions& options) {
  if (!(options.plain_weight >= 0 && options.plain_weight <= 1))
    throw InvalidInput("assembly: plain_weight must be in [0, 1], got " +
                       std::to_string(options.plain_weight));
  const int n = static_cast<int>(joints.parts.size());
  if (static_cast<int>(shapes.size()) != n)
    throw InvalidInput("assembly: " + std::to_string(shapes.size()) + " part shapes for " +
                       std::to_string(n) + " parts");
  std::vector<char> rimmed(n, 0);  // no free border: once its neighbours are placed, a hole
  std::vector<double> shared(n, 0);
  for (const BorderJoint& b : joints.borders)
    for (int side : {0, 1})
      if (b.patches[side] >= 0 && b.patches[side] < n) shared[b.patches[side]] += b.length;
  for (int p = 0; p < n; ++p) rimmed[p] = shared[p] >= 0.98 * shapes[p].perimeter - 1.0 ? 1 : 0;
  AssemblyPlan plan;
  plan.contacts = part_contacts(joints, n);
  auto weight = [&](const PartContact& c) {
    return c.toothed + options.plain_weight * (c.length - c.toothed);
  };
  std::vector<char> placed(n, 0);
  std::vector<double> hold(n, 0);     // weighted border to the placed parts
  std::vector<int> waiting(n, 0);     // neighbours not yet placed
  for (int p = 0; p < n; ++p) waiting[p] = static_cast<int>(plan.contacts[p].size());
  // Some neighbour of p is placed.
  auto touches = [&](int p) { return waiting[p] < static_cast<int>(plan.contacts[p].size()); };
  // Among the parts touching the placed ones: one that leaves no hole first, then the best held,
  // then the larger, then the lower number.
  auto better = [&](int a, int b) {
    const bool open_a = waiting[a] > 0 || !rimmed[a], open_b = waiting[b] > 0 || !rimmed[b];
    if (open_a != open_b) return open_a;
    if (hold[a] != hold[b]) return hold[a] > hold[b];
    if (shapes[a].area != shapes[b].area) return shapes[a].area > shapes[b].area;
    return a < b;
  };
  for (int step = 0; step < n; ++step) {
    int next = -1;
    bool touching = false;
    for (int p = 0; p < n; ++p)
      if (!placed[p] && touches(p) && (!touching || better(p, next))) {
        next = p;
        touching = true;
      }
    if (!touching)  // a new piece: the largest part left
      for (int p = 0; p < n; ++p)
        if (!placed[p] && (next < 0 || shapes[p].area > shapes[next].area)) next = p;
    AssemblyStep s;
    s.part = next;
    s.new_piece = !touching;
    s.closing = touching && waiting[next] == 0 && rimmed[next];
    for (const PartContact& c : plan.contacts[next])
      if (placed[c.part]) {
        s.joins.push_back(c);
        s.held += c.length;
      }
    plan.steps.push_back(std::move(s));
    if (!touching) ++plan.pieces;
    placed[next] = 1;
    for (const PartContact& c : plan.contacts[next]) {
      hold[c.part] += weight(c);
      --waiting[c.part];
    }
  }
  return plan;
}

}  // namespace kerfab

#include "kerfab/core/parallel.h"
#include "kerfab/layout/layout.h"

namespace kerfab {

std::vector<std::map<int, double>> part_neighbours(const Joints& joints, int parts) {
  std::vector<std::map<int, double>> out(parts);
  for (const BorderJoint& b : joints.borders) {
    out[b.patches[0]][b.patches[1]] += b.length;
    if (b.patches[1] != b.patches[0]) out[b.patches[1]][b.patches[0]] += b.length;
  }
  return out;
}

LayoutResult lay_out_parts(const Strips& strips, const Flattening& flat, const Joints& joints,
                           const KerfResult& kerf, const LayoutOptions& options) {
  std::vector<Polygon2> outlines;
  for (const auto& part : joints.parts) outlines.push_back(part.cut);
  LayoutResult out = nest_parts(outlines, options);
  const int parts = static_cast<int>(strips.patches.size());
  // Each part's labels look at that part alone: all parts at once, on every core.
  out.labels.resize(parts);
  out.engravings.resize(parts);
  for_each_index(parts, hardware_threads(), [&](int p) {
    // Labels go on the part itself, not on its glue tabs (hidden once glued).
    std::vector<Polygon2> tabs;
    for (const JointSpan& sp : joints.parts[p].spans)
      if (sp.kind == JointKind::kGlue && sp.region.size() >= 3) {
        Polygon2 t = sp.region;
        make_counter_clockwise(t);
        tabs.push_back(std::move(t));
      }
    Polygon2 outline = joints.parts[p].designed;
    if (!tabs.empty())
      if (Polygon2 body = largest_polygon(polygon_difference({outline}, polygon_offset(tabs, 0.01)));
          !body.empty())
        outline = std::move(body);
    out.labels[p] = part_label(strips, flat, kerf, outline, p);
    out.engravings[p] = border_labels(strips, flat, kerf, joints, outline, p, out.labels[p]);
    if (out.labels[p]) out.engravings[p].insert(out.engravings[p].begin(), *out.labels[p]);
  });
  out.neighbours = part_neighbours(joints, parts);
  for (int p = 0; p < parts; ++p) {
    out.border_labels_wanted +=
        static_cast<int>(out.neighbours[p].size() - out.neighbours[p].count(p));
    for (const auto& label : out.engravings[p])
      out.border_labels_placed += label.text[0] == '-' ? 1 : 0;
  }
  return out;
}

}  // namespace kerfab

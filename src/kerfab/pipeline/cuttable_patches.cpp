#include "kerfab/pipeline/cuttable_patches.h"

namespace kerfab {

CuttablePatches flatten_cuttable(const Strips& strips, const FlattenOptions& options,
                                 const LayoutOptions& usable) {
  CuttablePatches out{strips, flatten_patches(strips, options)};
  auto oversize = [&](std::size_t p) {
    return !fits_sheet(flat_outline(out.strips, out.flattening, static_cast<int>(p)), usable);
  };
  for (int round = 0; round < 12; ++round) {
    Strips split = out.strips;
    int splits = 0;
    for (std::size_t p = 0; p < out.flattening.patches.size(); ++p) {
      const int quads = static_cast<int>(split.patches[p].quads.size());
      // A facet is flat by construction: its outline is what the resolver chose (never split).
      if (quads < 2 || split.patches[p].flat) continue;
      const PatchFlattening& flat = out.flattening.patches[p];
      if (!flat.outline_simple) {
        ++out.overlap_splits;
      } else if (flat.inverted_quads > 0 || flat.max_angle_error >= options.max_angle_error) {
        ++out.distortion_splits;
      } else if (oversize(p)) {
        ++out.oversize_splits;
      } else {
        continue;
      }
      split = split_patch(split, static_cast<int>(p), quads / 2);
      ++splits;
    }
    if (splits == 0) break;
    out.strips = std::move(split);
    out.flattening = flatten_patches(out.strips, options);
  }
  return out;
}

SurfaceDistance flat_metric_deformation(const CuttablePatches& patches, double spacing) {
  return surface_distance(patch_triangles(patches.strips, patches.flattening, false),
                          patch_triangles(patches.strips, patches.flattening, true),
                          {.sample_spacing = spacing});
}

}  // namespace kerfab

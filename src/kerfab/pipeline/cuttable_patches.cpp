#include "kerfab/pipeline/cuttable_patches.h"

#include <algorithm>

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

std::vector<int> omit_patches(CuttablePatches& patches, const std::set<int>& quads) {
  constexpr int kNone = -1;
  Strips& s = patches.strips;
  std::vector<int> left_out;
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    const auto all = s.patches[p].all_quads();
    if (!all.empty() &&
        std::all_of(all.begin(), all.end(), [&](int q) { return quads.count(q) > 0; }))
      left_out.push_back(static_cast<int>(p));
  }
  if (left_out.empty()) return left_out;
  std::vector<int> renumber(s.patches.size(), kNone);
  std::vector<Patch> kept;
  std::vector<PatchFlattening> kept_flat;
  for (std::size_t p = 0, k = 0; p < s.patches.size(); ++p) {
    if (k < left_out.size() && left_out[k] == static_cast<int>(p)) {
      ++k;
      continue;
    }
    renumber[p] = static_cast<int>(kept.size());
    kept.push_back(std::move(s.patches[p]));
    kept_flat.push_back(std::move(patches.flattening.patches[p]));
  }
  s.patches = std::move(kept);
  patches.flattening.patches = std::move(kept_flat);
  for (int& p : s.quad_patch)
    if (p != kNone) p = renumber[p];
  // Their sub-quads go: every consumer of the strips sees only the patches' own.
  std::vector<int> face_id(s.faces.size(), kNone);
  std::vector<std::array<int, 4>> faces;
  std::vector<int> face_quad, face_patch;
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const int p = s.face_patch[f] == kNone ? kNone : renumber[s.face_patch[f]];
    if (p == kNone) continue;
    face_id[f] = static_cast<int>(faces.size());
    faces.push_back(s.faces[f]);
    face_quad.push_back(s.face_quad[f]);
    face_patch.push_back(p);
  }
  s.faces = std::move(faces);
  s.face_quad = std::move(face_quad);
  s.face_patch = std::move(face_patch);
  for (Patch& patch : s.patches) {
    for (int& f : patch.faces) f = face_id[f];
    for (PatchRow& row : patch.more_rows)
      for (int& f : row.faces) f = face_id[f];
    for (OutlineEdge& e : patch.flat_outline)
      if (e.sub_quad != kNone) e.sub_quad = face_id[e.sub_quad];
  }
  summarise_flattening(s, patches.flattening);
  return left_out;
}

SurfaceDistance flat_metric_deformation(const CuttablePatches& patches, double spacing) {
  // Within a budget of samples, as the quality stage's: a strip whose deformation ran off (a
  // cup with 3 mm walls at its own size: a part's corners 40 m away) would need more than the
  // distance's 50 million and failed the run after its resolve stage.
  constexpr long kSampleBudget = 10'000'000;
  return surface_distance(patch_triangles(patches.strips, patches.flattening, false),
                          patch_triangles(patches.strips, patches.flattening, true),
                          {.sample_spacing = spacing, .max_samples = kSampleBudget});
}

}  // namespace kerfab

#pragma once
/// \file The flattening step of the pipeline: flatten every patch, and split a patch whose flat
/// outline crosses itself or whose part would not fit the sheet, until every part can be cut.
#include <optional>
#include <set>

#include "kerfab/eval/surface_distance.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/layout/layout.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

struct CuttablePatches {
  Strips strips;  ///< the strips with every split applied (patch ids as used from here on)
  Flattening flattening;
  int overlap_splits = 0;     ///< patches split because their flat outline crossed itself
  int distortion_splits = 0;  ///< strips split because they flattened with an inverted quad
                              ///< or an angle error of FlattenOptions::max_angle_error or more
  int oversize_splits = 0;    ///< patches split because their part did not fit the sheet
  /// 3D strips against their deformation to the flat metric (flat_metric_deformation) [mm].
  std::optional<SurfaceDistance> deformation;
};

/// Flattens the patches of \p strips; a strip whose outline crosses itself, that flattens with
/// an inverted quad or too large an angle error, or that does not fit
/// \p usable (the sheet less its margins, with room for teeth), is split at the quad boundary
/// nearest its middle and flattened again, for up to 12 rounds. \throw InvalidInput options
/// out of range.
CuttablePatches flatten_cuttable(const Strips& strips, const FlattenOptions& options,
                                 const LayoutOptions& usable);

/// Leaves out every patch of \p patches whose quads all lie in \p quads (coarse quad ids): its
/// sub-quads are removed and its quads belong to no patch (-1), the other patches and sub-quads
/// are renumbered in order, and the borders are measured again (a neighbour's side where it was is
/// a free edge). Returns the old ids of the patches left out.
std::vector<int> omit_patches(CuttablePatches& patches, const std::set<int>& quads);

/// How far the 3D strips move when deformed to the flat metric (the evaluation behind
/// CuttablePatches::deformation), sampled \p spacing apart [mm]. Measured once per run, on the
/// patches as cut: the resolve stage's trial builds skip it.
SurfaceDistance flat_metric_deformation(const CuttablePatches& patches, double spacing);

}  // namespace kerfab

#pragma once
/// \file Distances between two triangulated surfaces: sampled two-sided Hausdorff distance and
/// mean distance (the paper's approximation-quality measures, Table 1).
#include "kerfab/core/mesh.h"

namespace kerfab {

struct SurfaceDistanceOptions {
  double sample_spacing = 1.0;  ///< largest distance between samples on either surface [mm], > 0
  /// > 0: where the spacing would need more samples than this, it is widened until they fit
  /// (SurfaceDistance::spacing says by how much); 0: such a spacing is refused.
  long max_samples = 0;
};

struct SurfaceDistance {
  double a_to_b_max = 0;   ///< max over samples x of A of dist(x, B) [mm]
  double a_to_b_mean = 0;  ///< area-weighted mean of dist(x, B) over A [mm]
  double b_to_a_max = 0;
  double b_to_a_mean = 0;
  double hausdorff = 0;  ///< max of the two maxima [mm]
  double mean = 0;       ///< mean of the two means (symmetric mean distance) [mm]
  long samples = 0;      ///< distance queries made
  double spacing = 0;    ///< the sample spacing used [mm] (the requested one unless widened)
  /// No point of either surface is farther than the spacing from a sample (every sub-triangle's
  /// edges are at most that long) and a distance function moves by at most the distance moved,
  /// so the true Hausdorff distance lies in [hausdorff, hausdorff + spacing].
  double hausdorff_upper_bound() const { return hausdorff + spacing; }
};

/// Samples each triangle on a barycentric grid fine enough for \p options.sample_spacing
/// (vertices, grid points and sub-triangle centroids, the centroids weighted by area for the
/// means) and measures each sample's distance to the other surface. Zero-area triangles are
/// skipped. \throw InvalidInput either mesh has no triangle of positive area, or the spacing
/// would need more than 50 million samples (and max_samples is 0).
SurfaceDistance surface_distance(const TriangleMesh& a, const TriangleMesh& b,
                                 const SurfaceDistanceOptions& options);

}  // namespace kerfab

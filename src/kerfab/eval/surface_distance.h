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
  Vec3 a_to_b_at{0, 0, 0};  ///< the point of A at distance a_to_b_max from B [mm]
  Vec3 b_to_a_at{0, 0, 0};  ///< the point of B at distance b_to_a_max from A [mm]
  double hausdorff = 0;     ///< max of the two maxima [mm]
  /// Where the Hausdorff distance is reached: a_to_b_at or b_to_a_at, whichever is farther
  /// (A's where they tie).
  bool hausdorff_on_a = true;
  const Vec3& hausdorff_at() const { return hausdorff_on_a ? a_to_b_at : b_to_a_at; }
  double mean = 0;     ///< mean of the two means (symmetric mean distance) [mm]
  long samples = 0;    ///< distance queries made
  double spacing = 0;  ///< the means' sample spacing [mm] (the requested one unless widened)
  /// The true Hausdorff distance lies in [hausdorff, hausdorff + hausdorff_gap]: the maxima
  /// are found by branch and bound until no triangle can hold a distance more than a quarter
  /// of the spacing above the largest one found (the distance to a surface moves by at most
  /// the distance moved) [mm].
  double hausdorff_gap = 0;
  double hausdorff_upper_bound() const { return hausdorff + hausdorff_gap; }
  /// How far the mean may be off: its difference from the same mean sampled twice as coarsely
  /// (the centroid rule's error falls with the square of the spacing) [mm].
  double mean_error_estimate = 0;
};

/// The largest distances each way by branch and bound over the triangles (to within a quarter
/// of \p options.sample_spacing, stated as SurfaceDistance::hausdorff_gap), the mean distances
/// from the centroids of each triangle cut into cells no wider than the spacing (each
/// weighted by its area). Zero-area triangles are skipped. \throw InvalidInput either mesh has
/// no triangle of positive area, or the spacing would need more than 50 million samples (and
/// max_samples is 0).
SurfaceDistance surface_distance(const TriangleMesh& a, const TriangleMesh& b,
                                 const SurfaceDistanceOptions& options);

}  // namespace kerfab

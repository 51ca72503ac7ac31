#pragma once
/// \file Bending directions (paper Sec. 3.1): edge weights from the target, the integer program
/// that picks the bendable edges, and the per-quad classification that follows from it.
#include <optional>
#include <string>
#include <vector>

#include "kerfab/adapters/packing_program.h"
#include "kerfab/adapters/target_surface.h"
#include "kerfab/core/guidance.h"
#include "kerfab/core/mesh.h"

namespace kerfab {

/// The largest alignment bias c accepted: past it the edges' own weights only break ties [-].
constexpr double kMaxAlignment = 1000;

struct BendingOptions {
  double alignment = 0.3;     ///< c in w0 = c * max_e w_e, the alignment bias [-], 0..1000
  int edge_samples = 24;      ///< signed-distance samples per edge for its variance [-], >= 2;
                              ///< 24 keeps every weight within 1% (of the largest) of the
                              ///< value at 48 samples on spot (measured: 0.61%)
  double time_limit_s = 60;   ///< integer-program time limit [s], > 0
  double relative_gap = 0.0;  ///< accepted relative optimality gap [-], >= 0
  std::vector<EdgeGuidance> guidance;  ///< forced edges
};

/// How a quad may bend, following from its bendable edges.
enum class QuadKind {
  kBending,   ///< both edges of one opposite pair bendable: the bending pair; the others rule
  kOneSided,  ///< one edge of a pair bendable, its opposite stiff: the quad must twist
  kRigid,     ///< no bendable edge
};

std::string to_string(QuadKind kind);

struct QuadBending {
  QuadKind kind = QuadKind::kRigid;
  int axis = -1;  ///< 0: local edges 0 and 2 form the bending pair (see quad_edges); 1: edges
                  ///< 1 and 3; -1 for rigid quads
};

struct BendingResult {
  std::vector<double> variance;    ///< w_e per edge: variance of the signed distance, 0 below
                                   ///< (1e-6 * bbox diagonal)^2 [mm^2]
  double w0 = 0;                   ///< bias c * max w_e added to every weight (c * 1 mm^2 if
                                   ///< every w_e is 0) [mm^2]
  std::vector<char> bendable;      ///< per edge: 1 = bendable
  std::vector<QuadBending> quads;  ///< per face
  double objective = 0;            ///< sum over bendable edges of (w_e + w0) [mm^2]
  double bound = 0;                ///< proven upper bound on the objective [mm^2]
  PackingStatus status = PackingStatus::kStopped;
  double solve_seconds = 0;     ///< integer-program time, cut rounds included [s]
  int interior_edges = 0;       ///< edges with a face on both sides
  int aligned_edges = 0;        ///< interior edges whose two quads agree on bending direction
  double aligned_fraction = 0;  ///< aligned_edges / interior_edges (paper n_aligned/|E|)
  int bendable_count = 0;
  // How the program was solved (seams.h, odd_cycles.h).
  int odd_vertices = 0;               ///< interior odd-valence vertices (seam ends)
  int seam_edges = 0;                 ///< edges on the seams of the start selection
  bool seam_pairing_optimal = false;  ///< the seams pair the odd vertices at minimum length
  double start_objective = 0;         ///< objective of the seam start [mm^2]
  int ring_cuts = 0;                  ///< odd rings added as cuts
  int separated_cuts = 0;             ///< odd cycles separated from the relaxation
  int cut_rounds = 0;                 ///< separation rounds
  int slack_limits = 0;               ///< separated cycles left slack, not given to CBC
  double relaxation_bound = 0;        ///< relaxation optimum with all cuts [mm^2]
  double cut_seconds = 0;             ///< time for start, rings and separation [s]
};

/// Variance of the signed distance to the target along each straight quad edge, sampled at
/// \p samples midpoints of equal sub-segments [mm^2]. \pre samples >= 2.
std::vector<double> edge_variances(const PolyMesh& quads, const TargetSurface& target, int samples);

/// Classifies every quad from a per-edge bendable flag.
std::vector<QuadBending> classify_quads(const PolyMesh& quads, const std::vector<char>& bendable);

/// Counts the interior edges (first) and, of those, the aligned ones (second): both quads are
/// non-rigid and give the edge the same role, on the bending axis or on the ruling axis.
std::pair<int, int> count_aligned_edges(const PolyMesh& quads,
                                        const std::vector<QuadBending>& classes);

/// Chooses the bendable edges (paper Eq. 1 with bias w0 and the user's fixed edges).
/// \pre quads is all quads. \throw InvalidInput bad options or guidance that names no edge of
/// the mesh, or forces two consecutive edges of one quad bendable.
BendingResult choose_bending_edges(const PolyMesh& quads, const TargetSurface& target,
                                   const BendingOptions& options);

}  // namespace kerfab

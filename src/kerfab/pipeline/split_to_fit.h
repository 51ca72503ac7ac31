#pragma once
/// \file A sheet fewer by splitting long strips (after the layout): a long curved strip leaves
/// gaps no other part fills, and on a multi-sheet job the last sheet may hold only a few such
/// strips. Where the sheets used exceed the lower bounds and the parts could fill one sheet fewer
/// (their spaced area within kFullestSheet of it), the strips at least a given length are split
/// in two at the ruling nearest their middle (a strip border there: the two halves meet edge to
/// edge in the same bent sheet, joined like any border), and the parts are cut and nested again:
/// taken where that uses fewer sheets with no more critical regions, parts too small to handle,
/// borders without a joint or parts off the sheets. An attempt is built only where the parts'
/// paths, the strips cut in two in the plane (halves_in_plane) and the rings recut there
/// (ring_recut_in_plane), nest on fewer sheets: a judgement, not a proof (those pieces lack
/// the new border's joint, and nesting smaller parts can use more sheets), which on the jobs
/// measured (README, issue 18) skipped no attempt that saves a sheet.
#include <array>
#include <string>
#include <vector>

#include "kerfab/core/guidance.h"
#include "kerfab/input/prepare.h"
#include "kerfab/layout/layout.h"
#include "kerfab/pipeline/resolve.h"

namespace kerfab {

struct SplitToFitOptions {
  bool enabled = true;  ///< false: strips stay whole (--keep-strips-whole)
  /// Tried in turn: strips whose minimum rectangle's longer side is at least this fraction of
  /// the stock sheet's shorter side inside its margins are split [-], each in (0, 2]. Fewest
  /// splits first; the first that saves a sheet is kept, and the next fraction may save another.
  /// Each fraction is tried with rings (strips cut open from a closed loop) cut in two, then
  /// with rings only cut open at their middle instead.
  std::vector<double> fractions = {0.8, 0.6};
};

struct SplitToFitResult {
  bool tried = false;   ///< the job was one that could save a sheet (see why_not otherwise)
  std::string why_not;  ///< why nothing was tried, or why nothing was kept (for the report)
  int attempts = 0;     ///< builds cut and nested
  /// Attempts not built: the parts' laser paths, the strips to split cut in two in the plane
  /// (halves_in_plane) and the rings to recut joined again where they were cut open
  /// (ring_recut_in_plane), nested on no fewer sheets (such a nesting takes up to about 1.5 s
  /// on the jobs measured, a build seconds).
  int screened = 0;
  int sheets_before = 0, sheets_after = 0;
  int parts_before = 0, parts_after = 0;
  double minutes_before = 0, minutes_after = 0;  ///< estimated cutting time [min]
  int strips_split = 0;      ///< strips split in two (a ring cut open at two rulings) (kept)
  int rings_recut = 0;       ///< rings cut open at their middle instead of where they were (kept)
  double min_length_mm = 0;  ///< the shortest strip length split (kept) [mm]
  std::vector<std::array<int, 2>> split_edges;  ///< quad-mesh vertex pairs made strip borders
  double seconds = 0;
  bool saved() const { return sheets_after < sheets_before; }
};

/// What split_to_fit needs of the run.
struct SplitToFitInput {
  const PreparedInput* input = nullptr;
  const PartsOptions* parts = nullptr;  ///< the options the final build was made with
  /// The guidance the final build was made with beyond PartsOptions (the resolve loop's).
  Guidance guidance;
  const LayoutOptions* layout = nullptr;  ///< the sheets (as the layout stage used them)
  double min_part_area = 50;              ///< what a maker can handle [mm^2] (ResolveOptions)
  double min_part_width = 3;              ///< [mm]
  /// Why the run's build may not be split (nothing is tried); empty: it may.
  std::string blocked;
};

/// The laser path (\p joints) of one-row strip \p p of \p flat cut in two in its own flattening at
/// ruling \p ruling (an index into Patch::rulings): what a build with a strip border there would
/// nest, but for the joint along the new border and the halves flattened afresh. The path on
/// the first half's side of the ruling's line and near that half (its rails and rulings grown
/// by \p reach [mm], which takes its teeth) is one piece, the rest the other; the whole path
/// where the ruling has no length. split_to_fit nests these before it builds an attempt.
std::vector<Polygon2> halves_in_plane(const CuttablePatches& flat, const Joints& joints, int p,
                                      int ruling, double reach);

/// The laser path of ring \p p of \p flat (a strip the strips stage cut open from a closed
/// loop, Patch::loop_cut) recut at ruling \p ruling instead: its two pieces there
/// (halves_in_plane) joined again where it was cut open, the first half turned and moved so
/// that its first ruling lies on the last one (the same ruling in 3D), as one outline. Where
/// the ring turns by more than a full circle the two overlap and the union is smaller than the
/// recut ring will be. The whole path where \p p is no ring or a ruling has no length.
std::vector<Polygon2> ring_recut_in_plane(const CuttablePatches& flat, const Joints& joints, int p,
                                          int ruling, double reach);

/// Tries to save sheets on \p build laid out as \p layout; where it does, replaces both (the
/// parts renumbered, \p layout filled as lay_out_parts fills it). \p memo: the run's.
SplitToFitResult split_to_fit(PartsBuild& build, LayoutResult& layout, const SplitToFitInput& in,
                              const SplitToFitOptions& options, PartsMemo* memo);

}  // namespace kerfab

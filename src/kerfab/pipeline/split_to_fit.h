#pragma once
/// \file A sheet fewer by splitting long strips (after the layout): a long curved strip leaves
/// gaps no other part fills, and on a multi-sheet job the last sheet may hold only a few such
/// strips. Where the sheets used exceed the lower bounds and the parts could fill one sheet fewer
/// (their spaced area within kFullestSheet of it), the strips at least a given length are split
/// in two at the ruling nearest their middle (a strip border there: the two halves meet edge to
/// edge in the same bent sheet, joined like any border), and the parts are cut and nested again:
/// taken where that uses fewer sheets with no more critical regions, parts too small to handle,
/// borders without a joint or parts off the sheets.
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

/// Tries to save sheets on \p build laid out as \p layout; where it does, replaces both (the
/// parts renumbered, \p layout filled as lay_out_parts fills it). \p memo: the run's.
SplitToFitResult split_to_fit(PartsBuild& build, LayoutResult& layout, const SplitToFitInput& in,
                              const SplitToFitOptions& options, PartsMemo* memo);

}  // namespace kerfab

#pragma once
/// \file What a finished stage tells the user: progress lines (details under the stage's own
/// "[stage] ..." line) and warnings for the report. Kept apart from the stage order.
#include <string>
#include <vector>

#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

struct StageNotes {
  std::vector<std::string> lines;     ///< progress details, one line each
  std::vector<std::string> warnings;  ///< also listed in the report
  /// Earlier stages whose warnings no longer hold: this stage rebuilt their results (its own
  /// warnings then say what holds for the rebuilt ones).
  std::vector<Stage> supersedes;
};

/// A warning per file whose faces reading turned round (MeshRepairs).
StageNotes notes(const LoadedInputs& loaded);
StageNotes notes(const PreparedInput& input);
StageNotes notes(const QuadMeshResult& quads);
StageNotes notes(const CoarsenResult& coarsened);
/// Why a given quad mesh was used without looking for rows too narrow to bend.
StageNotes notes_coarsen_skipped(const std::string& why);
StageNotes notes(const BendingResult& bending);
StageNotes notes(const Strips& strips, const std::optional<RowBaseline>& baseline,
                 const StripsOptions& options);
StageNotes notes(const CuttablePatches& flat, double target_diagonal);
/// \p thickness: the sheet's [mm]; 0 (paper) with JointOptions::glue_tab 0 asks for plain
/// borders, which are then no defect to warn of. \p unresolved: the parts the resolve stage left
/// too small, narrow or distorted to handle (ResolveResult::unresolved_parts), ascending: a
/// border without a joint beside one is said to be there first.
StageNotes notes(const Joints& joints, const JointOptions& options, double thickness,
                 const std::vector<int>& unresolved = {});
StageNotes notes(const KerfResult& kerf, const KerfOptions& options);
/// The warning for \p by_options of \p planned kerf cuts that found no room in their parts
/// with the --bridge, --kerf-margin and --min-cut-length asked but would with the defaults
/// (KerfResult::skipped_by_options); \p at_first: of the first build, which the resolve stage
/// changed since.
std::string skipped_cuts_warning(int by_options, int planned, const KerfOptions& options,
                                 bool at_first = false);
/// \p quads_made: kerfab made the quad mesh (no --quad); the sizes the warning names hold for
/// these quads, and a run at another size from the triangles alone would make others.
StageNotes notes(const ResolveResult& resolve, const KerfOptions& kerf, bool quads_made = false);
StageNotes notes(const LayoutResult& layout, const LayoutOptions& options);
/// One line where strips were split to save a sheet (none otherwise).
StageNotes notes(const SplitToFitResult& split);
StageNotes notes(const AssemblyPlan& assembly);
StageNotes notes(const SurfaceDistance& quality, double target_diagonal);
/// \p size_mm: the model's largest bounding-box side as run; \p quads_made: kerfab made the quad
/// mesh (model/quads.obj).
StageNotes notes(const ShellClearance& clearance, double size_mm, bool quads_made);

}  // namespace kerfab

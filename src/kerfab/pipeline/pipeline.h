#pragma once
/// \file The pipeline: runs the stages in order, times them, reports progress and collects
/// their results. No file output here (see output/run_output.h).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "kerfab/assembly/assembly.h"
#include "kerfab/bending/bending.h"
#include "kerfab/core/material.h"
#include "kerfab/eval/shell_clearance.h"
#include "kerfab/eval/surface_distance.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/joints/joints.h"
#include "kerfab/kerf/kerf.h"
#include "kerfab/layout/layout.h"
#include "kerfab/pipeline/cuttable_patches.h"
#include "kerfab/pipeline/resolve.h"
#include "kerfab/pipeline/split_to_fit.h"
#include "kerfab/pipeline/stages.h"
#include "kerfab/quads/coarsen.h"
#include "kerfab/quads/quads.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

/// Where the inputs come from.
struct RunInputs {
  std::filesystem::path target;                   ///< target mesh file
  std::optional<std::filesystem::path> quad;      ///< quad (polygon) mesh file
  std::optional<std::filesystem::path> guidance;  ///< guidance JSON (forced edges)
};

/// Most distance samples the quality stage takes (the demo needs 4.4 million; a 120 mm cube's
/// strips at the default spacing would need more than 50 million and the run failed): beyond it
/// the spacing is widened and the report says which spacing was used.
inline constexpr long kQualitySampleBudget = 10'000'000;

struct PipelineOptions {
  InputOptions input;
  QuadMeshOptions quads;   ///< the quad mesh made for a triangle target without --quad
  CoarsenOptions coarsen;  ///< rows of a given quad mesh too narrow to bend, collapsed
  BendingOptions bending;  ///< its guidance is added to that of RunInputs::guidance
  StripsOptions strips;    ///< its split and merge edges are added to those of the guidance
  FlattenOptions flatten;
  JointOptions joints;
  KerfOptions kerf;
  ResolveOptions resolve;
  LayoutOptions layout;
  SplitToFitOptions split_to_fit;  ///< long strips split where that saves a sheet
  AssemblyOptions assembly;
  Material material;  ///< the sheet: thickness and strength (joints, kerf cuts)
  Machine machine;    ///< the laser: kerf width (joints) and speed (cutting time)
  double quality_sample_spacing = 0.004;  ///< the mean distances' samples at most this far
                                          ///< apart, the Hausdorff distance to within a quarter
                                          ///< of it, as a fraction of the target's bbox
                                          ///< diagonal [-], > 0 (widened where it would need
                                          ///< more than kQualitySampleBudget samples)
  double max_memory_mb = 0;   ///< memory budget [MB]; > 0: work that would need more is refused
                              ///< before it starts (the sub-quads, kMemoryPerSubQuadKb each)
  bool row_baseline = false;  ///< also build the naive one-strip-per-row layout (for comparison)
  std::optional<std::string> stop_after;  ///< one of stage_names(); unset: run all
};

/// What the load stage read.
struct LoadedInputs {
  PolyMesh target;
  std::optional<PolyMesh> quad;
  Guidance guidance;                         ///< from the guidance file
  MeshRepairs target_repairs, quad_repairs;  ///< what reading the files mended
};

struct StageTiming {
  std::string stage;
  double seconds = 0;
};

/// Each stage's result, present once the stage ran.
struct RunResult {
  RunInputs inputs;
  PipelineOptions options;  ///< as given
  std::optional<LoadedInputs> loaded;
  std::optional<PreparedInput> input;
  std::optional<QuadMeshResult> quads;  ///< when kerfab made the quad mesh (then also in input)
  /// When a given quad mesh was examined for rows too narrow to bend (the quads stage); where
  /// rows were collapsed, the coarsened mesh is the one in input.
  std::optional<CoarsenResult> coarsened;
  std::string coarsen_skipped;  ///< why a given quad mesh was not examined (empty: it was)
  std::optional<BendingResult> bending;
  std::optional<Strips> strips;         ///< as built, before any split
  std::optional<RowBaseline> baseline;  ///< with options.row_baseline
  std::optional<CuttablePatches> flat;  ///< patches split as needed and flattened
  std::optional<Joints> joints;
  std::optional<KerfResult> kerf;
  std::optional<ResolveResult> resolve;  ///< after it, bending .. kerf hold the final build
  std::optional<LayoutResult> layout;
  /// What the layout stage tried to save a sheet (where it split strips, bending .. kerf and
  /// the layout hold the build with them; resolve's numbers are of the build before).
  std::optional<SplitToFitResult> split_to_fit;
  std::optional<AssemblyPlan> assembly;
  std::optional<SurfaceDistance> quality;  ///< strip mesh vs target [mm]
  /// Where two stretches of the strips come closer than the sheets are thick (quality stage).
  std::optional<ShellClearance> clearance;
  std::vector<StageTiming> timings;
  double total_seconds = 0;
  std::vector<std::string> warnings;
  /// The strips as cut: split by the flattening step once it ran, else as built.
  const Strips& final_strips() const { return flat ? flat->strips : *strips; }
};

/// Progress sink: one human-readable line per call (the CLI prints them on stderr).
using Progress = std::function<void(std::string_view)>;

/// Runs the pipeline. \throw InvalidInput, IoError, SolverError as the stages do.
RunResult run_pipeline(const RunInputs& inputs, const PipelineOptions& options,
                       const Progress& progress);

}  // namespace kerfab

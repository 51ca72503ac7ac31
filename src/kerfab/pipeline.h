#pragma once
/// \file The pipeline: runs the stages in order, times them, reports progress and collects
/// their results. No file output here (see io/run_output.h).
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "kerfab/bending/bending.h"
#include "kerfab/eval/surface_distance.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/input/prepare.h"
#include "kerfab/joints/joints.h"
#include "kerfab/kerf/kerf.h"
#include "kerfab/layout/labels.h"
#include "kerfab/layout/layout.h"
#include "kerfab/strips/strips.h"

namespace kerfab {

/// Where the inputs come from.
struct RunInputs {
  std::filesystem::path target;                   ///< target mesh file
  std::optional<std::filesystem::path> quad;      ///< quad (polygon) mesh file
  std::optional<std::filesystem::path> guidance;  ///< guidance JSON (forced edges)
};

/// The stages, in order. `stop_after` ends the run after the named one.
inline const std::vector<std::string>& stage_names() {
  static const std::vector<std::string> names = {
      "load", "prepare", "bending", "strips", "flatten", "joints", "kerf", "layout", "quality"};
  return names;
}

/// Cut-sheet file formats to write.
struct SheetFormats {
  bool svg = true;
  bool dxf = true;
  bool pdf = true;
};

struct PipelineOptions {
  InputOptions input;
  BendingOptions bending;  ///< guidance is filled from RunInputs::guidance
  StripsOptions strips;
  FlattenOptions flatten;
  JointOptions joints;  ///< thickness and kerf width are taken from `kerf` and the material
  KerfOptions kerf;
  MachineOptions machine;
  LayoutOptions layout;
  SheetFormats formats;
  SheetStyle style;
  double quality_sample_spacing = 0.002;  ///< distance samples at most this far apart, as a
                                          ///< fraction of the target's bbox diagonal [-], > 0
  std::optional<std::string> stop_after;  ///< one of stage_names(); unset: run all
};

struct StageTiming {
  std::string stage;
  double seconds = 0;
};

struct RunResult {
  RunInputs inputs;
  PipelineOptions options;  ///< the options as used (guidance resolved)
  std::optional<PreparedInput> input;
  std::optional<BendingResult> bending;
  std::optional<Strips> strips;
  int quad_rows = 0;         ///< dual chords of the quad mesh (see quad_rows())
  int naive_row_strips = 0;  ///< strips of the naive row layout (naive_row_bending()), same options
  std::optional<Flattening> flattening;
  int overlap_splits = 0;  ///< patches split because their flat outline crossed itself
  std::optional<SurfaceDistance> flatten_mimic;  ///< 3D strips vs their flat-metric deformation
  std::optional<Joints> joints;
  std::optional<KerfResult> kerf;
  double outline_length = 0;  ///< all parts' laser paths [mm]
  int oversize_splits = 0;    ///< patches split because they did not fit a sheet
  std::optional<LayoutResult> layout;
  std::vector<std::optional<Label>> labels;    ///< per part: its number
  std::vector<std::vector<Label>> engravings;  ///< per part: its number and border labels
  std::optional<SurfaceDistance> quality;      ///< strip mesh vs target [mm]
  double target_diagonal = 0;                  ///< target bbox diagonal [mm] (set by prepare)
  std::vector<StageTiming> timings;
  double total_seconds = 0;
  std::vector<std::string> warnings;
};

/// Progress sink: one human-readable line per call (the CLI prints them on stderr).
using Progress = std::function<void(std::string_view)>;

/// Runs the pipeline. \throw InvalidInput, IoError, SolverError as the stages do.
RunResult run_pipeline(const RunInputs& inputs, const PipelineOptions& options,
                       const Progress& progress);

}  // namespace kerfab

#pragma once
/// \file One function per section of report.json, each from its stage's result (internal to
/// output/: the only header that exposes nlohmann::json).
#include <nlohmann/json.hpp>

#include "kerfab/output/output_options.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab::report {

using nlohmann::json;

json input_section(const RunInputs& inputs, const std::optional<LoadedInputs>& loaded,
                   const std::optional<PreparedInput>& input);
json quads_section(const QuadMeshResult& quads);
json coarsen_section(const CoarsenResult& coarsened);
json options_section(const RunResult& run, const OutputOptions& output);
json bending_section(const BendingResult& bending, const BendingOptions& options);
json strips_section(const Strips& strips, int overlap_splits,
                    const std::optional<RowBaseline>& baseline);
json flatten_section(const CuttablePatches& flat, double target_diagonal);
json joints_section(const Joints& joints, const Material& material);
json kerf_section(const KerfResult& kerf, const KerfOptions& options);
json cutting_section(const CuttingEstimate& cutting, const Machine& machine);
json resolve_section(const ResolveResult& resolve, const ResolveOptions& options);
json layout_section(const LayoutResult& layout, const LayoutOptions& options,
                    const SheetFormats& formats, int oversize_splits);
/// The assembly order (assembly.order) and its steps, with each part's sheet.
/// What the layout stage tried to save a sheet by splitting long strips.
json split_to_fit_section(const SplitToFitResult& s);
json assembly_section(const AssemblyPlan& assembly, const LayoutResult& layout);
json quality_section(const SurfaceDistance& quality, double target_diagonal);
/// Where two stretches of the strips come closer than the sheets are thick.
json clearance_section(const ShellClearance& clearance);
json timings_section(const std::vector<StageTiming>& timings, double total_seconds);

}  // namespace kerfab::report

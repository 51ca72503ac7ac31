#include "kerfab/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>

#include "kerfab/core/errors.h"
#include "kerfab/io/guidance.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/pipeline/notes.h"

namespace kerfab {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Runs one stage at a time: announces it, times it, passes its notes on, and says whether the
/// run goes on after it (false once `stop_after` is reached).
class StageRunner {
 public:
  StageRunner(RunResult& run, const Progress& progress) : run_(run), progress_(progress) {}
  bool operator()(Stage stage, const std::function<StageNotes()>& body) {
    const std::string name(stage_name(stage));
    if (progress_) progress_("[" + name + "] ...");
    const auto t0 = Clock::now();
    const StageNotes notes = body();
    run_.timings.push_back({name, seconds_since(t0)});
    for (const auto& line : notes.lines)
      if (progress_) progress_("  " + line);
    run_.warnings.insert(run_.warnings.end(), notes.warnings.begin(), notes.warnings.end());
    return !(run_.options.stop_after && *run_.options.stop_after == name);
  }

 private:
  RunResult& run_;
  const Progress& progress_;
};

LoadedInputs load_inputs(const RunInputs& in) {
  LoadedInputs out{read_mesh(in.target), std::nullopt, {}};
  if (in.quad) out.quad = read_mesh(*in.quad);
  if (in.guidance) out.guidance = read_guidance(*in.guidance);
  return out;
}

}  // namespace

RunResult run_pipeline(const RunInputs& inputs, const PipelineOptions& o,
                       const Progress& progress) {
  const auto t_start = Clock::now();
  const auto& names = stage_names();
  if (o.stop_after && std::find(names.begin(), names.end(), *o.stop_after) == names.end())
    throw InvalidInput("--stop-after: unknown stage '" + *o.stop_after + "'");
  RunResult r{.inputs = inputs, .options = o};
  StageRunner stage(r, progress);
  auto diag = [&] { return r.input->target_diagonal; };
  LayoutOptions usable = o.layout;  // room for a plate thickness of teeth along the margins
  usable.margin += o.material.thickness;

  // The stages in order; each stores its result in r and returns what it tells the user.
  const std::vector<std::pair<Stage, std::function<StageNotes()>>> stages = {
      {Stage::kLoad,
       [&] {
         r.loaded = load_inputs(inputs);
         return StageNotes{};
       }},
      {Stage::kPrepare,
       [&] {
         r.input = prepare_input(r.loaded->target, r.loaded->quad, o.input);
         return notes(*r.input);
       }},
      {Stage::kBending,
       [&] {
         BendingOptions bending = o.bending;  // with the guidance file's edges
         const Guidance& g = r.loaded->guidance;
         bending.guidance.insert(bending.guidance.end(), g.edges.begin(), g.edges.end());
         r.bending = choose_bending_edges(r.input->quads, r.input->surface, bending);
         return notes(*r.bending);
       }},
      {Stage::kStrips,
       [&] {
         StripsOptions strips = o.strips;  // with the guidance file's splits and merges
         const Guidance& g = r.loaded->guidance;
         strips.split_edges.insert(strips.split_edges.end(), g.split.begin(), g.split.end());
         strips.merge_edges.insert(strips.merge_edges.end(), g.merge.begin(), g.merge.end());
         r.strips = build_strips(r.input->quads, *r.bending, r.input->surface, strips);
         if (o.row_baseline) r.baseline = row_baseline(r.input->quads, r.input->surface, o.strips);
         return notes(*r.strips, r.baseline, o.strips);
       }},
      {Stage::kFlatten,
       [&] {
         r.flat = flatten_cuttable(*r.strips, o.flatten, usable,
                                   5 * o.quality_sample_spacing * diag());  // smooth difference
         return notes(*r.flat, diag());
       }},
      {Stage::kJoints,
       [&] {
         r.joints =
             make_joints(r.flat->strips, r.flat->flattening, o.material, o.machine, o.joints);
         return notes(*r.joints, o.joints);
       }},
      {Stage::kKerf,
       [&] {
         r.kerf = place_kerf_cuts(r.flat->strips, r.flat->flattening, *r.joints, o.material,
                                  o.machine, o.kerf);
         return notes(*r.kerf, o.kerf);
       }},
      {Stage::kLayout,
       [&] {
         r.layout = lay_out_parts(r.flat->strips, r.flat->flattening, *r.joints, *r.kerf, o.layout);
         return notes(*r.layout, o.layout);
       }},
      {Stage::kQuality,
       [&] {
         r.quality = surface_distance(triangulate(r.flat->strips), r.input->surface.mesh(),
                                      {.sample_spacing = o.quality_sample_spacing * diag()});
         return notes(*r.quality, diag());
       }},
  };
  for (const auto& [id, body] : stages)
    if (!stage(id, body)) break;
  r.total_seconds = seconds_since(t_start);
  return r;
}

}  // namespace kerfab

#include "kerfab/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

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

/// The flattening's check of how far the strips move when deformed to the flat metric samples
/// this many times more coarsely than the quality stage (a hundredth of the diagonal by
/// default): it only has to see that the move is small [-].
constexpr double kDeformationSpacing = 2.5;

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
    for (Stage earlier : notes.supersedes) warnings_.erase(earlier);
    warnings_[stage] = notes.warnings;
    run_.warnings.clear();
    for (const auto& [s, list] : warnings_)  // in stage order
      run_.warnings.insert(run_.warnings.end(), list.begin(), list.end());
    return !(run_.options.stop_after && *run_.options.stop_after == name);
  }

 private:
  RunResult& run_;
  const Progress& progress_;
  std::map<Stage, std::vector<std::string>> warnings_;
};

LoadedInputs load_inputs(const RunInputs& in) {
  LoadedInputs out;
  out.target = read_mesh(in.target, &out.target_repairs);
  if (in.quad) out.quad = read_mesh(*in.quad, &out.quad_repairs);
  if (in.guidance) out.guidance = read_guidance(*in.guidance);
  return out;
}

}  // namespace

/// The parts from bending to kerf, taken out of \p r as one build.
static PartsBuild take_build(RunResult& r) {
  return {std::move(*r.bending), std::move(*r.strips), std::move(*r.flat), std::move(*r.joints),
          std::move(*r.kerf)};
}

/// \p build back into \p r.
static void put_build(RunResult& r, PartsBuild&& build) {
  r.bending = std::move(build.bending);
  r.strips = std::move(build.strips);
  r.flat = std::move(build.flat);
  r.joints = std::move(build.joints);
  r.kerf = std::move(build.kerf);
}

/// The warnings of the stages from strips to kerf on the parts \p r holds now (a stage that
/// rebuilds them carries these in its notes and supersedes theirs).
static std::vector<std::string> rebuilt_warnings(const RunResult& r, double diagonal) {
  const PipelineOptions& o = r.options;
  const std::vector<int> unresolved = r.resolve ? r.resolve->unresolved_parts : std::vector<int>{};
  std::vector<std::string> held;
  for (const StageNotes& rebuilt :
       {notes(*r.strips, r.baseline, o.strips), notes(*r.flat, diagonal),
        notes(*r.joints, o.joints, o.material.thickness, unresolved), notes(*r.kerf, o.kerf)})
    held.insert(held.end(), rebuilt.warnings.begin(), rebuilt.warnings.end());
  return held;
}

/// The resolve stage: the parts built so far go in, the rebuilt ones come back into \p r. Its
/// notes carry the warnings that hold for the rebuilt parts and replace the earlier stages'.
/// \p of_first: what it says of the first build that no later stage can see again.
static StageNotes resolve_stage(RunResult& r, const PartsOptions& parts, double diagonal,
                                double deformation_spacing, const Progress& progress,
                                PartsMemo& memo, std::vector<std::string>& of_first) {
  const PipelineOptions& o = r.options;
  // Cuts the options left no room for in the first build: named even where the resolve stage
  // then made those parts flat facets (--bridge 50 made all of Spot facets, with no word why).
  const int first_skipped = r.kerf->skipped_by_options;
  const int first_planned = r.kerf->cuts + r.kerf->skipped;
  PartsBuild build = take_build(r);
  // Joints drafted without stub teeth: the loop's final build has them even where it changed
  // nothing else, and the joints and kerf stages' notes were of the draft.
  const bool drafted = build.joints.draft;
  const auto round_done = [&](const std::string& line) {
    if (progress) progress("  " + line);
  };
  r.resolve = resolve_critical_regions(build, *r.input, parts, o.resolve, round_done, &memo);
  put_build(r, std::move(build));
  if (r.resolve->rounds > 0 && o.flatten.mimic_3d)
    r.flat->deformation = flat_metric_deformation(*r.flat, deformation_spacing);
  StageNotes n = notes(*r.resolve, o.kerf, r.quads.has_value());
  if (r.resolve->rounds > 0 || drafted) {
    n.supersedes = {Stage::kStrips, Stage::kFlatten, Stage::kJoints, Stage::kKerf};
    std::vector<std::string> held = rebuilt_warnings(r, diagonal);
    if (first_skipped > 0 && r.kerf->skipped_by_options == 0)
      of_first.push_back(skipped_cuts_warning(first_skipped, first_planned, o.kerf, true));
    held.insert(held.end(), of_first.begin(), of_first.end());
    n.warnings.insert(n.warnings.begin(), held.begin(), held.end());
  }
  return n;
}

/// The layout stage's second half: long strips split where that saves a sheet (split_to_fit),
/// only on a build the resolve stage left with no part it names by number (unresolved, or
/// left out beside one) and no facet cut along its outline alone (a rebuild would not make
/// that again). Where it splits, the notes of the stages it rebuilt are made again, and the
/// resolve stage's (which carried theirs), with \p of_first (resolve_stage).
static StageNotes split_to_fit_stage(RunResult& r, const PartsOptions& parts, double diagonal,
                                     double deformation_spacing, PartsMemo& memo,
                                     const std::vector<std::string>& of_first) {
  const PipelineOptions& o = r.options;
  SplitToFitInput in{r.input ? &*r.input : nullptr, &parts, {}, &o.layout, o.resolve.min_part_area,
                     o.resolve.min_part_width};
  if (r.resolve) {
    in.guidance = r.resolve->added;
    if (!r.resolve->unresolved_parts.empty())
      in.blocked = "the resolve stage left parts unresolved";
    for (const RegionChange& c : r.resolve->changes)
      if (c.action == "omit" || c.action == "outline")
        in.blocked = "the resolve stage left parts out or cut facets along their outlines";
  }
  PartsBuild build = take_build(r);
  r.split_to_fit = split_to_fit(build, *r.layout, in, o.split_to_fit, &memo);
  put_build(r, std::move(build));
  StageNotes n = notes(*r.layout, o.layout);
  if (!r.split_to_fit->saved()) return n;
  if (o.flatten.mimic_3d)
    r.flat->deformation = flat_metric_deformation(*r.flat, deformation_spacing);
  const StageNotes split = notes(*r.split_to_fit);
  n.lines.insert(n.lines.begin(), split.lines.begin(), split.lines.end());
  n.supersedes = {Stage::kStrips, Stage::kFlatten, Stage::kJoints, Stage::kKerf, Stage::kResolve};
  std::vector<std::string> held = rebuilt_warnings(r, diagonal);
  held.insert(held.end(), of_first.begin(), of_first.end());
  if (r.resolve) {
    const StageNotes own = notes(*r.resolve, o.kerf, r.quads.has_value());
    held.insert(held.end(), own.warnings.begin(), own.warnings.end());
  }
  n.warnings.insert(n.warnings.begin(), held.begin(), held.end());
  return n;
}

RunResult run_pipeline(const RunInputs& inputs, const PipelineOptions& o,
                       const Progress& progress) {
  const auto t_start = Clock::now();
  const auto& names = stage_names();
  if (o.stop_after && std::find(names.begin(), names.end(), *o.stop_after) == names.end())
    throw InvalidInput("--stop-after: unknown stage '" + *o.stop_after + "'");
  RunResult r{.inputs = inputs, .options = o};
  StageRunner stage(r, progress);
  auto diag = [&] { return r.input->target_diagonal; };
  // A part must fit the sheet with what its joints add beyond its flat outline: room for a
  // plate thickness of teeth along the margins, or in paper (no thickness) a glue tab's height
  // (a 23-quad strip of the bunny fitted A4 until its tabs were added, and was left off).
  LayoutOptions usable = o.layout;
  usable.margin += o.material.thickness > 0 ? o.material.thickness : o.joints.glue_tab;
  check_sheets(usable);  // before any work: a sheet with no room fails only in the layout
  // The joints give a part too small or too narrow to handle the teeth instead of the slots,
  // by the resolve step's measures of what a maker can handle.
  JointOptions joints = o.joints;
  joints.min_part_area = o.resolve.min_part_area;
  joints.min_part_width = o.resolve.min_part_width;
  check_joint_options(o.material, o.machine, joints);  // before any work, as the sheets
  check_kerf_options(o.material, o.machine, o.kerf);
  // Paper folds: a strip's quads that twist are creased along a diagonal and flattened as
  // their two triangles, where a sheet of wood (split at its folds, bent along its rulings)
  // cannot be.
  FlattenOptions flatten = o.flatten;
  flatten.crease_twisted = flatten.crease_twisted || o.material.thickness == 0;
  // The flattening's 3D check: how finely it samples the strips' move [mm].
  auto deformation_spacing = [&] {
    return kDeformationSpacing * o.quality_sample_spacing * diag();
  };
  // The options the stages from bending to kerf run with, the guidance file's edges included.
  auto parts_options = [&] {
    PartsOptions p{o.bending, o.strips, flatten, usable, o.material, o.machine, joints, o.kerf};
    const Guidance& g = r.loaded->guidance;
    p.bending.guidance.insert(p.bending.guidance.end(), g.edges.begin(), g.edges.end());
    if (r.quads)  // the quads stage's own (an extrusion's wall stiff between its rows)
      p.bending.guidance.insert(p.bending.guidance.end(), r.quads->bending.begin(),
                                r.quads->bending.end());
    p.strips.split_edges.insert(p.strips.split_edges.end(), g.split.begin(), g.split.end());
    p.strips.merge_edges.insert(p.strips.merge_edges.end(), g.merge.begin(), g.merge.end());
    p.strips.max_memory_mb = o.max_memory_mb;
    return p;
  };

  // Part outlines drawn by the joints stage and patches' cuts placed by the kerf stage, reused
  // by the resolve stage's rebuilds.
  PartsMemo memo(parts_memo_bytes(o.max_memory_mb));
  // Warnings of the first build that the resolve stage carries and a later rebuild keeps.
  std::vector<std::string> of_first;
  // Whether the resolve loop runs on the parts the joints and kerf stages cut.
  const bool resolve_follows =
      o.resolve.enabled &&
      (!o.stop_after || (*o.stop_after != "joints" && *o.stop_after != "kerf"));
  // The stages in order; each stores its result in r and returns what it tells the user.
  const std::vector<std::pair<Stage, std::function<StageNotes()>>> stages = {
      {Stage::kLoad,
       [&] {
         r.loaded = load_inputs(inputs);
         return notes(*r.loaded);
       }},
      {Stage::kPrepare,
       [&] {
         r.input = prepare_input(r.loaded->target, r.loaded->quad, o.input);
         return notes(*r.input);
       }},
      {Stage::kQuads,
       [&] {
         if (!r.input->needs_quads) {
           // A given quad mesh: rows too narrow for their bend are collapsed, unless a
           // guidance file names its vertices (they would no longer be the same).
           const Guidance& g = r.loaded->guidance;
           const bool guided = !g.edges.empty() || !g.split.empty() || !g.merge.empty() ||
                               !o.bending.guidance.empty() || !o.strips.split_edges.empty() ||
                               !o.strips.merge_edges.empty();
           if (!o.coarsen.enabled) return StageNotes{};
           if (guided) {
             r.coarsen_skipped = "guidance names the given quad mesh's vertices";
             return notes_coarsen_skipped(r.coarsen_skipped);
           }
           CoarsenOptions co = o.coarsen;
           co.min_cut_spacing = o.kerf.min_cut_spacing;
           co.feature_angle = o.quads.feature_angle;
           r.coarsened = coarsen_quads(r.input->quads, r.input->surface, o.material, co);
           if (r.coarsened->changed()) attach_quads(*r.input, r.coarsened->quads, o.input);
           return notes(*r.coarsened);
         }
         QuadMeshOptions qo = o.quads;
         qo.min_cut_spacing = o.kerf.min_cut_spacing;
         r.quads = make_quad_mesh(r.input->surface, o.material, qo, [&](const std::string& line) {
           if (progress) progress("  " + line);
         });
         attach_quads(*r.input, r.quads->quads, o.input);
         return notes(*r.quads);
       }},
      {Stage::kBending,
       [&] {
         r.bending =
             choose_bending_edges(r.input->quads, r.input->surface, parts_options().bending);
         return notes(*r.bending);
       }},
      {Stage::kStrips,
       [&] {
         r.strips =
             build_strips(r.input->quads, *r.bending, r.input->surface, parts_options().strips);
         if (o.row_baseline) r.baseline = row_baseline(r.input->quads, r.input->surface, o.strips);
         return notes(*r.strips, r.baseline, o.strips);
       }},
      {Stage::kFlatten,
       [&] {
         r.flat = flatten_cuttable(*r.strips, flatten, usable);
         if (o.flatten.mimic_3d)
           r.flat->deformation = flat_metric_deformation(*r.flat, deformation_spacing());
         return notes(*r.flat, diag());
       }},
      {Stage::kJoints,
       [&] {
         // Where the resolve stage follows, a draft without the short borders' stub teeth: it
         // looks for critical regions and parts too small, and its final build gets them.
         JointOptions first = joints;
         first.stub_teeth = !resolve_follows;
         r.joints = make_joints(r.flat->strips, r.flat->flattening, o.material, o.machine, first,
                                &memo.outlines);
         return notes(*r.joints, first, o.material.thickness);
       }},
      {Stage::kKerf,
       [&] {
         r.kerf = place_kerf_cuts(r.flat->strips, r.flat->flattening, *r.joints, o.material,
                                  o.machine, o.kerf, &memo.kerf);
         return notes(*r.kerf, o.kerf);
       }},
      {Stage::kResolve,
       [&] {
         return resolve_stage(r, parts_options(), diag(), deformation_spacing(), progress, memo,
                              of_first);
       }},
      {Stage::kLayout,
       [&] {
         r.layout = lay_out_parts(r.flat->strips, r.flat->flattening, *r.joints, *r.kerf, o.layout);
         return split_to_fit_stage(r, parts_options(), diag(), deformation_spacing(), memo,
                                   of_first);
       }},
      {Stage::kAssembly,
       [&] {
         const std::vector<double> perimeter = part_perimeters(r.flat->strips);
         std::vector<PartShape> shapes;
         for (std::size_t p = 0; p < r.joints->parts.size(); ++p)
           shapes.push_back({std::abs(polygon_area(r.joints->parts[p].designed)),
                             p < perimeter.size() ? perimeter[p] : 0.0});
         r.assembly = plan_assembly(*r.joints, shapes, o.assembly);
         return notes(*r.assembly);
       }},
      {Stage::kQuality,
       [&] {
         const Strips& built = r.flat->strips;
         const TriangleMesh triangles = triangulate(built);
         r.quality = surface_distance(triangles, r.input->surface.mesh(),
                                      {.sample_spacing = o.quality_sample_spacing * diag(),
                                       .max_samples = kQualitySampleBudget});
         StageNotes n = notes(*r.quality, diag());
         r.clearance = shell_clearance(
             {built.vertices, built.faces, built.face_patch, built.edge_vertices, triangles},
             {.thickness = o.material.thickness, .max_fold = kMaxJointFold}, &r.input->surface);
         const StageNotes c =
             notes(*r.clearance, bounding_box(r.input->surface.mesh()).largest_side(),
                   r.quads.has_value());
         n.lines.insert(n.lines.end(), c.lines.begin(), c.lines.end());
         n.warnings.insert(n.warnings.end(), c.warnings.begin(), c.warnings.end());
         return n;
       }},
  };
  for (const auto& [id, body] : stages)
    if (!stage(id, body)) break;
  r.total_seconds = seconds_since(t_start);
  return r;
}

}  // namespace kerfab

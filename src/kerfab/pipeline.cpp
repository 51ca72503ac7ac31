#include "kerfab/pipeline.h"

#include <algorithm>
#include <chrono>
#include <sstream>

#include "kerfab/core/errors.h"
#include "kerfab/io/guidance.h"
#include "kerfab/io/mesh_io.h"

namespace kerfab {
namespace {

class StageClock {
 public:
  StageClock(RunResult& run, const Progress& progress) : run_(run), progress_(progress) {}
  template <class F>
  void stage(const std::string& name, F&& body) {
    if (progress_) progress_("[" + name + "] ...");
    const auto t0 = std::chrono::steady_clock::now();
    body();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run_.timings.push_back({name, s});
  }

 private:
  RunResult& run_;
  const Progress& progress_;
};

std::string summary_line(const std::string& what, const MeshSummary& s) {
  std::ostringstream os;
  os.precision(4);
  os << what << ": " << s.vertices << " vertices, " << s.faces << " faces (";
  for (std::size_t i = 0; i < s.face_sizes.size(); ++i)
    os << (i ? ", " : "") << s.face_sizes[i].second << "x" << s.face_sizes[i].first << "-gon";
  const Vec3 size = s.bbox.size();
  os << "), " << s.boundary_loops << " boundary loop(s), Euler characteristic "
     << s.euler_characteristic << ", bbox " << size.x() << " x " << size.y() << " x " << size.z()
     << " mm";
  return os.str();
}

}  // namespace

RunResult run_pipeline(const RunInputs& inputs, const PipelineOptions& options,
                       const Progress& progress) {
  const auto t_start = std::chrono::steady_clock::now();
  if (options.stop_after) {
    const auto& names = stage_names();
    if (std::find(names.begin(), names.end(), *options.stop_after) == names.end())
      throw InvalidInput("--stop-after: unknown stage '" + *options.stop_after + "'");
  }
  RunResult run;
  run.inputs = inputs;
  run.options = options;
  StageClock clock(run, progress);
  auto say = [&](const std::string& line) {
    if (progress) progress("  " + line);
  };
  auto done_after = [&](const std::string& stage) {
    return options.stop_after && *options.stop_after == stage;
  };
  auto finish = [&]() -> RunResult {
    run.total_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return std::move(run);
  };

  PolyMesh target;
  std::optional<PolyMesh> quad;
  clock.stage("load", [&] {
    target = read_mesh(inputs.target);
    if (inputs.quad) quad = read_mesh(*inputs.quad);
    if (inputs.guidance) run.options.bending.guidance = read_guidance(*inputs.guidance);
  });
  if (done_after("load")) return finish();

  clock.stage("prepare", [&] {
    run.input = prepare_input(target, quad, options.input);
    run.target_diagonal = bounding_box(run.input->surface.mesh()).diagonal();
    const PreparedInput& in = *run.input;
    say(summary_line("target", in.target_summary));
    say(summary_line(in.quads_from_target ? "quads (from target)" : "quads", in.quad_summary));
    std::ostringstream os;
    os.precision(4);
    os << "scale " << in.scale << ", quad vertices to target: max " << in.quad_max_distance
       << " mm, mean " << in.quad_mean_distance << " mm";
    say(os.str());
    for (const auto& w : in.warnings) run.warnings.push_back(w);
  });
  if (done_after("prepare")) return finish();

  clock.stage("bending", [&] {
    run.bending = choose_bending_edges(run.input->quads, run.input->surface, run.options.bending);
    const BendingResult& b = *run.bending;
    std::ostringstream os;
    os.precision(4);
    os << b.bendable_count << " of " << b.bendable.size() << " edges bendable, objective "
       << b.objective << " (bound " << b.bound << ", " << to_string(b.status) << ", "
       << b.solve_seconds << " s), aligned " << 100.0 * b.aligned_fraction << "%";
    say(os.str());
    if (b.status != PackingStatus::kOptimal) {
      std::ostringstream w;
      w.precision(4);
      w << "bending program not proven optimal (" << to_string(b.status) << "): objective "
        << b.objective << ", bound " << b.bound;
      run.warnings.push_back(w.str());
    }
  });
  if (done_after("bending")) return finish();

  clock.stage("strips", [&] {
    run.strips =
        build_strips(run.input->quads, *run.bending, run.input->surface, run.options.strips);
    run.quad_rows = quad_rows(run.input->quads);
    run.naive_row_strips =
        static_cast<int>(build_strips(run.input->quads, naive_row_bending(run.input->quads),
                                      run.input->surface, run.options.strips)
                             .patches.size());
    const Strips& s = *run.strips;
    std::ostringstream os;
    os.precision(4);
    os << s.patches.size() << " strips from " << s.chains << " chains (" << s.closed_loops
       << " closed loops cut, " << s.split_borders << " split at folds > "
       << run.options.strips.split_angle * 180 / M_PI << " deg); " << s.faces.size()
       << " sub-quads, " << s.vertices.size() << " vertices, " << s.t_junctions
       << " T-junction vertices; a naive one-strip-per-row layout would give "
       << run.naive_row_strips << " (" << run.quad_rows << " quad rows)";
    say(os.str());
    if (s.ray_fallbacks > 0) {
      std::ostringstream w;
      w << s.ray_fallbacks << " vertices missed the target along their normal and went to the "
        << "closest point instead";
      say(w.str());
    }
  });
  if (done_after("strips")) return finish();

  clock.stage("flatten", [&] {
    run.flattening = flatten_patches(*run.strips, run.options.flatten);
    // A patch whose unrolled outline crosses itself cannot be cut in one piece: split it at the
    // quad boundary nearest its middle and flatten again, until every outline is simple.
    // So is a part larger than the sheet (allowing a plate thickness for its teeth).
    LayoutOptions usable = run.options.layout;
    usable.margin += run.options.kerf.material.thickness;
    auto oversize = [&](std::size_t p) {
      return !fits_sheet(flat_outline(*run.strips, *run.flattening, static_cast<int>(p)), usable);
    };
    for (int round = 0; round < 12; ++round) {
      Strips split = *run.strips;
      int splits = 0;
      for (std::size_t p = 0; p < run.flattening->patches.size(); ++p) {
        const int quads = static_cast<int>(split.patches[p].quads.size());
        if (quads < 2) continue;
        if (!run.flattening->patches[p].outline_simple) {
          ++run.overlap_splits;
        } else if (oversize(p)) {
          ++run.oversize_splits;
        } else {
          continue;
        }
        split = split_patch(split, static_cast<int>(p), quads / 2);
        ++splits;
      }
      if (splits == 0) break;
      run.strips = std::move(split);
      run.flattening = flatten_patches(*run.strips, run.options.flatten);
    }
    const Flattening& f = *run.flattening;
    if (run.overlap_splits + run.oversize_splits > 0)
      say(std::to_string(run.overlap_splits) + " patch splits because a flat outline crossed " +
          "itself, " + std::to_string(run.oversize_splits) +
          " because a part was larger than the sheet; now " +
          std::to_string(run.strips->patches.size()) + " patches");
    int iterations = 0;
    for (const auto& p : f.patches) iterations = std::max(iterations, p.iterations);
    std::ostringstream os;
    os.precision(4);
    os << f.patches.size() << " patches flattened (at most " << iterations
       << " Gauss-Newton iterations, " << f.unconverged << " not converged); max angle error "
       << f.max_angle_error * 180 / M_PI << " deg, max border length error "
       << 100 * f.max_border_length_error_rel << "%, mating borders differ by at most "
       << 100 * f.max_mating_mismatch_rel << "% per piece, "
       << 100 * f.max_shared_border_mismatch_rel << "% per shared border";
    say(os.str());
    if (run.options.flatten.mimic_3d) {
      const double diag = run.target_diagonal;
      SurfaceDistanceOptions d;
      d.sample_spacing = 5 * run.options.quality_sample_spacing * diag;  // smooth difference
      run.flatten_mimic = surface_distance(patch_triangles(*run.strips, f, false),
                                           patch_triangles(*run.strips, f, true), d);
      std::ostringstream m;
      m.precision(4);
      m << "3D strips deformed to the flat metric move by at most " << run.flatten_mimic->hausdorff
        << " mm (Hausdorff, " << 100 * run.flatten_mimic->hausdorff / diag << "% of diagonal)";
      say(m.str());
    }
    if (f.inverted_quads > 0)
      run.warnings.push_back("flattening inverted " + std::to_string(f.inverted_quads) +
                             " quads (see flatten.patches in the report); those parts will not "
                             "fit as designed");
    if (f.non_simple_outlines > 0)
      run.warnings.push_back(std::to_string(f.non_simple_outlines) +
                             " flattened patches still overlap themselves in the plane after "
                             "splitting (see flatten.patches)");
    if (f.unconverged > 0)
      run.warnings.push_back(std::to_string(f.unconverged) +
                             " patches did not converge in the flattening iteration limit");
  });
  if (done_after("flatten")) return finish();

  run.options.joints.thickness = run.options.kerf.material.thickness;
  run.options.joints.kerf_width = run.options.kerf.kerf_width;
  clock.stage("joints", [&] {
    run.joints = make_joints(*run.strips, *run.flattening, run.options.joints);
    const Joints& j = *run.joints;
    int blocked = 0, shallow = 0;
    for (const auto& b : j.borders) blocked += b.blocked, shallow += b.shallow;
    std::ostringstream os;
    os.precision(4);
    os << j.teeth << " teeth on " << j.borders.size() << " border pieces ("
       << 100 * (j.border_length > 0 ? j.toothed_length / j.border_length : 0)
       << "% of the shared border length); intervals without teeth: " << shallow
       << " too shallow (tip - slot < " << run.options.joints.min_depth << " mm), " << blocked
       << " in collision regions";
    say(os.str());
    if (j.repaired_parts > 0)
      run.warnings.push_back(std::to_string(j.repaired_parts) +
                             " parts fell apart into pieces when their joints were cut; only "
                             "the largest piece of each is kept");
  });
  if (done_after("joints")) return finish();

  clock.stage("kerf", [&] {
    run.kerf = place_kerf_cuts(*run.strips, *run.flattening, *run.joints, run.options.kerf);
    const KerfResult& k = *run.kerf;
    run.outline_length = 0;
    for (const auto& part : run.joints->parts)
      for (std::size_t i = 0; i < part.cut.size(); ++i)
        run.outline_length += (part.cut[(i + 1) % part.cut.size()] - part.cut[i]).norm();
    std::ostringstream os;
    os.precision(4);
    os << k.cuts << " kerf cuts, " << k.cut_length / 1000 << " m; " << k.critical.size()
       << " critical regions (cuts closer than " << run.options.kerf.min_cut_spacing
       << " mm); estimated cutting time "
       << cutting_minutes(k.cut_length + run.outline_length,
                          k.cuts + static_cast<int>(run.joints->parts.size()), run.options.machine)
       << " min";
    say(os.str());
    if (!k.critical.empty()) {
      std::ostringstream w;
      w.precision(3);
      w << k.critical.size() << " critical kerf regions: the bend needs cuts closer than "
        << run.options.kerf.min_cut_spacing << " mm (first: patch " << k.critical.front().patch
        << " at " << k.critical.front().start << " mm, spacing " << k.critical.front().spacing
        << " mm); see kerf.critical and model/kerf_density.ply";
      run.warnings.push_back(w.str());
    }
  });
  if (done_after("kerf")) return finish();

  clock.stage("layout", [&] {
    std::vector<Polygon2> outlines;
    for (const auto& part : run.joints->parts) outlines.push_back(part.cut);
    run.layout = nest_parts(outlines, run.options.layout);
    run.labels.clear();
    run.engravings.clear();
    for (std::size_t p = 0; p < run.strips->patches.size(); ++p) {
      const int id = static_cast<int>(p);
      run.labels.push_back(part_label(*run.strips, *run.flattening, *run.kerf, id));
      run.engravings.push_back(border_labels(*run.strips, *run.flattening, *run.kerf, *run.joints,
                                             id, run.labels.back()));
      if (run.labels.back())
        run.engravings.back().insert(run.engravings.back().begin(), *run.labels.back());
    }
    const LayoutResult& l = *run.layout;
    std::ostringstream os;
    os.precision(3);
    os << outlines.size() << " parts on " << l.sheets << " sheets of "
       << run.options.layout.sheet_width << " x " << run.options.layout.sheet_height
       << " mm, material used " << 100 * l.utilization << "%";
    say(os.str());
    if (!l.unplaced.empty())
      run.warnings.push_back(std::to_string(l.unplaced.size()) +
                             " parts fit no sheet and are missing from cut/ (see layout.unplaced)");
    int unlabelled = 0;
    for (const auto& label : run.labels) unlabelled += label ? 0 : 1;
    if (unlabelled > 0)
      run.warnings.push_back(std::to_string(unlabelled) +
                             " parts are too narrow between kerf cuts for an engraved number");
  });
  if (done_after("layout")) return finish();

  clock.stage("quality", [&] {
    SurfaceDistanceOptions d;
    d.sample_spacing = run.options.quality_sample_spacing * run.target_diagonal;
    run.quality = surface_distance(triangulate(*run.strips), run.input->surface.mesh(), d);
    const SurfaceDistance& q = *run.quality;
    std::ostringstream os;
    os.precision(4);
    os << "strips vs target: Hausdorff " << q.hausdorff << " mm ("
       << 100 * q.hausdorff / run.target_diagonal << "% of diagonal), mean " << q.mean << " mm ("
       << 100 * q.mean / run.target_diagonal << "%), " << q.samples << " samples";
    say(os.str());
  });
  return finish();
}

}  // namespace kerfab

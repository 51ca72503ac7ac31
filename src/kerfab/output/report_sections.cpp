#include "kerfab/output/report_sections.h"

#include <cmath>

namespace kerfab::report {
namespace {

json to_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

template <class T>
json optional_json(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

json summary_json(const MeshSummary& s) {
  json sizes = json::object();
  for (auto [sides, count] : s.face_sizes) sizes[std::to_string(sides)] = count;
  return {{"vertices", s.vertices},
          {"faces", s.faces},
          {"edges", s.edges},
          {"face_sizes", sizes},
          {"boundary_loops", s.boundary_loops},
          {"euler_characteristic", s.euler_characteristic},
          {"bbox_mm", to_json(s.bbox.size())}};
}

}  // namespace

json input_section(const RunInputs& inputs, const std::optional<LoadedInputs>& loaded,
                   const std::optional<PreparedInput>& input) {
  json j;
  j["target"] = inputs.target.string();
  if (loaded) {
    const auto repairs = [](const MeshRepairs& r) {
      return json{{"faces_turned", r.faces_turned},
                  {"vertices_welded", r.vertices_welded},
                  {"duplicate_faces", r.duplicate_faces}};
    };
    j["target_repairs"] = repairs(loaded->target_repairs);
    if (loaded->quad) j["quad_repairs"] = repairs(loaded->quad_repairs);
  }
  if (inputs.quad)
    j["quad"] = inputs.quad->string();
  else if (input && !input->quads_from_target)
    j["quad"] = nullptr;  // a triangle mesh alone: kerfab meshed it (quads; model/quads.obj)
  else
    j["quad"] = inputs.target.string();
  if (input) {
    const PreparedInput& in = *input;
    j["quads"] = in.quad_summary.faces;
    j["bbox_mm"] = to_json(in.target_summary.bbox.size());
    j["scale"] = in.scale;
    j["quads_from_target"] = in.quads_from_target;
    j["target_mesh"] = summary_json(in.target_summary);
    j["quad_mesh"] = summary_json(in.quad_summary);
    j["quad_max_distance_mm"] = in.quad_max_distance;
    j["quad_mean_distance_mm"] = in.quad_mean_distance;
    j["united_solids"] = in.united_solids;
    j["united_surface_gone_mm2"] = in.united_surface_gone;
    j["cavities_left_out"] = in.cavities_left_out;
    j["cavity_area_mm2"] = in.cavity_area;
  }
  return j;
}

json quads_section(const QuadMeshResult& q) {
  json valences = json::object();
  for (auto [v, c] : q.valences) valences[std::to_string(v)] = c;
  return {{"quads", q.quads.n_faces()},
          {"method", q.method},
          {"size_mm", q.size.size},
          {"size_rule",
           {{"reason", q.size.reason},
            {"area_mm2", q.size.area},
            {"bend_curvature_per_mm", q.size.bend_curvature},
            {"ruling_curvature_per_mm", q.size.ruling_curvature},
            {"kerf_size_mm", q.size.kerf_size},
            {"fidelity_size_mm",
             std::isfinite(q.size.fidelity_size) ? json(q.size.fidelity_size) : json(nullptr)},
            {"tube_thickness_mm",
             std::isfinite(q.size.tube_thickness) ? json(q.size.tube_thickness) : json(nullptr)},
            {"tube_size_mm",
             std::isfinite(q.size.tube_size) ? json(q.size.tube_size) : json(nullptr)}}},
          {"remeshed_vertices", q.remeshed_vertices},
          {"lattice_quads", q.lattice_quads},
          {"lattice_triangles", q.lattice_triangles},
          {"triangle_rows", q.triangle_rows},
          {"unpaired_triangles", q.unpaired_triangles},
          {"feature_angle_deg", q.feature_angle * 180 / M_PI},
          {"feature_angle_asked_deg",
           q.feature_angle_asked > 0 ? json(q.feature_angle_asked * 180 / M_PI) : json(nullptr)},
          {"dislocations", q.dislocations},
          {"dislocations_left", q.dislocations_left},
          {"irregular_vertices", q.irregular_vertices},
          {"interior_valences", valences},
          {"feature_edges", q.feature_edges},
          {"feature_length_mm", q.feature_length},
          {"feature_length_on_quad_edges_mm", q.feature_length_on_quads},
          {"max_distance_mm", q.max_distance},
          {"corner_angle_deg", {q.min_corner_angle * 180 / M_PI, q.max_corner_angle * 180 / M_PI}},
          {"corner_deviation_deg", q.mean_corner_deviation * 180 / M_PI},
          {"corners_outside_45_135", q.skewed_corners}};
}

json coarsen_section(const CoarsenResult& c) {
  return {{"quads", c.quads_after},
          {"method", c.changed() ? "given, coarsened" : "given"},
          {"given_quads", c.quads_before},
          {"levels_taken_back", c.levels_taken_back},
          {"rows_collapsed", c.rows_collapsed},
          {"rows_refused", c.rows_refused},
          {"narrow_fraction_before", c.narrow_before},
          {"narrow_fraction_after", c.narrow_after}};
}

json options_section(const RunResult& run, const OutputOptions& output) {
  const PipelineOptions& o = run.options;
  const Material& m = o.material;
  std::size_t guidance_edges = o.bending.guidance.size();
  std::size_t split_edges = o.strips.split_edges.size(), merge_edges = o.strips.merge_edges.size();
  if (run.loaded) {
    guidance_edges += run.loaded->guidance.edges.size();
    split_edges += run.loaded->guidance.split.size();
    merge_edges += run.loaded->guidance.merge.size();
  }
  json j;
  j["size_mm"] = optional_json(o.input.size);
  j["subdivide"] = o.input.subdivide;
  j["quads"] = optional_json(o.quads.quads);
  j["quad_size_mm"] = optional_json(o.quads.quad_size);
  j["quad_feature_angle_deg"] = o.quads.feature_angle * 180 / M_PI;
  j["max_quad_distance_rel"] = o.input.max_quad_distance;
  j["coarsen"] = o.coarsen.enabled;
  j["alignment"] = o.bending.alignment;
  j["edge_samples"] = o.bending.edge_samples;
  j["ilp_time_limit_s"] = o.bending.time_limit_s;
  j["ilp_gap"] = o.bending.relative_gap;
  j["guidance"] = run.inputs.guidance ? json(run.inputs.guidance->string()) : json(nullptr);
  j["guidance_edges"] = guidance_edges;
  j["guidance_split_edges"] = split_edges;
  j["guidance_merge_edges"] = merge_edges;
  j["rulings_per_quad"] = o.strips.rulings_per_quad;
  j["max_ruling_spacing_mm"] = o.strips.max_ruling_spacing;
  j["projection"] = o.strips.projection == Projection::kNormal ? "normal" : "closest";
  j["split_angle_deg"] = o.strips.split_angle * 180 / M_PI;
  j["features_deg"] = o.strips.features ? json(*o.strips.features * 180 / M_PI) : json(nullptr);
  j["flatten_lambda"] = o.flatten.lambda;
  j["flatten_max_iterations"] = o.flatten.max_iterations;
  j["material"] = m.name;
  j["thickness_mm"] = m.thickness;
  j["shear_modulus_mpa"] = m.shear_modulus;
  j["yield_strength_mpa"] =
      std::isfinite(m.yield_strength) ? json(m.yield_strength) : json("infinity");
  j["safety"] = m.safety;
  j["kerf_smoothing_mm"] = optional_json(o.kerf.smoothing);
  j["min_cut_length_mm"] = o.kerf.min_cut_length;
  j["min_cut_spacing_mm"] = o.kerf.min_cut_spacing;
  j["bridge_mm"] = o.kerf.bridge;
  j["kerf_margin_mm"] = o.kerf.margin;
  j["constant_density"] = optional_json(o.kerf.constant_cuts_per_quad);
  j["cut_speed_mm_s"] = o.machine.speed;
  j["per_cut_s"] = o.machine.per_cut;
  j["protrusion_mm"] = o.joints.protrusion;
  j["tooth_width_mm"] = o.joints.tooth_width;
  j["min_tooth_depth_mm"] = o.joints.min_depth;
  j["tab_misfit_mm"] = o.joints.tab_misfit;
  j["glue_tab_mm"] = o.joints.glue_tab;
  j["score_rulings"] = o.joints.score_rulings;
  j["kerf_width_mm"] = o.machine.kerf_width;
  j["stroke_mm"] = output.style.stroke;
  j["cut_colour"] = output.style.cut;
  j["engrave_colour"] = output.style.engrave;
  j["mountain_colour"] = output.style.mountain;
  j["valley_colour"] = output.style.valley;
  j["quality_sample_spacing_rel"] = o.quality_sample_spacing;
  j["row_baseline"] = o.row_baseline;
  j["stop_after"] = optional_json(o.stop_after);
  return j;
}

json bending_section(const BendingResult& b, const BendingOptions& options) {
  int kinds[3] = {0, 0, 0};
  for (const auto& q : b.quads) ++kinds[static_cast<int>(q.kind)];
  const double w_max = options.alignment > 0 ? b.w0 / options.alignment : 0.0;
  return {{"edges", b.bendable.size()},
          {"bendable", b.bendable_count},
          {"objective", b.objective},
          {"bound", b.bound},
          {"status", to_string(b.status)},
          {"solve_seconds", b.solve_seconds},
          {"w0", b.w0},
          {"w0_rel", options.alignment},
          {"w_max", w_max},
          {"interior_edges", b.interior_edges},
          {"aligned_edges", b.aligned_edges},
          {"aligned_fraction", b.aligned_fraction},
          {"quads_bending", kinds[static_cast<int>(QuadKind::kBending)]},
          {"quads_one_sided", kinds[static_cast<int>(QuadKind::kOneSided)]},
          {"quads_rigid", kinds[static_cast<int>(QuadKind::kRigid)]},
          {"program",
           {{"odd_vertices", b.odd_vertices},
            {"seam_edges", b.seam_edges},
            {"seam_pairing_optimal", b.seam_pairing_optimal},
            {"start_objective", b.start_objective},
            {"ring_cuts", b.ring_cuts},
            {"separated_cuts", b.separated_cuts},
            {"cut_rounds", b.cut_rounds},
            {"slack_limits", b.slack_limits},
            {"relaxation_bound", b.relaxation_bound},
            {"cut_seconds", b.cut_seconds}}}};
}

json strips_section(const Strips& s, int overlap_splits,
                    const std::optional<RowBaseline>& baseline) {
  int seg_min = s.quad_segments.empty() ? 0 : s.quad_segments.front(), seg_max = seg_min;
  for (int k : s.quad_segments) seg_min = std::min(seg_min, k), seg_max = std::max(seg_max, k);
  json patches = json::array();
  for (const Patch& p : s.patches)
    patches.push_back({{"quads", p.all_quads().size()},
                       {"rows", p.rows()},
                       {"facet", p.flat},
                       {"sub_quads", p.all_faces().size()},
                       {"chain", p.chain},
                       {"loop_cut", p.loop_cut}});
  json j = {{"strips", static_cast<int>(s.patches.size()) - overlap_splits},
            {"patches", s.patches.size()},
            {"chains", s.chains},
            {"closed_loops_cut", s.closed_loops},
            {"split_borders", s.split_borders},
            {"sub_quads", s.faces.size()},
            {"vertices", s.vertices.size()},
            {"t_junction_vertices", s.t_junctions},
            {"segments_per_quad_min", seg_min},
            {"segments_per_quad_max", seg_max},
            {"ray_fallbacks", s.ray_fallbacks},
            {"feature_vertices", s.feature_vertices},
            {"max_fold_in_patch_deg", s.max_fold * 180 / M_PI},
            {"patch_list", patches}};
  if (baseline) {
    j["quad_rows"] = baseline->quad_rows;
    j["naive_row_strips"] = baseline->strips;
  }
  return j;
}

json flatten_section(const CuttablePatches& c, double diagonal) {
  const Flattening& f = c.flattening;
  json patches = json::array();
  for (std::size_t p = 0; p < f.patches.size(); ++p) {
    const PatchFlattening& pf = f.patches[p];
    patches.push_back({{"patch", p},
                       {"iterations", pf.iterations},
                       {"initial_energy", pf.initial_energy},
                       {"energy", pf.energy},
                       {"status", pf.converged ? "converged" : "iteration_limit"},
                       {"max_angle_error_deg", pf.max_angle_error * 180 / M_PI},
                       {"max_border_length_error_rel", pf.max_border_length_error_rel},
                       {"inverted_quads", pf.inverted_quads},
                       {"outline_simple", pf.outline_simple},
                       {"area_3d_mm2", pf.area_3d},
                       {"area_2d_mm2", pf.area_2d}});
  }
  json borders = json::array();
  for (const SharedBorder& b : f.borders)
    borders.push_back({{"patches", b.patches},
                       {"pieces", b.pieces},
                       {"length_3d_mm", b.length_3d},
                       {"length_2d_mm", b.length_2d}});
  json j = {{"max_angle_error_deg", f.max_angle_error * 180 / M_PI},
            {"max_border_length_error_rel", f.max_border_length_error_rel},
            {"max_mating_mismatch_rel", f.max_mating_mismatch_rel},
            {"max_shared_border_mismatch_rel", f.max_shared_border_mismatch_rel},
            {"inverted_quads", f.inverted_quads},
            {"non_simple_outlines", f.non_simple_outlines},
            {"overlap_splits", c.overlap_splits},
            {"distortion_splits", c.distortion_splits},
            {"unconverged_patches", f.unconverged},
            {"patches", patches},
            {"borders", borders}};
  if (c.deformation) {
    j["deformed_3d_hausdorff_mm"] = c.deformation->hausdorff;
    j["deformed_3d_hausdorff_rel"] = c.deformation->hausdorff / diagonal;
  }
  return j;
}

json joints_section(const Joints& jt, const Material& material) {
  json samples = json::array();
  int blocked = 0, shallow = 0;
  for (const BorderJoint& b : jt.borders) {
    blocked += b.blocked, shallow += b.shallow;
    for (const JointInterval& in : b.intervals)
      samples.push_back({{"fold_deg", in.fold * 180 / M_PI},
                         {"tip_mm", in.offsets.tip},
                         {"slot_mm", in.offsets.slot},
                         {"tooth", in.owner >= 0},
                         {"joint", to_string(in.kind)},
                         {"patches", b.patches},
                         {"edge", b.edge},
                         {"s_mm", {in.s0, in.s1}}});
  }
  int tab_roots = 0, rulings = 0, diagonals = 0, mountain = 0;
  for (const PartOutline& part : jt.parts)
    for (const FoldLine& f : part.folds) {
      (f.kind == FoldLine::Kind::kRuling     ? rulings
       : f.kind == FoldLine::Kind::kDiagonal ? diagonals
                                             : tab_roots) += 1;
      mountain += f.mountain() ? 1 : 0;
    }
  const json folds = {{"tab_roots", tab_roots},
                      {"rulings", rulings},
                      {"diagonals", diagonals},
                      {"mountain", mountain},
                      {"valley", tab_roots + rulings + diagonals - mountain}};
  json borders = json::array();
  int flared = 0;
  for (std::size_t i = 0; i < jt.borders.size(); ++i) {
    const BorderJoint& b = jt.borders[i];
    const int flares = i < jt.flares.size() ? static_cast<int>(jt.flares[i].size()) : 0;
    flared += flares;
    borders.push_back({{"edge", b.edge},
                       {"edges", b.edges},
                       {"patches", b.patches},
                       {"length_mm", b.length},
                       {"joint", b.kind()},
                       {"teeth", b.teeth - b.tabs},
                       {"tabs", b.tabs},
                       {"glue_tabs", b.glue},
                       {"dovetail_sides", flares}});
    if (b.kind() == "none" && b.free_room >= 0) borders.back()["free_room_mm"] = b.free_room;
    if (!b.joined_through.empty()) borders.back()["joined_through"] = b.joined_through;
    if (!b.joined_through_far.empty()) borders.back()["joined_through_far"] = b.joined_through_far;
  }
  return {{"thickness_mm", material.thickness},
          {"teeth", jt.teeth - jt.tabs},
          {"tabs", jt.tabs},
          {"borders_without_joint", jt.borders_without_joint},
          {"stubs_joined_at_corners", jt.stubs_joined_at_corners},
          {"tab_length_mm", jt.tab_length},
          {"glue_tabs", jt.glue_tabs},
          {"glue_length_mm", jt.glue_length},
          {"fold_lines", folds},
          {"dovetail_sides", flared},
          {"borders", borders},
          {"border_pieces", jt.borders.size()},
          {"border_length_mm", jt.border_length},
          {"toothed_length_mm", jt.toothed_length},
          {"intervals_too_shallow", shallow},
          {"intervals_in_collision", blocked},
          {"repaired_parts", jt.repaired_parts},
          {"thin_neck_parts", jt.thin_neck_parts},
          {"slit_parts", jt.slit_parts},
          {"lost_area_mm2", jt.lost_area},
          {"largest_lost_piece_mm2", jt.largest_lost_piece},
          {"samples", samples}};
}

json kerf_section(const KerfResult& k, const KerfOptions& options) {
  json patches = json::array();
  for (std::size_t p = 0; p < k.patches.size(); ++p)
    patches.push_back({{"patch", p},
                       {"cuts", k.patches[p].cuts.size()},
                       {"min_spacing_mm", k.patches[p].min_spacing},
                       {"stress_ratio", k.patches[p].stress_ratio}});
  json critical = json::array();
  for (const auto& c : k.critical)
    critical.push_back({{"patch", c.patch},
                        {"position_mm", 0.5 * (c.start + c.end)},
                        {"from_mm", c.start},
                        {"to_mm", c.end},
                        {"cuts", c.cuts},
                        {"spacing_mm", c.spacing},
                        {"stress_ratio", c.stress_ratio},
                        {"cause", to_string(c.cause)},
                        {"fit_factor", c.fit_factor},
                        {"quads", c.quads},
                        {"centre_mm", to_json(c.centre)}});
  return {{"cuts", k.cuts},
          {"cut_length_mm", k.cut_length},
          {"smoothing_mm", k.smoothing},
          {"critical_regions", k.critical.size()},
          {"skipped_cuts", k.skipped},
          {"skipped_by_options", k.skipped_by_options},
          {"critical", critical},
          {"mode", options.constant_cuts_per_quad ? "constant" : "adaptive"},
          {"max_cuts_per_quad", k.max_cuts_per_quad},
          {"patches", patches}};
}

json cutting_section(const CuttingEstimate& c, const Machine& machine) {
  return {{"total_cut_length_mm", c.total_length()},
          {"outline_length_mm", c.outline_length},
          {"kerf_length_mm", c.kerf_length},
          {"paths", c.paths},
          {"estimated_minutes", c.minutes},
          {"machine", {{"speed_mm_s", machine.speed}, {"per_cut_s", machine.per_cut}}}};
}

json resolve_section(const ResolveResult& r, const ResolveOptions& options) {
  json changes = json::array();
  for (const RegionChange& c : r.changes)
    changes.push_back({{"action", c.action},
                       {"centre_mm", to_json(c.centre)},
                       {"quads", c.quads},
                       {"spacing_mm", c.spacing},
                       {"stress_ratio", c.stress_ratio},
                       {"size_factor", c.size_factor},
                       {"local_distance_mm", c.local_distance},
                       {"reason", c.reason}});
  json materials = json::array();
  for (const MaterialSize& m : r.materials)
    materials.push_back(
        {{"material", m.material}, {"thickness_mm", m.thickness}, {"min_size_mm", m.size_mm}});
  return {{"enabled", options.enabled},
          {"rounds", r.rounds},
          {"time_limit_s", options.time_limit},
          {"time_limited", r.time_limited},
          {"critical_before", r.critical_before},
          {"critical_after", r.critical_after},
          {"narrow_after", r.narrow_after},
          {"narrow_min_size_mm", r.narrow_size_mm},
          {"small_parts_after", r.small_parts_after},
          {"distorted_parts_after", r.distorted_parts_after},
          {"unsized_parts_after", r.unsized_parts_after},
          {"unresolved_parts", r.unresolved_parts},
          {"parts_before", r.parts_before},
          {"parts_after", r.parts_after},
          {"minutes_before", r.minutes_before},
          {"minutes_after", r.minutes_after},
          {"size_mm", r.current_size_mm},
          {"min_size_mm", r.min_size_mm},
          {"small_parts_min_size_mm", r.small_parts_size_mm},
          {"gone_parts", r.gone_parts},
          {"gone_parts_min_size_mm", r.gone_parts_size_mm},
          {"materials", materials},
          {"added",
           {{"stiff_edges", r.added.edges.size()},
            {"split_edges", r.added.split.size()},
            {"merge_edges", r.added.merge.size()},
            {"facets", r.added.facets.size()}}},
          {"changes", changes}};
}

json layout_section(const LayoutResult& l, const LayoutOptions& options,
                    const SheetFormats& formats, int oversize_splits) {
  json parts = json::array();
  for (std::size_t i = 0; i < l.placements.size(); ++i)
    parts.push_back({{"part", i},
                     {"sheet", l.sheet_number(static_cast<int>(i))},
                     {"angle_deg", l.placements[i].angle * 180 / M_PI},
                     {"offset_mm", {l.placements[i].offset.x(), l.placements[i].offset.y()}},
                     {"label", l.labels.size() > i && l.labels[i].has_value()}});
  json assembly = json::array();
  for (std::size_t p = 0; p < l.neighbours.size(); ++p) {
    json list = json::array();
    for (const auto& [q, length] : l.neighbours[p])
      list.push_back({{"part", q}, {"length_mm", length}});
    assembly.push_back(
        {{"part", p}, {"sheet", l.sheet_number(static_cast<int>(p))}, {"neighbours", list}});
  }
  json offcuts = json::array(), sizes = json::array();
  for (const Vec2& o : options.offcuts) offcuts.push_back({o.x(), o.y()});
  for (const Vec2& size : l.sheet_sizes) sizes.push_back({size.x(), size.y()});
  json written = json::array();
  if (formats.svg) written.push_back("svg");
  if (formats.dxf) written.push_back("dxf");
  if (formats.pdf) written.push_back("pdf");
  return {
      {"sheets", l.sheets},
      {"sheet_mm", {options.sheet_width, options.sheet_height}},
      {"offcuts_mm", offcuts},
      {"sheet_sizes_mm", sizes},
      {"margin_mm", options.margin},
      {"spacing_mm", options.spacing},
      {"utilization", l.utilization},
      {"sheet_utilization", l.sheet_utilization},
      {"sheets_lower_bound", l.sheets_lower_bound},
      {"sheets_lower_bound_spaced", l.sheets_lower_bound_spaced},
      {"unplaced", l.unplaced},
      {"empty", l.empty},
      {"oversize_splits", oversize_splits},
      {"formats", written},
      {"parts", parts},
      {"assembly", assembly},
      {"border_labels", {{"placed", l.border_labels_placed}, {"wanted", l.border_labels_wanted}}}};
}

json split_to_fit_section(const SplitToFitResult& s) {
  json edges = json::array();
  for (const auto& e : s.split_edges) edges.push_back({e[0], e[1]});
  return {{"tried", s.tried},
          {"saved_sheets", s.sheets_before - s.sheets_after},
          {"sheets_before", s.sheets_before},
          {"sheets_after", s.sheets_after},
          {"parts_before", s.parts_before},
          {"parts_after", s.parts_after},
          {"minutes_before", s.minutes_before},
          {"minutes_after", s.minutes_after},
          {"strips_split", s.strips_split},
          {"rings_recut", s.rings_recut},
          {"min_length_mm", s.min_length_mm},
          {"split_edges", edges},
          {"attempts", s.attempts},
          {"screened", s.screened},
          {"seconds", s.seconds},
          {"why_not", s.why_not}};
}

json assembly_section(const AssemblyPlan& a, const LayoutResult& l) {
  json order = json::array(), steps = json::array();
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    const AssemblyStep& s = a.steps[k];
    order.push_back(s.part);
    json joins = json::array();
    for (const PartContact& c : s.joins)
      joins.push_back({{"part", c.part}, {"length_mm", c.length}, {"toothed_mm", c.toothed}});
    steps.push_back({{"step", k + 1},
                     {"part", s.part},
                     {"sheet", l.sheet_number(s.part)},
                     {"joins", joins},
                     {"held_mm", s.held},
                     {"new_piece", s.new_piece},
                     {"closing", s.closing}});
  }
  return {{"rule", kAssemblyRule},
          {"pieces", a.pieces},
          {"order", order},
          {"steps", steps},
          {"guide", "assembly/index.html"}};
}

json quality_section(const SurfaceDistance& q, double diagonal) {
  const double d = diagonal > 0 ? diagonal : 1.0;
  return {{"hausdorff_rel", q.hausdorff / d},
          {"mean_distance_rel", q.mean / d},
          {"hausdorff_mm", q.hausdorff},
          {"mean_distance_mm", q.mean},
          {"strips_to_target_max_mm", q.a_to_b_max},
          {"strips_to_target_mean_mm", q.a_to_b_mean},
          {"target_to_strips_max_mm", q.b_to_a_max},
          {"target_to_strips_mean_mm", q.b_to_a_mean},
          {"strips_to_target_max_at_mm", {q.a_to_b_at.x(), q.a_to_b_at.y(), q.a_to_b_at.z()}},
          {"target_to_strips_max_at_mm", {q.b_to_a_at.x(), q.b_to_a_at.y(), q.b_to_a_at.z()}},
          {"target_diagonal_mm", diagonal},
          {"sample_spacing_mm", q.spacing},
          {"hausdorff_upper_bound_mm", q.hausdorff_upper_bound()},
          {"hausdorff_gap_mm", q.hausdorff_gap},
          {"mean_error_estimate_mm", q.mean_error_estimate},
          {"samples", q.samples}};
}

json clearance_section(const ShellClearance& c) {
  json contacts = json::array();
  for (const ClearanceContact& k : c.contacts)
    contacts.push_back({{"parts", {k.part_a, k.part_b}},
                        {"gap_mm", k.gap},
                        {"area_mm2", k.area},
                        {"inside_out", k.inside_out},
                        {"at_mm", {k.at.x(), k.at.y(), k.at.z()}},
                        {"across_mm", {k.across.x(), k.across.y(), k.across.z()}}});
  return {{"thickness_mm", c.thickness},
          {"sample_spacing_mm", c.spacing},
          {"samples", c.samples},
          {"min_gap_mm", c.min_gap()},
          {"min_thin_gap_mm", c.min_thin_gap()},
          {"size_factor", c.size_factor()},
          {"area_mm2", c.area()},
          {"contacts", contacts}};
}

json timings_section(const std::vector<StageTiming>& timings, double total_seconds) {
  json j = json::object();
  for (const auto& t : timings) j[t.stage] = t.seconds;
  j["total"] = total_seconds;
  return j;
}

}  // namespace kerfab::report

#include "kerfab/io/report.h"

#include <cmath>

#include "kerfab/io/assembly_page.h"

namespace kerfab {
namespace {

nlohmann::json to_json(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json options_json(const RunResult& run) {
  const PipelineOptions& o = run.options;
  nlohmann::json j;
  j["size_mm"] = o.input.size ? nlohmann::json(*o.input.size) : nlohmann::json(nullptr);
  j["subdivide"] = o.input.subdivide;
  j["max_quad_distance_rel"] = o.input.max_quad_distance;
  j["alignment"] = o.bending.alignment;
  j["edge_samples"] = o.bending.edge_samples;
  j["ilp_time_limit_s"] = o.bending.time_limit_s;
  j["ilp_gap"] = o.bending.relative_gap;
  j["guidance"] =
      run.inputs.guidance ? nlohmann::json(run.inputs.guidance->string()) : nlohmann::json(nullptr);
  j["guidance_edges"] = o.bending.guidance.size();
  j["rulings_per_quad"] = o.strips.rulings_per_quad;
  j["max_ruling_spacing_mm"] = o.strips.max_ruling_spacing;
  j["projection"] = o.strips.projection == Projection::kNormal ? "normal" : "closest";
  j["split_angle_deg"] = o.strips.split_angle * 180 / M_PI;
  j["features_deg"] =
      o.strips.features ? nlohmann::json(*o.strips.features * 180 / M_PI) : nlohmann::json(nullptr);
  j["flatten_lambda"] = o.flatten.lambda;
  j["flatten_max_iterations"] = o.flatten.max_iterations;
  j["material"] = o.kerf.material.name;
  j["thickness_mm"] = o.kerf.material.thickness;
  j["shear_modulus_mpa"] = o.kerf.material.shear_modulus;
  j["yield_strength_mpa"] = std::isfinite(o.kerf.material.yield_strength)
                                ? nlohmann::json(o.kerf.material.yield_strength)
                                : nlohmann::json("infinity");
  j["safety"] = o.kerf.material.safety;
  j["kerf_smoothing_mm"] = o.kerf.smoothing;
  j["min_cut_spacing_mm"] = o.kerf.min_cut_spacing;
  j["bridge_mm"] = o.kerf.bridge;
  j["kerf_margin_mm"] = o.kerf.margin;
  j["constant_density"] = o.kerf.constant_cuts_per_quad
                              ? nlohmann::json(*o.kerf.constant_cuts_per_quad)
                              : nlohmann::json(nullptr);
  j["cut_speed_mm_s"] = o.machine.speed;
  j["per_cut_s"] = o.machine.per_cut;
  j["protrusion_mm"] = o.joints.protrusion;
  j["tooth_width_mm"] = o.joints.tooth_width;
  j["min_tooth_depth_mm"] = o.joints.min_depth;
  j["kerf_width_mm"] = o.joints.kerf_width;
  j["stroke_mm"] = o.style.stroke;
  j["cut_colour"] = o.style.cut;
  j["engrave_colour"] = o.style.engrave;
  j["quality_sample_spacing_rel"] = o.quality_sample_spacing;
  j["stop_after"] = o.stop_after ? nlohmann::json(*o.stop_after) : nlohmann::json(nullptr);
  return j;
}

nlohmann::json summary_json(const MeshSummary& s) {
  nlohmann::json sizes = nlohmann::json::object();
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

nlohmann::json make_report(const RunResult& run) {
  nlohmann::json r;
  r["version"] = 1;
  r["status"] = "ok";
  r["units"] = "mm";
  nlohmann::json input;
  input["target"] = run.inputs.target.string();
  input["quad"] = run.inputs.quad ? run.inputs.quad->string() : run.inputs.target.string();
  if (run.input) {
    const PreparedInput& in = *run.input;
    input["quads"] = in.quad_summary.faces;
    input["bbox_mm"] = to_json(in.target_summary.bbox.size());
    input["scale"] = in.scale;
    input["quads_from_target"] = in.quads_from_target;
    input["target_mesh"] = summary_json(in.target_summary);
    input["quad_mesh"] = summary_json(in.quad_summary);
    input["quad_max_distance_mm"] = in.quad_max_distance;
    input["quad_mean_distance_mm"] = in.quad_mean_distance;
  }
  r["input"] = input;
  r["options"] = options_json(run);
  if (run.bending) {
    const BendingResult& b = *run.bending;
    int kinds[3] = {0, 0, 0};
    for (const auto& q : b.quads) ++kinds[static_cast<int>(q.kind)];
    const double w_max =
        run.options.bending.alignment > 0 ? b.w0 / run.options.bending.alignment : 0.0;
    r["bending"] = {{"edges", b.bendable.size()},
                    {"bendable", b.bendable_count},
                    {"objective", b.objective},
                    {"bound", b.bound},
                    {"status", to_string(b.status)},
                    {"solve_seconds", b.solve_seconds},
                    {"w0", b.w0},
                    {"w0_rel", run.options.bending.alignment},
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
                      {"relaxation_bound", b.relaxation_bound},
                      {"cut_seconds", b.cut_seconds}}}};
  }
  if (run.strips) {
    const Strips& s = *run.strips;
    int seg_min = s.quad_segments.empty() ? 0 : s.quad_segments.front(), seg_max = seg_min;
    for (int k : s.quad_segments) seg_min = std::min(seg_min, k), seg_max = std::max(seg_max, k);
    nlohmann::json patches = nlohmann::json::array();
    for (const Patch& p : s.patches)
      patches.push_back({{"quads", p.quads.size()},
                         {"sub_quads", p.faces.size()},
                         {"chain", p.chain},
                         {"loop_cut", p.loop_cut}});
    r["strips"] = {{"strips", static_cast<int>(s.patches.size()) - run.overlap_splits},
                   {"patches", s.patches.size()},
                   {"chains", s.chains},
                   {"closed_loops_cut", s.closed_loops},
                   {"split_borders", s.split_borders},
                   {"quad_rows", run.quad_rows},
                   {"naive_row_strips", run.naive_row_strips},
                   {"sub_quads", s.faces.size()},
                   {"vertices", s.vertices.size()},
                   {"t_junction_vertices", s.t_junctions},
                   {"segments_per_quad_min", seg_min},
                   {"segments_per_quad_max", seg_max},
                   {"ray_fallbacks", s.ray_fallbacks},
                   {"feature_vertices", s.feature_vertices},
                   {"max_fold_in_patch_deg", s.max_fold * 180 / M_PI},
                   {"patch_list", patches}};
  }
  if (run.flattening) {
    const Flattening& f = *run.flattening;
    nlohmann::json patches = nlohmann::json::array();
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
    nlohmann::json borders = nlohmann::json::array();
    for (const SharedBorder& b : f.borders)
      borders.push_back({{"patches", b.patches},
                         {"pieces", b.pieces},
                         {"length_3d_mm", b.length_3d},
                         {"length_2d_mm", b.length_2d}});
    r["flatten"] = {{"max_angle_error_deg", f.max_angle_error * 180 / M_PI},
                    {"max_border_length_error_rel", f.max_border_length_error_rel},
                    {"max_mating_mismatch_rel", f.max_mating_mismatch_rel},
                    {"max_shared_border_mismatch_rel", f.max_shared_border_mismatch_rel},
                    {"inverted_quads", f.inverted_quads},
                    {"non_simple_outlines", f.non_simple_outlines},
                    {"overlap_splits", run.overlap_splits},
                    {"unconverged_patches", f.unconverged},
                    {"patches", patches},
                    {"borders", borders}};
    if (run.flatten_mimic) {
      const double d = run.target_diagonal;
      r["flatten"]["deformed_3d_hausdorff_mm"] = run.flatten_mimic->hausdorff;
      r["flatten"]["deformed_3d_hausdorff_rel"] = run.flatten_mimic->hausdorff / d;
    }
  }
  if (run.joints) {
    const Joints& jt = *run.joints;
    nlohmann::json samples = nlohmann::json::array();
    int blocked = 0, shallow = 0;
    for (const BorderJoint& b : jt.borders) {
      blocked += b.blocked, shallow += b.shallow;
      for (const JointInterval& in : b.intervals)
        samples.push_back({{"fold_deg", in.fold * 180 / M_PI},
                           {"tip_mm", in.offsets.tip},
                           {"slot_mm", in.offsets.slot},
                           {"tooth", in.owner >= 0},
                           {"patches", b.patches},
                           {"edge", b.edge},
                           {"s_mm", {in.s0, in.s1}}});
    }
    r["joints"] = {{"thickness_mm", run.options.kerf.material.thickness},
                   {"teeth", jt.teeth},
                   {"border_pieces", jt.borders.size()},
                   {"border_length_mm", jt.border_length},
                   {"toothed_length_mm", jt.toothed_length},
                   {"intervals_too_shallow", shallow},
                   {"intervals_in_collision", blocked},
                   {"repaired_parts", jt.repaired_parts},
                   {"samples", samples}};
  }
  if (run.kerf) {
    const KerfResult& k = *run.kerf;
    nlohmann::json patches = nlohmann::json::array();
    for (std::size_t p = 0; p < k.patches.size(); ++p)
      patches.push_back({{"patch", p},
                         {"cuts", k.patches[p].cuts.size()},
                         {"min_spacing_mm", k.patches[p].min_spacing}});
    nlohmann::json critical = nlohmann::json::array();
    for (const auto& c : k.critical)
      critical.push_back({{"patch", c.patch},
                          {"position_mm", 0.5 * (c.start + c.end)},
                          {"from_mm", c.start},
                          {"to_mm", c.end},
                          {"cuts", c.cuts},
                          {"spacing_mm", c.spacing}});
    r["kerf"] = {{"cuts", k.cuts},
                 {"cut_length_mm", k.cut_length},
                 {"critical_regions", k.critical.size()},
                 {"critical", critical},
                 {"mode", run.options.kerf.constant_cuts_per_quad ? "constant" : "adaptive"},
                 {"max_cuts_per_quad", k.max_cuts_per_quad},
                 {"patches", patches}};
    const int paths = k.cuts + static_cast<int>(run.joints->parts.size());
    r["cutting"] = {
        {"total_cut_length_mm", k.cut_length + run.outline_length},
        {"outline_length_mm", run.outline_length},
        {"kerf_length_mm", k.cut_length},
        {"paths", paths},
        {"estimated_minutes",
         cutting_minutes(k.cut_length + run.outline_length, paths, run.options.machine)},
        {"machine",
         {{"speed_mm_s", run.options.machine.speed}, {"per_cut_s", run.options.machine.per_cut}}}};
  }
  if (run.layout) {
    const LayoutResult& l = *run.layout;
    nlohmann::json parts = nlohmann::json::array();
    for (std::size_t i = 0; i < l.placements.size(); ++i)
      parts.push_back({{"part", i},
                       {"sheet", l.placements[i].sheet + 1},
                       {"angle_deg", l.placements[i].angle * 180 / M_PI},
                       {"offset_mm", {l.placements[i].offset.x(), l.placements[i].offset.y()}},
                       {"label", run.labels.size() > i && run.labels[i].has_value()}});
    r["layout"] = {{"sheets", l.sheets},
                   {"sheet_mm", {run.options.layout.sheet_width, run.options.layout.sheet_height}},
                   {"margin_mm", run.options.layout.margin},
                   {"spacing_mm", run.options.layout.spacing},
                   {"utilization", l.utilization},
                   {"unplaced", l.unplaced},
                   {"oversize_splits", run.oversize_splits},
                   {"formats",
                    [&] {
                      nlohmann::json f = nlohmann::json::array();
                      if (run.options.formats.svg) f.push_back("svg");
                      if (run.options.formats.dxf) f.push_back("dxf");
                      if (run.options.formats.pdf) f.push_back("pdf");
                      return f;
                    }()},
                   {"parts", parts},
                   {"assembly", make_assembly_json(run)},
                   {"border_labels", [&] {
                      int placed = 0, wanted = 0;
                      const auto neighbours = part_neighbours(run);
                      for (std::size_t p = 0; p < neighbours.size(); ++p) {
                        wanted += static_cast<int>(neighbours[p].size() - neighbours[p].count(p));
                        if (p < run.engravings.size())
                          for (const auto& label : run.engravings[p])
                            placed += label.text[0] == '-' ? 1 : 0;
                      }
                      return nlohmann::json{{"placed", placed}, {"wanted", wanted}};
                    }()}};
  }
  if (run.quality) {
    const SurfaceDistance& q = *run.quality;
    const double d = run.target_diagonal > 0 ? run.target_diagonal : 1.0;
    r["quality"] = {{"hausdorff_rel", q.hausdorff / d},
                    {"mean_distance_rel", q.mean / d},
                    {"hausdorff_mm", q.hausdorff},
                    {"mean_distance_mm", q.mean},
                    {"strips_to_target_max_mm", q.a_to_b_max},
                    {"strips_to_target_mean_mm", q.a_to_b_mean},
                    {"target_to_strips_max_mm", q.b_to_a_max},
                    {"target_to_strips_mean_mm", q.b_to_a_mean},
                    {"target_diagonal_mm", run.target_diagonal},
                    {"samples", q.samples}};
  }
  nlohmann::json timings = nlohmann::json::object();
  for (const auto& t : run.timings) timings[t.stage] = t.seconds;
  timings["total"] = run.total_seconds;
  r["timings_s"] = timings;
  r["warnings"] = run.warnings;
  return r;
}

nlohmann::json make_failure_report(int exit_code, const std::string& kind,
                                   const std::string& message) {
  return {{"version", 1},
          {"status", "failed"},
          {"error", {{"exit_code", exit_code}, {"kind", kind}, {"message", message}}}};
}

nlohmann::json make_bending_dump(const PolyMesh& quads, const BendingResult& b) {
  nlohmann::json j;
  nlohmann::json vertices = nlohmann::json::array();
  for (auto v : quads.vertices()) vertices.push_back(to_json(to_eigen(quads.point(v))));
  nlohmann::json faces = nlohmann::json::array();
  for (auto f : quads.faces()) faces.push_back(quad_vertices(quads, f));
  nlohmann::json edges = nlohmann::json::array();
  for (auto e : quads.edges()) {
    const auto h = quads.halfedge_handle(e, 0);
    edges.push_back({{"v", {quads.from_vertex_handle(h).idx(), quads.to_vertex_handle(h).idx()}},
                     {"weight", b.variance[e.idx()] + b.w0},
                     {"variance", b.variance[e.idx()]},
                     {"bendable", b.bendable[e.idx()] != 0}});
  }
  nlohmann::json quad_classes = nlohmann::json::array();
  for (const auto& q : b.quads)
    quad_classes.push_back({{"kind", to_string(q.kind)}, {"axis", q.axis}});
  j["vertices"] = vertices;
  j["quads"] = faces;
  j["edges"] = edges;
  j["quad_bending"] = quad_classes;
  j["w0"] = b.w0;
  j["objective"] = b.objective;
  j["bound"] = b.bound;
  j["status"] = to_string(b.status);
  return j;
}

nlohmann::json make_parts_dump(const RunResult& run) {
  auto poly = [](const Polygon2& p) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& v : p) a.push_back({v.x(), v.y()});
    return a;
  };
  nlohmann::json parts = nlohmann::json::array();
  for (std::size_t i = 0; i < run.joints->parts.size(); ++i) {
    const PartOutline& part = run.joints->parts[i];
    nlohmann::json teeth = nlohmann::json::array();
    for (const auto& sp : part.spans)
      if (sp.tooth) teeth.push_back(poly(sp.region));
    nlohmann::json kerf = nlohmann::json::array();
    if (run.kerf)
      for (const auto& c : run.kerf->patches[i].cuts)
        kerf.push_back({c.a.x(), c.a.y(), c.b.x(), c.b.y()});
    parts.push_back({{"part", i},
                     {"kerf", kerf},
                     {"designed", poly(part.designed)},
                     {"cut", poly(part.cut)},
                     {"teeth", teeth},
                     {"repaired", part.repaired}});
  }
  return {{"units", "mm"}, {"kerf_width_mm", run.options.joints.kerf_width}, {"parts", parts}};
}

}  // namespace kerfab

#include "kerfab/output/report.h"

#include "kerfab/output/report_sections.h"

namespace kerfab {

using report::json;

std::string report_json(const RunResult& run, const OutputOptions& output) {
  const double diagonal = run.input ? run.input->target_diagonal : 0.0;
  json r;
  r["version"] = 1;
  r["status"] = "ok";
  r["units"] = "mm";
  r["input"] = report::input_section(run.inputs, run.loaded, run.input);
  r["options"] = report::options_section(run, output);
  if (run.quads) r["quads"] = report::quads_section(*run.quads);
  if (run.coarsened) r["quads"] = report::coarsen_section(*run.coarsened);
  if (run.bending) r["bending"] = report::bending_section(*run.bending, run.options.bending);
  if (run.strips)
    r["strips"] = report::strips_section(run.final_strips(),
                                         run.flat ? run.flat->overlap_splits : 0, run.baseline);
  if (run.flat) r["flatten"] = report::flatten_section(*run.flat, diagonal);
  if (run.joints) r["joints"] = report::joints_section(*run.joints, run.options.material);
  if (run.kerf) {
    r["kerf"] = report::kerf_section(*run.kerf, run.options.kerf);
    r["cutting"] = report::cutting_section(run.kerf->cutting, run.options.machine);
  }
  if (run.resolve) r["resolve"] = report::resolve_section(*run.resolve, run.options.resolve);
  if (run.layout)
    r["layout"] = report::layout_section(*run.layout, run.options.layout, output.formats,
                                         run.flat->oversize_splits);
  if (run.layout && run.split_to_fit)
    r["layout"]["split_to_fit"] = report::split_to_fit_section(*run.split_to_fit);
  if (run.assembly && run.layout)
    r["assembly"] = report::assembly_section(*run.assembly, *run.layout);
  if (run.quality) r["quality"] = report::quality_section(*run.quality, diagonal);
  if (run.quality && run.clearance)
    r["quality"]["clearance"] = report::clearance_section(*run.clearance);
  // A run that dropped geometry does not call itself ok: pieces of parts that fell apart, parts
  // that fit no sheet.
  json incomplete = json::array();
  if (run.joints && run.joints->repaired_parts > 0)
    incomplete.push_back(std::to_string(run.joints->repaired_parts) +
                         " parts fell apart when cut; only their largest piece is kept");
  if (run.layout && run.layout->too_large() > 0)
    incomplete.push_back(std::to_string(run.layout->too_large()) +
                         " parts fit no sheet and are missing from cut/");
  if (run.layout && !run.layout->empty.empty())
    incomplete.push_back(std::to_string(run.layout->empty.size()) +
                         " parts have nothing left once their slots and mitres are cut");
  if (!incomplete.empty()) {
    r["status"] = "incomplete";
    r["incomplete"] = incomplete;
  }
  r["timings_s"] = report::timings_section(run.timings, run.total_seconds);
  r["warnings"] = run.warnings;
  return r.dump(2, ' ', false, json::error_handler_t::replace) + "\n";  // paths need not be UTF-8
}

std::string failure_report_json(int exit_code, const std::string& kind,
                                const std::string& message) {
  const json r = {{"version", 1},
                  {"status", "failed"},
                  {"error", {{"exit_code", exit_code}, {"kind", kind}, {"message", message}}}};
  return r.dump(2, ' ', false, json::error_handler_t::replace) + "\n";  // paths need not be UTF-8
}

std::string bending_dump_json(const PolyMesh& quads, const BendingResult& b) {
  json vertices = json::array();
  for (auto v : quads.vertices()) {
    const auto& p = quads.point(v);
    vertices.push_back({p[0], p[1], p[2]});
  }
  json faces = json::array();
  for (auto f : quads.faces()) faces.push_back(quad_vertices(quads, f));
  json edges = json::array();
  for (auto e : quads.edges()) {
    const auto h = quads.halfedge_handle(e, 0);
    edges.push_back({{"v", {quads.from_vertex_handle(h).idx(), quads.to_vertex_handle(h).idx()}},
                     {"weight", b.variance[e.idx()] + b.w0},
                     {"variance", b.variance[e.idx()]},
                     {"bendable", b.bendable[e.idx()] != 0}});
  }
  json quad_classes = json::array();
  for (const auto& q : b.quads)
    quad_classes.push_back({{"kind", to_string(q.kind)}, {"axis", q.axis}});
  json j;
  j["vertices"] = vertices;
  j["quads"] = faces;
  j["edges"] = edges;
  j["quad_bending"] = quad_classes;
  j["w0"] = b.w0;
  j["objective"] = b.objective;
  j["bound"] = b.bound;
  j["status"] = to_string(b.status);
  return j.dump(2) + "\n";
}

std::string parts_dump_json(const RunResult& run) {
  auto poly = [](const Polygon2& p) {
    json a = json::array();
    for (const auto& v : p) a.push_back({v.x(), v.y()});
    return a;
  };
  json parts = json::array();
  for (std::size_t i = 0; i < run.joints->parts.size(); ++i) {
    const PartOutline& part = run.joints->parts[i];
    json teeth = json::array();
    for (const auto& sp : part.spans)
      if (sp.tooth) teeth.push_back(poly(sp.region));
    json kerf = json::array();
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
  const json j = {
      {"units", "mm"}, {"kerf_width_mm", run.options.machine.kerf_width}, {"parts", parts}};
  return j.dump(2) + "\n";
}

}  // namespace kerfab

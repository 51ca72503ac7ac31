#pragma once
/// \file The machine-readable run report (schema: docs/outputs.md) and the stage dumps, as JSON
/// text.
#include <string>

#include "kerfab/output/output_options.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// report.json of a finished run (status "ok"); sections of stages that did not run are absent.
std::string report_json(const RunResult& run, const OutputOptions& output);

/// report.json of a failed run: {"version", "status": "failed", "error": {...}}.
std::string failure_report_json(int exit_code, const std::string& kind, const std::string& message);

/// stages/bending.json: quad mesh, per-edge weight and bendable flag, objective and status.
std::string bending_dump_json(const PolyMesh& quads, const BendingResult& bending);

/// stages/parts.json: every part's outline with teeth (designed and kerf-compensated, mm, in the
/// frame of its NNN_2d.obj), its tooth regions and its kerf cuts ([x0, y0, x1, y1]).
std::string parts_dump_json(const RunResult& run);

}  // namespace kerfab

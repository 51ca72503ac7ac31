#pragma once
/// \file The machine-readable run report (schema: shared/OUTPUTS.md) and stage dumps.
#include <nlohmann/json.hpp>

#include "kerfab/pipeline.h"

namespace kerfab {

/// report.json of a finished run (status "ok"); sections of stages that did not run are absent.
nlohmann::json make_report(const RunResult& run);

/// report.json of a failed run: {"version", "status": "failed", "error": {...}}.
nlohmann::json make_failure_report(int exit_code, const std::string& kind,
                                   const std::string& message);

/// stages/bending.json: quad mesh, per-edge weight and bendable flag, objective and status.
nlohmann::json make_bending_dump(const PolyMesh& quads, const BendingResult& bending);

/// stages/parts.json: every part's outline with teeth (designed and kerf-compensated, mm, in the
/// frame of its NNN_2d.obj), its tooth regions and its kerf cuts ([x0, y0, x1, y1]).
nlohmann::json make_parts_dump(const RunResult& run);

}  // namespace kerfab

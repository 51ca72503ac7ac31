#pragma once
/// \file Writing a run's output directory safely: a failed run never leaves a report.json that
/// looks complete, and a directory that is not a kerfab output is never overwritten.
#include <filesystem>

#include "kerfab/output/output_options.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// Makes \p dir ready for a new run: creates it, or clears the outputs of an earlier kerfab run
/// in it. \throw IoError it exists, is not empty and holds no kerfab report.json, or cannot be
/// created.
void prepare_output_dir(const std::filesystem::path& dir);

/// Writes model/target.obj, stages/ (with output.dump), cut/ and finally report.json
/// (atomically). \throw IoError a file could not be written.
void write_run(const RunResult& run, const OutputOptions& output, const std::filesystem::path& dir);

/// Removes this run's partial outputs from \p dir and writes a failed-status report.json.
/// Never throws (best effort: it is called while handling another error).
void write_failure(const std::filesystem::path& dir, int exit_code, const std::string& kind,
                   const std::string& message) noexcept;

}  // namespace kerfab

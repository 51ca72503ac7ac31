#pragma once
/// \file Writing a run's output directory safely. A run writes into a fresh staging folder
/// beside DIR and puts it in place only when complete (an atomic exchange), so a failed or
/// interrupted run leaves DIR exactly as it was: an earlier good run intact, a user's files
/// untouched. kerfab recognises its own earlier run by a marker file (`.kerfab`, which lists the
/// files it wrote) and replaces only those files; anything else a user put into the folder is
/// carried over. A lock beside DIR lets one run at a time write it.
#include <filesystem>
#include <string>

#include "kerfab/output/output_options.h"
#include "kerfab/pipeline/pipeline.h"

namespace kerfab {

/// The name of the marker file kerfab writes into every output folder.
inline constexpr const char* kRunMarker = ".kerfab";

/// One run's output folder, from the start of the run to its end.
class OutputFolder {
 public:
  /// Checks \p dir, takes its lock and creates the staging folder beside it (removing stale
  /// ones of runs that were killed). \throw IoError \p dir is a file, holds files but no kerfab
  /// marker, another run is writing it, or the folders cannot be created.
  explicit OutputFolder(const std::filesystem::path& dir);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// Where this run writes its files.
  const std::filesystem::path& staging() const { return staging_; }
  const std::filesystem::path& dir() const { return dir_; }

  /// Puts the staging folder in place of DIR (signals blocked meanwhile): the earlier run's
  /// files go, a user's own files in it are kept (hard links, or copies). \throw IoError a
  /// user's file would be replaced by one of the run's, or the exchange failed (DIR unchanged).
  void commit();

  /// The run failed: the staging folder goes. If DIR did not exist or was empty, it gets a
  /// failed-status report.json (and the marker); an earlier run in it is left as it was.
  /// Returns true when such a report was written. Never throws.
  bool fail(int exit_code, const std::string& kind, const std::string& message) noexcept;

 private:
  void prepare(const std::string& pid);  // the checks and the staging folder, under the lock

  std::filesystem::path dir_, staging_, lock_;
  int lock_fd_ = -1;
  bool had_run_ = false, committed_ = false;
};

/// Writes model/target.obj, stages/ (with output.dump), cut/ and finally report.json
/// (atomically) into \p dir. \throw IoError a file could not be written.
void write_run(const RunResult& run, const OutputOptions& output, const std::filesystem::path& dir);

/// Replaces characters that would break a one-line message (newlines, other control
/// characters) by escapes.
std::string one_line(const std::string& text);

}  // namespace kerfab

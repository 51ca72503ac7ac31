#include "kerfab/output/run_output.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "kerfab/core/errors.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/output/assembly_guide.h"
#include "kerfab/output/assembly_page.h"
#include "kerfab/output/dxf_sheets.h"
#include "kerfab/output/pdf_sheets.h"
#include "kerfab/output/pictures.h"
#include "kerfab/output/report.h"
#include "kerfab/output/strip_files.h"
#include "kerfab/output/svg_sheets.h"

namespace kerfab {
namespace fs = std::filesystem;
namespace {

void write_json(const std::string& text, const fs::path& path) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw IoError("cannot write " + tmp.string());
    out << text;
    if (!out) throw IoError("cannot write " + tmp.string());
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw IoError("cannot write " + path.string() + ": " + ec.message());
}

void make_dirs(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create directory " + dir.string() + ": " + ec.message());
}

/// Absolute, normalised, without a trailing separator.
fs::path normalised(const fs::path& dir) {
  fs::path p = fs::absolute(dir).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

/// Files (and symbolic links) under \p root, relative to it, without the marker.
std::vector<std::string> files_under(const fs::path& root) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    const auto status = it->symlink_status(ec);
    if (ec || fs::is_directory(status)) continue;
    const std::string rel = fs::relative(it->path(), root, ec).generic_string();
    if (!ec && rel != kRunMarker) out.push_back(rel);
  }
  if (ec) throw IoError("cannot list " + root.string() + ": " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

/// The files an earlier run wrote, from its marker (empty if it has none or it is unreadable).
std::set<std::string> manifest(const fs::path& dir) {
  std::set<std::string> out;
  std::ifstream in(dir / kRunMarker);
  if (!in) return out;
  try {
    const auto doc = nlohmann::json::parse(in);
    for (const auto& f : doc.at("files")) out.insert(f.get<std::string>());
  } catch (const nlohmann::json::exception&) {
  }
  return out;
}

void write_marker(const fs::path& dir, const std::vector<std::string>& files) {
  write_json(nlohmann::json{{"kerfab_output", 1}, {"files", files}}.dump(
                 1, ' ', false, nlohmann::json::error_handler_t::replace) +
                 "\n",
             dir / kRunMarker);
}

/// Blocks the signals that end a run, for as long as it lives.
class SignalsBlocked {
 public:
  SignalsBlocked() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&set, s);
    pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~SignalsBlocked() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }

 private:
  sigset_t old_;
};

}  // namespace

std::string one_line(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '\n') {
      out += "\\n";
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(c));
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

OutputFolder::OutputFolder(const fs::path& dir) : dir_(normalised(dir)) {
  const fs::path parent = dir_.parent_path();
  const std::string name = dir_.filename().string();
  make_dirs(parent);
  // One run at a time: an advisory lock on a file beside DIR (released by the kernel when a
  // run dies, so a killed run never blocks the next one).
  lock_ = parent / ("." + name + ".kerfab-lock");
  for (int attempt = 0; attempt < 8; ++attempt) {
    lock_fd_ = ::open(lock_.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    if (lock_fd_ < 0)
      throw IoError("cannot create the lock " + lock_.string() + ": " + std::strerror(errno));
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
      char pid[32] = {0};
      const ssize_t n = ::pread(lock_fd_, pid, sizeof pid - 1, 0);
      ::close(lock_fd_);
      lock_fd_ = -1;
      throw IoError(
          "another kerfab run" +
          (n > 0 ? std::string(" (pid ") + std::string(pid, static_cast<std::size_t>(n)) + ")"
                 : std::string()) +
          " is writing " + dir_.string() + "; wait for it or choose another --out");
    }
    // The lock file may have been removed by the run that held it just before: lock the file
    // that is there now.
    struct stat held {
    }, now{};
    if (::fstat(lock_fd_, &held) == 0 && ::stat(lock_.c_str(), &now) == 0 &&
        held.st_ino == now.st_ino && held.st_dev == now.st_dev)
      break;
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
  if (lock_fd_ < 0) throw IoError("cannot lock " + lock_.string());
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) == 0) (void)!::pwrite(lock_fd_, pid.data(), pid.size(), 0);
  try {
    prepare(pid);
  } catch (...) {
    ::unlink(lock_.c_str());  // no destructor runs for a constructor that throws
    ::close(lock_fd_);
    throw;
  }
}

void OutputFolder::prepare(const std::string& pid) {
  const std::string name = dir_.filename().string();
  const fs::path parent = dir_.parent_path();
  std::error_code ec;
  if (fs::exists(dir_, ec)) {
    if (!fs::is_directory(dir_, ec))
      throw IoError("output path is not a directory: " + dir_.string());
    if (!fs::is_empty(dir_, ec)) {
      if (!fs::exists(dir_ / kRunMarker, ec))
        throw IoError("output directory " + dir_.string() +
                      " is not empty and holds no earlier kerfab run (no " + kRunMarker +
                      " marker); choose another --out");
      had_run_ = true;
    }
  }
  // Staging folders of runs that were killed (this run holds the lock: none is in use).
  const std::string prefix = "." + name + ".kerfab-tmp-";
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().rfind(prefix, 0) == 0) {
      std::error_code ignore;
      fs::remove_all(it->path(), ignore);
    }
  staging_ = parent / (prefix + pid);
  fs::create_directory(staging_, ec);
  if (ec)
    throw IoError("cannot create the staging folder " + staging_.string() + ": " + ec.message());
}

OutputFolder::~OutputFolder() {
  std::error_code ec;
  if (!committed_) fs::remove_all(staging_, ec);
  if (lock_fd_ >= 0) {
    ::unlink(lock_.c_str());  // while still holding it (see the constructor)
    ::close(lock_fd_);
  }
}

void OutputFolder::commit() {
  const SignalsBlocked blocked;
  std::error_code ec;
  const std::vector<std::string> written = files_under(staging_);
  if (fs::exists(dir_, ec)) {
    // A user's own files in the earlier run's folder come along (hard links: the earlier
    // folder keeps them until the exchange is done).
    const std::set<std::string> earlier = manifest(dir_);
    for (const std::string& f : files_under(dir_)) {
      if (earlier.count(f)) continue;
      const fs::path from = dir_ / f, to = staging_ / f;
      if (fs::exists(fs::symlink_status(to, ec)))
        throw IoError(from.string() +
                      " is not kerfab's and this run writes a file of that name; "
                      "move it and run again (" +
                      dir_.string() + " is unchanged)");
      make_dirs(to.parent_path());
      fs::create_hard_link(from, to, ec);
      if (ec) {
        ec.clear();
        fs::copy(from, to, fs::copy_options::copy_symlinks, ec);
      }
      if (ec)
        throw IoError("cannot carry over " + from.string() + ": " + ec.message() + " (" +
                      dir_.string() + " is unchanged)");
    }
    write_marker(staging_, written);
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) != 0) {
      // No atomic exchange on this file system: move the old folder aside, then back on failure.
      const fs::path aside = staging_.string() + "-old";
      fs::rename(dir_, aside, ec);
      if (ec) throw IoError("cannot replace " + dir_.string() + ": " + ec.message());
      fs::rename(staging_, dir_, ec);
      if (ec) {
        std::error_code back;
        fs::rename(aside, dir_, back);
        throw IoError("cannot replace " + dir_.string() + ": " + ec.message());
      }
      fs::remove_all(aside, ec);
    } else {
      fs::remove_all(staging_, ec);  // now the earlier run
    }
  } else {
    write_marker(staging_, written);
    fs::rename(staging_, dir_, ec);
    if (ec) throw IoError("cannot create " + dir_.string() + ": " + ec.message());
  }
  committed_ = true;
}

bool OutputFolder::fail(int exit_code, const std::string& kind,
                        const std::string& message) noexcept {
  try {
    std::error_code ec;
    fs::remove_all(staging_, ec);
    committed_ = true;  // nothing left to remove
    if (had_run_) return false;
    if (fs::exists(dir_, ec) && !fs::is_empty(dir_, ec)) return false;
    fs::create_directories(dir_, ec);
    if (ec) return false;
    write_json(failure_report_json(exit_code, kind, message), dir_ / "report.json");
    write_marker(dir_, {"report.json"});
    return true;
  } catch (...) {
    return false;
  }
}

void write_run(const RunResult& run, const OutputOptions& output, const fs::path& dir) {
  if (run.input) {
    make_dirs(dir / "model");
    write_mesh(run.input->target, dir / "model" / "target.obj");
  }
  // The quad mesh kerfab made, to inspect, edit and feed back with --quad.
  // In the frame and units of the target file as given, so that it pairs with that file and
  // the same --size when fed back with --quad (model/target.obj is scaled, in mm).
  if (run.quads || (run.coarsened && run.coarsened->changed())) {
    PolyMesh quads = run.input->quads;
    for (auto v : quads.vertices()) quads.set_point(v, quads.point(v) / run.input->scale);
    write_mesh(quads, dir / "model" / "quads.obj");
  }
  if (run.strips) write_strips_ply(run.final_strips(), dir / "model" / "strips.ply");
  if (run.kerf)
    write_kerf_density_ply(run.final_strips(), *run.kerf, dir / "model" / "kerf_density.ply");
  if (output.dump && run.bending && run.input) {
    make_dirs(dir / "stages");
    write_json(bending_dump_json(run.input->quads, *run.bending), dir / "stages" / "bending.json");
  }
  if (output.dump && run.strips) {
    const Strips& strips = run.final_strips();
    make_dirs(dir / "stages" / "patches");
    for (std::size_t p = 0; p < strips.patches.size(); ++p) {
      char name[32];
      std::snprintf(name, sizeof name, "%03zu_3d.obj", p);
      write_patch_obj(strips, static_cast<int>(p), dir / "stages" / "patches" / name);
      if (run.flat) {
        std::snprintf(name, sizeof name, "%03zu_2d.obj", p);
        write_patch_flat_obj(strips, static_cast<int>(p), run.flat->flattening.patches[p].points,
                             dir / "stages" / "patches" / name);
      }
    }
  }
  if (output.dump && run.joints) write_json(parts_dump_json(run), dir / "stages" / "parts.json");
  // The assembly guide (the demo's largest output: 1.3 of 2.7 s writing) is written beside the
  // sheets and pictures, on a thread of its own: the writers share nothing but the run, which
  // they only read, and each draws on cairo surfaces of its own. Its errors surface here; where
  // another writer throws first, the future's destructor still waits for the guide (a future
  // from std::async does), so it never outlives the run it reads.
  std::future<void> guide;
  if (run.layout && run.assembly)
    guide = std::async(std::launch::async, [&] { write_assembly_guide(run, dir / "assembly"); });
  if (run.layout) {
    if (output.formats.svg) write_svg_sheets(run, output.style, dir / "cut");
    if (output.formats.dxf) write_dxf_sheets(run, dir / "cut");
    if (output.formats.pdf) write_pdf_sheets(run, output.style, dir / "cut");
    write_sheet_previews(run, output.style, dir / "cut");
    write_assembly_page(run, dir / "cut");
  }
  write_pictures(run, {}, dir / "pictures");
  if (guide.valid()) guide.get();
  write_json(report_json(run, output), dir / "report.json");
}

}  // namespace kerfab

#include "kerfab/output/run_output.h"

#include <cstdio>
#include <fstream>

#include "kerfab/core/errors.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/output/assembly_page.h"
#include "kerfab/output/dxf_sheets.h"
#include "kerfab/output/pdf_sheets.h"
#include "kerfab/output/report.h"
#include "kerfab/output/strip_files.h"
#include "kerfab/output/svg_sheets.h"

namespace kerfab {
namespace fs = std::filesystem;
namespace {

// Everything a run may write; only these are ever removed.
const char* const kOutputs[] = {"report.json", "report.json.tmp", "model", "stages", "cut"};

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

}  // namespace

void prepare_output_dir(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw IoError("output path is not a directory: " + dir.string());
    const bool empty = fs::is_empty(dir, ec);
    if (!empty && !fs::exists(dir / "report.json", ec))
      throw IoError("output directory " + dir.string() +
                    " is not empty and holds no kerfab report.json; choose another --out");
    for (const char* name : kOutputs) fs::remove_all(dir / name, ec);
    if (ec) throw IoError("cannot clear old outputs in " + dir.string() + ": " + ec.message());
  }
  make_dirs(dir);
}

void write_run(const RunResult& run, const OutputOptions& output, const fs::path& dir) {
  if (run.input) {
    make_dirs(dir / "model");
    write_mesh(run.input->target, dir / "model" / "target.obj");
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
  if (run.layout) {
    if (output.formats.svg) write_svg_sheets(run, output.style, dir / "cut");
    if (output.formats.dxf) write_dxf_sheets(run, dir / "cut");
    if (output.formats.pdf) write_pdf_sheets(run, output.style, dir / "cut");
    write_sheet_previews(run, output.style, dir / "cut");
    write_assembly_page(run, dir / "cut");
  }
  write_json(report_json(run, output), dir / "report.json");
}

void write_failure(const fs::path& dir, int exit_code, const std::string& kind,
                   const std::string& message) noexcept {
  try {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    for (const char* name : kOutputs) fs::remove_all(dir / name, ec);
    write_json(failure_report_json(exit_code, kind, message), dir / "report.json");
  } catch (...) {
  }
}

}  // namespace kerfab

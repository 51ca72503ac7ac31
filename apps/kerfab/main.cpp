// kerfab command line: flags -> options, run the pipeline, write outputs, map errors to exit
// codes (docs/outputs.md). No geometry here.
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include "kerfab/core/errors.h"
#include "kerfab/output/run_output.h"
#include "kerfab/pipeline/pipeline.h"

namespace {

namespace fs = std::filesystem;

enum ExitCode { kOk = 0, kInvalid = 1, kIo = 2, kSolver = 3, kInternal = 4 };

// SIGINT, SIGTERM, SIGHUP: stop at once. The run writes into a staging folder beside --out that
// is put in place only when complete, so nothing partial reaches --out; the next run removes
// the staging folder. Only async-signal-safe calls here.
extern "C" void stop_on_signal(int signal) {
  const char* text =
      signal == SIGINT    ? "kerfab: error: interrupted (SIGINT); nothing partial was written\n"
      : signal == SIGTERM ? "kerfab: error: terminated (SIGTERM); nothing partial was written\n"
                          : "kerfab: error: hung up (SIGHUP); nothing partial was written\n";
  (void)!::write(STDERR_FILENO, text, std::strlen(text));
  ::_exit(128 + signal);
}

void stop_on_signals() {
  struct sigaction action {};
  action.sa_handler = stop_on_signal;
  sigemptyset(&action.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &action, nullptr);
}

// Every numeric value given on the command line must be finite: CLI11's range checks let "nan"
// through (every comparison with it is false). Returns the message for the first that is not.
std::optional<std::string> non_finite_option(const CLI::App& cmd) {
  for (const CLI::Option* opt : cmd.get_options()) {
    for (const std::string& value : opt->results()) {
      const char* text = value.c_str();
      char* end = nullptr;
      const double x = std::strtod(text, &end);
      if (end != text && *end == '\0' && !std::isfinite(x))
        return opt->get_name() + " must be a finite number, got '" + value + "'";
    }
  }
  return std::nullopt;
}

double machine_memory_mb() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * page / (1024.0 * 1024.0) : 0;
}

// Half of the machine's memory, not less than 512 MB (and 4096 MB where it cannot be read).
double default_memory_budget_mb() {
  const double machine = machine_memory_mb();
  return machine > 0 ? std::max(512.0, std::floor(machine / 2)) : 4096.0;
}

// The budget becomes the process's data limit (heap and private mappings; RLIMIT_DATA), never
// raising one set outside; returns the limit now in force [MB].
double limit_memory(double budget_mb) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // AddressSanitizer and ThreadSanitizer map terabytes of shadow memory: a data limit would stop
  // the sanitized test build itself. The budget's early estimates still apply.
  return budget_mb;
#endif
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_DATA, &limit) != 0) return budget_mb;
  const double bytes = budget_mb * 1024.0 * 1024.0;
  if (limit.rlim_cur == RLIM_INFINITY || bytes < static_cast<double>(limit.rlim_cur)) {
    limit.rlim_cur = static_cast<rlim_t>(bytes);
    if (limit.rlim_max != RLIM_INFINITY && limit.rlim_cur > limit.rlim_max)
      limit.rlim_cur = limit.rlim_max;
    ::setrlimit(RLIMIT_DATA, &limit);
  }
  return static_cast<double>(limit.rlim_cur) / (1024.0 * 1024.0);
}

struct RunFlags {
  std::string target, quad, guidance, out;
  std::optional<double> size;
  std::string stop_after;
  double split_angle_deg = 60.0;
  std::optional<double> features_deg;
  double quad_feature_angle_deg = 60.0;
  std::string projection = "normal";
  std::string material = "mdf";
  std::string sheet = "600x450";
  CLI::Option* sheet_option = nullptr;        // to tell a given --sheet from the default
  CLI::Option* split_angle_option = nullptr;  // to tell a given --split-angle from the default
  CLI::Option* feature_angle_option = nullptr;  // and a given --quad-feature-angle
  CLI::Option* stroke_option = nullptr;       // to tell a given --stroke from the default
  std::string format = "svg,dxf,pdf";
  std::optional<double> thickness, shear_modulus, yield_strength, safety;
  std::optional<int> constant_density;
  bool quiet = false;
  double max_memory_mb = default_memory_budget_mb();
  kerfab::PipelineOptions options;
  kerfab::OutputOptions output;
};

// Range checks with a short message naming the limit (CLI11's own print the largest double).
const CLI::Validator kPositive(
    [](std::string& value) -> std::string {
      const double x = std::strtod(value.c_str(), nullptr);
      return x > 0 ? std::string() : "must be > 0, got " + value;
    },
    "> 0");
const CLI::Validator kNonNegative(
    [](std::string& value) -> std::string {
      const double x = std::strtod(value.c_str(), nullptr);
      return x >= 0 ? std::string() : "must be >= 0, got " + value;
    },
    ">= 0");

void add_pipeline_options(CLI::App& cmd, RunFlags& f) {
  auto& in = f.options.input;
  auto& b = f.options.bending;
  cmd.add_option("--size", f.size,
                 "Scale the model so its largest bounding-box side is this many mm [mm]; "
                 "without it, inputs are millimetres and must measure 10 mm .. 10 m")
      ->check(kPositive);
  cmd.add_option("--subdivide", in.subdivide,
                 "Catmull-Clark steps applied to the quad mesh first; any polygon mesh is all "
                 "quads after one [count, 0..4]")
      ->capture_default_str()
      ->check(CLI::Range(0, 4));
  cmd.add_option("--quads", f.options.quads.quads,
                 "With a target not all quads and no --quad: make about this many quads instead of "
                 "the size the model and material call for [count, 20..20000]")
      ->check(CLI::Range(20, 20000));
  cmd.add_option("--quad-size", f.options.quads.quad_size,
                 "With a target not all quads and no --quad: quad edge length (wins over --quads) "
                 "[mm, > 0]")
      ->check(kPositive);
  f.feature_angle_option =
      cmd.add_option(
             "--quad-feature-angle", f.quad_feature_angle_deg,
             "With a target not all quads and no --quad: target edges folding more than this are "
             "sharp features the quad edges follow (shallower folds over 20 deg between "
             "two wide planes too); the default is raised 5 deg at a time, up to 90, where a "
             "triangle walled in by such edges leaves the lattice without quads [deg, (0, 180)]")
          ->capture_default_str()
          ->check(CLI::Range(1e-6, 179.999));
  cmd.add_option("--max-quad-distance", in.max_quad_distance,
                 "Refuse a quad mesh with a vertex farther from the target than this fraction of "
                 "the target's bbox diagonal [ratio]")
      ->capture_default_str()
      ->check(kPositive);
  cmd.add_option("--alignment", b.alignment,
                 "Alignment bias c: w0 = c * max edge weight is added to every edge weight; "
                 "larger c gives fewer, longer strips (paper Sec. 3.1); past about 100 the edges' "
                 "own weights only break ties [ratio, 0..1000]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, kerfab::kMaxAlignment));
  cmd.add_option("--edge-samples", b.edge_samples,
                 "Signed-distance samples per quad edge for its weight (variance) [count, >= 2]")
      ->capture_default_str()
      ->check(CLI::Range(2, 4096));
  cmd.add_option("--ilp-time-limit", b.time_limit_s,
                 "Time limit of the bending integer program; the best selection found is used "
                 "and the report says so [s]")
      ->capture_default_str()
      ->check(kPositive);
  cmd.add_option("--ilp-gap", b.relative_gap,
                 "Accepted relative optimality gap of the bending integer program [ratio, >= 0]")
      ->capture_default_str()
      ->check(kNonNegative);
  auto& st = f.options.strips;
  cmd.add_option("--rulings-per-quad", st.rulings_per_quad,
                 "Segments each bending edge of a quad is split into, i.e. new rulings + 1 "
                 "[count, 1..64]")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd.add_option("--max-ruling-spacing", st.max_ruling_spacing,
                 "Largest distance between rulings along a bending edge; a long edge gets more "
                 "segments than --rulings-per-quad (the larger count wins) [mm]")
      ->capture_default_str()
      ->check(kPositive);
  cmd.add_option("--projection", f.projection,
                 "How new vertices reach the target: along the normal (ray, closest point as "
                 "fallback) or to the closest point [normal|closest]")
      ->capture_default_str()
      ->check(CLI::IsMember({"normal", "closest"}));
  f.split_angle_option =
      cmd.add_option("--split-angle", f.split_angle_deg,
                     "Split a strip between two quads whose sector normals at an end of their "
                     "shared ruling differ by more than this; 100 with --material paper, which "
                     "creases there instead (scored) [deg, (0, 180]]")
          ->capture_default_str()
          ->check(CLI::Range(1e-6, 180.0));
  cmd.add_option("--features", f.features_deg,
                 "Feature-preserving projection: vertices on quad-mesh edges sharper than this "
                 "dihedral angle (and on the boundary) go to the target's sharp edges and "
                 "boundary; off by default [deg, (0, 180)]")
      ->check(CLI::Range(1e-6, 179.999));
  cmd.add_option("--flatten-lambda", f.options.flatten.lambda,
                 "Weight of the border-length term against the quad-angle term in the "
                 "flattening energy (paper Eq. 2); lengths are measured relative to the patch's "
                 "mean border edge [ratio, 0..1]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  auto& jo = f.options.joints;
  auto& ko = f.options.kerf;
  cmd.add_option("--material", f.material,
                 "Sheet material preset: mdf (3 mm, G 1.6 GPa, tau 18 MPa, G/tau 100 with safety), "
                 "mdf2 (the same, 2 mm), plywood (4 mm birch, G 620 MPa, tau 9.5 MPa, safety "
                 "1.5), plywood3 (the same, 3 mm), paper (h 0, no cuts)")
      ->capture_default_str()
      ->check(CLI::IsMember({"mdf", "mdf2", "plywood", "plywood3", "paper"}));
  cmd.add_option("--thickness", f.thickness,
                 "Sheet thickness h, overrides the material's, 0 (paper) to 25 [mm]")
      ->check(kNonNegative);
  cmd.add_option("--shear-modulus", f.shear_modulus,
                 "Shear modulus G, overrides the material's (steel is 80000) [MPa, 1..200000]")
      ->check(CLI::Range(1.0, 200000.0));
  cmd.add_option("--yield-strength", f.yield_strength,
                 "Shear yield strength tau, overrides the material's [MPa, 0.01..2000]")
      ->check(CLI::Range(0.01, 2000.0));
  cmd.add_option(
         "--safety", f.safety,
         "Safety factor dividing the yield strength, overrides the material's [ratio, >= 1]")
      ->check(CLI::Range(1.0, 100.0));
  cmd.add_option("--protrusion", jo.protrusion,
                 "How far a box-joint tooth may stick out of the shell between the surface "
                 "offsets +-h/2, at most h [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--tooth-width", jo.tooth_width,
                 "Width of box-joint teeth along the border, 1 to 100 [mm]")
      ->capture_default_str()
      ->check(kPositive);
  cmd.add_option("--min-tooth-depth", jo.min_depth,
                 "No teeth where the tooth would overlap its slot by less than this; at most the "
                 "deepest box tooth of the sheet (5.76 h) [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--tab-misfit", jo.tab_misfit,
                 "Where a fold is too shallow for box teeth, in-plane dovetail tabs whose tip "
                 "leaves the other part's faces by at most this, at most h; 0: no tabs [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--glue-tab", jo.glue_tab,
                 "Paper (--material paper or --thickness 0): height of the glue tabs, one side "
                 "of every border, folded under the other part; 0: no tabs, plain borders [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_flag("--score-rulings", jo.score_rulings,
               "Paper: also draw the rulings that bend by 1 degree or more as fold lines (the "
               "strips are folded there instead of curved)");
  cmd.add_option("--kerf-width", f.options.machine.kerf_width,
                 "Width of the laser cut; outlines are offset by half of it so parts fit as "
                 "designed [mm, 0..5]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 5.0));
  cmd.add_option("--min-cut-spacing", ko.min_cut_spacing,
                 "Kerf cuts closer than this are a critical region (reported, shown red in "
                 "model/kerf_density.ply) [mm, more than --kerf-width]")
      ->capture_default_str()
      ->check(kPositive);
  cmd.add_option("--min-cut-length", ko.min_cut_length,
                 "Kerf cuts shorter than this are not made [mm]")
      ->capture_default_str()
      ->check(kPositive);
  cmd.add_option("--bridge", ko.bridge, "Material left at alternating ends of each kerf cut [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--kerf-margin", ko.margin,
                 "Kerf cuts keep this far from the part outline and its joints [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--kerf-smoothing", ko.smoothing,
                 "Width of the tent kernel averaging the twist rate along a strip; default: twice "
                 "the target's facet size (median sqrt(2 area) of its triangles) [mm]")
      ->check(kNonNegative);
  cmd.add_option("--constant-density", f.constant_density,
                 "Instead of the adaptive density: this many kerf cuts per quad of the quad mesh "
                 "(the paper's baseline) [count]")
      ->check(CLI::Range(0, 1000));
  cmd.add_option("--cut-speed", f.options.machine.speed,
                 "Laser cutting speed for the time estimate [mm/s, 0.01..10000]")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 10000.0));
  cmd.add_option("--per-cut-time", f.options.machine.per_cut,
                 "Overhead per separate cut path (pierce, travel) for the time estimate "
                 "[s, 0..3600]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  f.sheet_option = cmd.add_option("--sheet", f.sheet,
                                  "Sheet size WxH of the laser bed or stock, e.g. 600x450, or a "
                                  "paper size A4, A3, letter (portrait) [mm]; A4 with "
                                  "--material paper. Offcuts first, comma separated: "
                                  "300x200,250x250,600x450 fills one 300x200 and one 250x250 "
                                  "sheet before as many 600x450 sheets as needed")
                       ->capture_default_str();
  cmd.add_option("--format", f.format,
                 "Cut-sheet files to write, comma separated: svg, dxf, pdf (PNG previews always)")
      ->capture_default_str();
  f.stroke_option = cmd.add_option("--stroke", f.output.style.stroke,
                                   "Line width of cut, engrave and fold lines in the SVG and PDF "
                                   "sheets; the default hairline is what laser drivers expect; "
                                   "0.2 with --material paper, for printing [mm, up to 2]")
                        ->capture_default_str()
                        ->check(CLI::Range(1e-6, 2.0));
  const auto colour = CLI::Validator(
      [](std::string& c) {
        const bool ok = c.size() == 7 && c[0] == '#' &&
                        c.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
        return ok ? std::string() : "colour must be #rrggbb, got '" + c + "'";
      },
      "#rrggbb");
  cmd.add_option("--cut-colour", f.output.style.cut, "Colour of cut lines in SVG and PDF")
      ->capture_default_str()
      ->check(colour);
  cmd.add_option("--engrave-colour", f.output.style.engrave,
                 "Colour of engraved labels in SVG and PDF")
      ->capture_default_str()
      ->check(colour);
  cmd.add_option("--mountain-colour", f.output.style.mountain,
                 "Paper: colour of mountain fold lines (dash-dot) in SVG and PDF")
      ->capture_default_str()
      ->check(colour);
  cmd.add_option("--valley-colour", f.output.style.valley,
                 "Paper: colour of valley fold lines (dashed) in SVG and PDF")
      ->capture_default_str()
      ->check(colour);
  cmd.add_option("--margin", f.options.layout.margin, "Free border along each sheet edge [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--spacing", f.options.layout.spacing, "Gap between parts on a sheet [mm]")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd.add_option("--quality-spacing", f.options.quality_sample_spacing,
                 "Sample spacing of the mean distance; the Hausdorff distance is found to "
                 "within a quarter of it. As a fraction of the target's bbox diagonal [ratio]")
      ->capture_default_str()
      ->check(CLI::Range(1e-5, 0.1));
  cmd.add_option("--max-memory", f.max_memory_mb,
                 "Memory the run may use [MB]; work that would need more is refused before it "
                 "starts, and a run that reaches it stops with an error (default: half of this "
                 "machine's memory, at least 512)")
      ->capture_default_str()
      ->check(CLI::Range(64.0, 1e9));
  cmd.add_flag(
      "--no-resolve", [&f](std::int64_t) { f.options.resolve.enabled = false; },
      "Keep critical kerf regions as they are and only report them (the paper's "
      "behaviour) instead of changing the layout there until the parts can be cut");
  cmd.add_option("--resolve-time-limit", f.options.resolve.time_limit,
                 "No new round of the resolve step starts after this long; the run goes on with "
                 "the best build it saw and lists the regions left [s, > 0]")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd.add_option(
         "--min-part-width", f.options.resolve.min_part_width,
         "The narrowest part a maker can handle: parts nowhere this wide take their borders' "
         "teeth instead of their slots and are changed by the resolve step, and slivers "
         "narrower than this across are left out [mm, 0.1 to 1000]")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1000.0));
  cmd.add_flag(
      "--no-coarsen", [&f](std::int64_t) { f.options.coarsen.enabled = false; },
      "Use a given quad mesh as it is, instead of collapsing rows of quads where the strips "
      "beside them are too narrow for the material to bend (the mesh used is written to "
      "OUT/model/quads.obj)");
  cmd.add_flag(
      "--keep-strips-whole", [&f](std::int64_t) { f.options.split_to_fit.enabled = false; },
      "Never split a long strip in two to save a sheet (by default, where the parts need more "
      "sheets than their area does, the longest strips are split at their middle ruling when "
      "that saves a whole sheet; layout.split_to_fit in the report)");
  cmd.add_flag("--dump", f.output.dump, "Also write intermediate stages to OUT/stages/");
  cmd.add_flag("--row-baseline", f.options.row_baseline,
               "Also build the naive one-strip-per-row layout and report its strip count "
               "(strips.naive_row_strips, for comparison)");
  cmd.add_flag("--quiet", f.quiet, "No progress lines on stderr");
  std::string stages;
  for (const auto& s : kerfab::stage_names()) stages += (stages.empty() ? "" : "|") + s;
  cmd.add_option("--stop-after", f.stop_after, "End the run after this stage (" + stages + ")")
      ->check(CLI::IsMember(kerfab::stage_names()));
}

int run(const kerfab::RunInputs& inputs, RunFlags& f) {
  const fs::path out = f.out;
  kerfab::PipelineOptions options = f.options;
  kerfab::OutputOptions output = f.output;
  options.input.size = f.size;
  options.strips.split_angle = f.split_angle_deg * M_PI / 180.0;
  // Paper folds where a stiff sheet must be split: its strips are split only at folds over
  // kPaperSplitAngle, and the rulings folding over kCreaseFold are scored (docs/joints.md).
  if (f.material == "paper" && f.split_angle_option && f.split_angle_option->count() == 0)
    options.strips.split_angle = kerfab::kPaperSplitAngle;
  options.quads.feature_angle = f.quad_feature_angle_deg * M_PI / 180.0;
  // The default angle may be raised where a triangle walled in by creases loses the lattice
  // (docs/quad-meshing.md); an angle the user gives is kept.
  options.quads.raise_feature_angle =
      !f.feature_angle_option || f.feature_angle_option->count() == 0;
  try {
    options.material = kerfab::material_preset(f.material);
  } catch (const kerfab::InvalidInput& e) {
    std::cerr << "kerfab: error: " << e.what() << "\n";
    return kInvalid;
  }
  if (f.thickness) options.material.thickness = *f.thickness;
  if (f.shear_modulus) options.material.shear_modulus = *f.shear_modulus;
  if (f.yield_strength) options.material.yield_strength = *f.yield_strength;
  if (f.safety) options.material.safety = *f.safety;
  options.kerf.constant_cuts_per_quad = f.constant_density;
  {
    // Paper sizes by name (ISO 216 and US letter, portrait); paper models print on A4 unless
    // told otherwise.
    std::string sheet = f.sheet;
    if (f.material == "paper" && f.sheet_option && f.sheet_option->count() == 0) sheet = "A4";
    // Printed lines must be visible; a laser driver wants hairlines.
    if (f.material == "paper" && f.stroke_option && f.stroke_option->count() == 0)
      output.style.stroke = 0.2;
    // Offcuts first, the stock sheet last: "300x200,600x450".
    std::vector<kerfab::Vec2> sizes;
    std::stringstream list(sheet);
    std::string item;
    while (std::getline(list, item, ',')) {
      std::string lower = item;
      for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (lower == "a4") item = "210x297";
      if (lower == "a3") item = "297x420";
      if (lower == "letter") item = "215.9x279.4";
      double w = 0, h = 0;
      char x = 0, rest = 0;
      if (std::sscanf(item.c_str(), "%lf%c%lf%c", &w, &x, &h, &rest) != 3 ||
          (x != 'x' && x != 'X') || !(w > 0) || !(h > 0) || !(w <= 10000) || !(h <= 10000) ||
          sizes.size() >= 100) {
        sizes.clear();
        break;
      }
      sizes.emplace_back(w, h);
    }
    if (sizes.empty() || sheet.empty() || sheet.back() == ',') {
      std::cerr << "kerfab: error: --sheet must be WxH in mm, each side in (0, 10000], e.g. "
                   "600x450, or A4, A3, letter, or up to 100 such sizes comma separated "
                   "(offcuts first, the stock sheet last), got '"
                << kerfab::one_line(f.sheet) << "'\n";
      return kInvalid;
    }
    options.layout.sheet_width = sizes.back().x();
    options.layout.sheet_height = sizes.back().y();
    options.layout.offcuts.assign(sizes.begin(), sizes.end() - 1);
  }
  {
    output.formats = {false, false, false};
    std::stringstream list(f.format);
    std::string item;
    while (std::getline(list, item, ',')) {
      if (item == "svg") {
        output.formats.svg = true;
      } else if (item == "dxf") {
        output.formats.dxf = true;
      } else if (item == "pdf") {
        output.formats.pdf = true;
      } else {
        std::cerr << "kerfab: error: --format: unknown or unavailable format '" << item
                  << "' (svg, dxf, pdf)\n";
        return kInvalid;
      }
    }
  }
  if (f.features_deg) options.strips.features = *f.features_deg * M_PI / 180.0;
  options.strips.projection =
      f.projection == "closest" ? kerfab::Projection::kClosest : kerfab::Projection::kNormal;
  if (!f.stop_after.empty()) options.stop_after = f.stop_after;
  options.max_memory_mb = f.max_memory_mb;
  const double memory_limit_mb = limit_memory(f.max_memory_mb);
  std::optional<kerfab::OutputFolder> folder;
  auto fail = [&](int code, const char* kind, const std::string& message) {
    std::cerr << "kerfab: error: " << kerfab::one_line(message);
    if (folder && !folder->fail(code, kind, message))
      std::cerr << " (" << kerfab::one_line(folder->dir().string()) << " is as it was)";
    std::cerr << "\n";
    return code;
  };
  try {
    folder.emplace(out);
    kerfab::Progress progress;
    if (!f.quiet) progress = [](std::string_view line) { std::cerr << line << "\n"; };
    const kerfab::RunResult result = kerfab::run_pipeline(inputs, options, progress);
    kerfab::write_run(result, output, folder->staging());
    folder->commit();
    // The run is in place: nothing after this may turn it into a failure.
    try {
      for (const auto& w : result.warnings) std::cerr << "kerfab: warning: " << w << "\n";
      if (!f.quiet)
        std::cerr << "done in " << result.total_seconds
                  << " s; report: " << kerfab::one_line((folder->dir() / "report.json").string())
                  << "\n";
    } catch (...) {
    }
    return kOk;
  } catch (const kerfab::InvalidInput& e) {
    return fail(kInvalid, "invalid_input", e.what());
  } catch (const kerfab::IoError& e) {
    return fail(kIo, "io", e.what());
  } catch (const kerfab::SolverError& e) {
    return fail(kSolver, "solver", e.what());
  } catch (const std::bad_alloc&) {
    return fail(kInvalid, "invalid_input",
                "out of memory: the run needed more than its limit of " +
                    std::to_string(std::llround(memory_limit_mb)) +
                    " MB (--max-memory, or a lower limit set outside kerfab; this machine has " +
                    std::to_string(std::llround(machine_memory_mb())) +
                    " MB): raise it, or ask for less work (a coarser quad mesh, fewer rulings)");
  } catch (const std::exception& e) {
    return fail(kInternal, "internal", std::string("internal error: ") + e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"kerfab " KERFAB_VERSION
               ": turns a 3D shape into laser-cut, kerfed parts of stiff sheet material.\n"
               "Lengths are millimetres, angles degrees on the command line."};
  app.require_subcommand(1);

  RunFlags run_flags;
  std::string quad_help =
      "Quad (or any polygon, with --subdivide) mesh on the target, same frame and units; "
      "without it kerfab uses the target itself when it is all quads (or with --subdivide), "
      "else makes one from the target's triangles and polygons (see --quads, --quad-size; "
      "written to model/quads.obj)";
  CLI::App* run_cmd = app.add_subcommand("run", "Run the pipeline on a target and a quad mesh");
  run_cmd->add_option("--target", run_flags.target, "Target mesh (.obj .off .ply .stl)")
      ->required();
  run_cmd->add_option("--quad", run_flags.quad, quad_help);
  run_cmd->add_option("--guidance", run_flags.guidance,
                      "JSON file {\"bendable\": [[v0,v1],...], \"stiff\": [...], \"split\": [...], "
                      "\"merge\": [...]}: quad-mesh edges (vertex indices of the quad mesh as "
                      "used) forced bendable or stiff, strip borders inserted, strips merged "
                      "sideways");
  run_cmd->add_option("--out", run_flags.out, "Output directory")->required();
  add_pipeline_options(*run_cmd, run_flags);

  RunFlags demo_flags;
  demo_flags.options.input.subdivide = 1;
  demo_flags.output.dump = true;
  CLI::App* demo_cmd = app.add_subcommand(
      "demo",
      "Run the bundled example: Spot (public domain) at 250 mm, control mesh with one "
      "Catmull-Clark step");
  demo_cmd->add_option("--out", demo_flags.out, "Output directory")->capture_default_str();
  demo_flags.out = "out/demo";
  add_pipeline_options(*demo_cmd, demo_flags);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::string message = e.what();
    if (message.empty()) message = "no subcommand given (run or demo; see kerfab --help)";
    std::cerr << "kerfab: error: " << kerfab::one_line(message) << " (see kerfab --help)\n";
    return kInvalid;
  }
  for (const CLI::App* cmd :
       {static_cast<const CLI::App*>(run_cmd), static_cast<const CLI::App*>(demo_cmd)})
    if (*cmd)
      if (const auto message = non_finite_option(*cmd)) {
        std::cerr << "kerfab: error: " << kerfab::one_line(*message) << "\n";
        return kInvalid;
      }
  stop_on_signals();

  if (*run_cmd) {
    kerfab::RunInputs inputs{.target = run_flags.target};
    if (!run_flags.quad.empty()) inputs.quad = run_flags.quad;
    if (!run_flags.guidance.empty()) inputs.guidance = run_flags.guidance;
    return run(inputs, run_flags);
  }
  const fs::path examples = KERFAB_EXAMPLE_DIR;
  kerfab::RunInputs inputs{.target = examples / "spot" / "spot_triangulated.obj",
                           .quad = examples / "spot" / "spot_control_mesh.obj"};
  if (!demo_flags.size) demo_flags.size = 250.0;
  return run(inputs, demo_flags);
}

// Hostile inputs: broken files of every format, special files, huge header counts, non-finite
// numbers, bad guidance, sheets nothing fits. Each ends in one line "kerfab: error: ...", the
// documented exit code, quickly, and writes no cut files.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "cli_util.h"
#include "kerfab/io/mesh_io.h"
#include "shapes.h"
#include "test_util.h"

namespace kerfab {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string name, content;  // file name (its extension picks the reader) and bytes
  int exit_code;
  std::string says;  // a piece of the error line
};

std::string binary_stl(std::uint32_t count, int triangles_written) {
  std::string s(80, ' ');
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < triangles_written; ++t) s.append(50, '\0');
  return s;
}

/// A closed tetrahedron (100 mm legs) as binary STL, one corner of triangle \p bad (1-based;
/// 0: none) set to NaN.
std::string tetrahedron_stl(int bad, const std::string& header = "") {
  const float p[4][3] = {{0, 0, 0}, {100, 0, 0}, {0, 100, 0}, {0, 0, 100}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string s = header;
  s.resize(80, ' ');
  const std::uint32_t count = 4;
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < 4; ++t) {
    float floats[12] = {};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) floats[3 + 3 * c + k] = p[faces[t][c]][k];
    if (t + 1 == bad) floats[6] = std::nanf("");
    s.append(reinterpret_cast<const char*>(floats), sizeof floats);
    s.append(2, '\0');
  }
  return s;
}

void expect_one_line_failure(const test::CliRun& r, int code, const std::string& says,
                             const fs::path& out, const std::string& what) {
  EXPECT_EQ(r.exit_code, code) << what << "\n" << r.err;
  const auto lines = test::message_lines(r.err);
  ASSERT_EQ(lines.size(), 1u) << what << "\n" << r.err;
  EXPECT_EQ(lines[0].rfind("kerfab: error: ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(says), std::string::npos) << what << ": " << lines[0];
  EXPECT_FALSE(fs::exists(out / "cut")) << what;
}

TEST(HostileInput, BrokenMeshFilesEndInOneClearLine) {
  const fs::path scratch = test::fresh_dir();
  const std::string quad = "v 0 0 0\nv 100 0 0\nv 100 100 0\nv 0 100 0\n";
  const std::vector<Case> cases = {
      {"nan.stl",
       "solid x\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 100 0 0\nvertex 0 100 "
       "0\nendloop\nendfacet\nendsolid x\n",
       1, "non-finite number 'nan'"},
      {"inf.obj", "v 0 0 0\nv 100 0 0\nv 100 inf 0\nv 0 100 0\nf 1 2 3 4\n", 1,
       "non-finite number 'inf'"},
      {"nan.off", "OFF\n4 1 0\n0 0 0\n100 0 0\n100 -nan 0\n0 100 0\n4 0 1 2 3\n", 1,
       "non-finite number '-nan'"},
      {"nan.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n100 "
       "0 0\n100 100 NaN\n0 100 0\n4 0 1 2 3\n",
       1, "non-finite number 'NaN'"},
      // A coordinate that is no number, or past a float's range: the readers dropped the line
      // or read garbage and the run said "no faces", "out-of-range vertex index" or "zero area".
      {"word.obj", "v 0 0 0\nv 100 0 0\nv 100 abc 0\nv 0 100 0\nf 1 2 3 4\n", 1,
       "mesh line 3: 'abc' is not a number"},
      {"far.stl",
       "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e300 0 0\nvertex 0 100 "
       "0\nendloop\nendfacet\nendsolid x\n",
       1, "mesh line 5: 1e300 is out of range"},
      {"hex.off", "OFF\n4 1 0\n0 0 0\n0x10 0 0\n100 100 0\n0 100 0\n4 0 1 2 3\n", 1,
       "mesh line 4: '0x10' is not a number"},
      {"word.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n100 "
       "0 0\n100 100 1.5.3\n0 100 0\n4 0 1 2 3\n",
       1, "mesh line 12: '1.5.3' is not a number"},
      {"huge.off", "OFF\n999999999999 1 0\n0 0 0\n", 1, "header promises 999999999999 vertices"},
      {"huge.ply",
       "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float "
       "y\nproperty float z\nend_header\n0 0 0\n",
       1, "header promises 4000000000 vertices"},
      {"negative.off", "OFF\n-4 1 0\n0 0 0\n", 1, "negative count"},
      {"huge.stl", binary_stl(1000000000u, 2), 1, "header promises 1000000000 triangles"},
      {"truncated.stl", binary_stl(12u, 5), 1, "header promises 12 triangles"},
      // The reader dropped the triangle, and the tetrahedron was cut open without a word.
      // A stray vertex 1e30 away made every real face "zero area" next to the model's extent,
      // and the line said only that.
      {"stray.obj", quad + "v 1e30 0 5\nf 1 2 3 4\nf 2 5 3\n", 1,
       "vertex 4 at (1e+30, 0, 5) lies 1e+30 from the middle of the others: a stray vertex?"},
      {"nan-binary.stl", tetrahedron_stl(2), 1,
       "binary STL triangle 2 has a non-finite coordinate (nan or inf)"},
      // Binary, though its header starts with "solid" (as some exporters write it): the reader
      // goes by the size and read it as binary, the check as ASCII, and the tetrahedron came
      // out open with exit 0.
      {"nan-solid-binary.stl", tetrahedron_stl(3, "solid exported"), 1,
       "binary STL triangle 3 has a non-finite coordinate (nan or inf)"},
      {"outside.obj", quad + "f 1 2 3 99\n", 1, "out-of-range vertex index"},
      {"repeated.obj", quad + "f 1 2 2 4\n", 1, "a face repeats vertex 2"},
      {"empty.obj", "", 1, "no faces"},
      {"nonmanifold.obj",
       quad + "v 0 0 100\nv 0 0 -100\nv 50 0 50\nf 1 2 3 4\nf 1 2 5\nf 2 1 6\nf 1 2 7\n", 1,
       "not manifold"},
  };
  for (const Case& c : cases) {
    const fs::path file = scratch / c.name, out = scratch / ("out-" + c.name);
    test::write_text(file, c.content);  // bytes as they are (NULs too)
    const auto r = test::run_cli(
        "run --quiet --target " + file.string() + " --size 100 --out " + out.string(), scratch);
    expect_one_line_failure(r, c.exit_code, c.says, out, c.name);
  }
}

// Inputs the fuzzers found (scripts/fuzz.sh), kept: an OBJ face corner without a vertex index
// aborted inside OpenMesh's reader (an assertion), an OFF face count that is not a whole number
// made it loop for minutes.
TEST(HostileInput, FuzzerFindingsStayFixed) {
  const fs::path scratch = test::fresh_dir();
  const fs::path dir = fs::path(KERFAB_TEST_DATA) / "fuzz";
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".md") continue;
    ++files;
    const fs::path out = scratch / ("out-" + e.path().filename().string());
    const auto r = test::run_cli(
        "run --quiet --target " + e.path().string() + " --size 100 --out " + out.string(), scratch);
    expect_one_line_failure(r, 1, "line", out, e.path().filename().string());
  }
  EXPECT_GE(files, 2);
}

TEST(HostileInput, SpecialFilesAreRefusedByTypeBeforeReading) {
  const fs::path scratch = test::fresh_dir();
  ASSERT_EQ(mkfifo((scratch / "fifo.obj").c_str(), 0644), 0);
  fs::create_symlink("/dev/zero", scratch / "zero.obj");
  fs::create_directories(scratch / "folder.obj");
  for (const std::string name : {"fifo.obj", "zero.obj", "folder.obj"}) {
    const fs::path out = scratch / ("out-" + name);
    const auto r = test::run_cli(
        "run --quiet --target " + (scratch / name).string() + " --out " + out.string(), scratch);
    expect_one_line_failure(r, 2, name == "folder.obj" ? "is a directory" : "not a regular file",
                            out, name);
  }
  // The guidance file too.
  const fs::path target = scratch / "plane.obj";
  write_mesh(test::quad_plane(100, 4).quads, target);
  for (const std::string name : {"fifo.obj", "folder.obj"}) {
    const fs::path out = scratch / ("guided-" + name);
    const auto r = test::run_cli("run --quiet --target " + target.string() + " --guidance " +
                                     (scratch / name).string() + " --out " + out.string(),
                                 scratch);
    expect_one_line_failure(r, 2, "not a regular file", out, "guidance " + name);
  }
}

TEST(HostileInput, GuidanceIndicesNeverWrapOntoRealVertices) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "plane.obj";
  write_mesh(test::quad_plane(100, 4).quads, target);
  for (const std::string pair : {"[4294967296, 4294967297]", "[-1, 0]", "[0, 1.5]", "[0, 99]"}) {
    test::write_text(scratch / "g.json", "{\"stiff\": [" + pair + "]}");
    const fs::path out = scratch / "out";
    fs::remove_all(out);
    const auto r = test::run_cli("run --quiet --target " + target.string() + " --guidance " +
                                     (scratch / "g.json").string() + " --out " + out.string(),
                                 scratch);
    expect_one_line_failure(r, 1, "guidance", out, pair);
  }
}

TEST(HostileInput, ASheetNothingFitsIsAnInputErrorAndManySheetsAreStillWritten) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "cube.obj";
  write_mesh(test::sphere(50, 1).quads, target);  // a cube of six 100 mm plates
  const fs::path out = scratch / "small";
  auto r = test::run_cli(
      "run --quiet --target " + target.string() + " --sheet 40x40 --out " + out.string(), scratch);
  expect_one_line_failure(r, 1, "no part fits a 40 x 40 mm sheet", out, "40x40");
  // A sheet with no room inside its margins (10 mm, and 3 mm for the teeth) is refused before
  // any stage runs: it was refused by the layout, after every stage before it.
  const fs::path none = scratch / "none";
  r = test::run_cli(
      "run --target " + target.string() + " --sheet 600x450,20x20 --out " + none.string(), scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(
                "kerfab: error: --sheet: the 20 x 20 mm sheet has no room inside margins of 13 mm"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("[load]"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(none / "cut"));
  // Parts with nothing left once cut are not parts too big for the sheet: an open triangular
  // prism 60 mm long and 5 mm across, whose three faces' mitres (folds of 120 deg) meet in the
  // middle of each, once said "no part fits a 600 x 450 mm sheet".
  {
    const fs::path prism = scratch / "prism.obj";
    std::ofstream f(prism);
    const double radius = 5 / std::sqrt(3.0);
    for (int i = 0; i <= 4; ++i)
      for (int k = 0; k < 3; ++k) {
        const double a = M_PI / 2 + 2 * M_PI * k / 3;
        f << "v " << 15 * i << " " << radius * std::sin(a) << " " << radius * std::cos(a) << "\n";
      }
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k)
        f << "f " << 3 * i + k + 1 << " " << 3 * (i + 1) + k + 1 << " "
          << 3 * (i + 1) + (k + 1) % 3 + 1 << " " << 3 * i + (k + 1) % 3 + 1 << "\n";
    f.close();
    const fs::path thin = scratch / "thin";
    r = test::run_cli(
        "run --quiet --target " + prism.string() + " --size 60 --out " + thin.string(), scratch);
    expect_one_line_failure(r, 1, "every part has nothing left once its slots and mitres are cut",
                            thin, "prism");
  }
  // Tiny sheets: every sheet written, one preview each, a contact sheet of all of them.
  const fs::path sphere = scratch / "sphere.obj";
  write_mesh(test::sphere(40, 4).quads, sphere);
  const fs::path many = scratch / "many";
  r = test::run_cli("run --quiet --target " + sphere.string() +
                        " --size 120 --sheet 60x60 --margin 0 --spacing 0 --format svg --out " +
                        many.string(),
                    scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = test::read_report(many);
  const int sheets = report["layout"]["sheets"].get<int>();
  EXPECT_GT(sheets, 10);
  int svg = 0, png = 0;
  for (const auto& e : fs::directory_iterator(many / "cut")) {
    svg += e.path().extension() == ".svg" ? 1 : 0;
    png += e.path().extension() == ".png" ? 1 : 0;
  }
  EXPECT_EQ(svg, sheets);
  EXPECT_EQ(png, sheets + 1);  // and the contact sheet
  // Parts that fit no sheet make the run "incomplete", never "ok".
  if (!report["layout"]["unplaced"].empty()) {
    EXPECT_EQ(report["status"], "incomplete");
  }
}

// Options that would ask for runaway work are refused before the work, naming what it would be.
TEST(HostileInput, RunawayWorkIsRefusedBeforeItStarts) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "plane.obj";
  write_mesh(test::quad_plane(100, 4).quads, target);
  const std::string run = "run --quiet --target " + target.string() + " --out ";
  auto r = test::run_cli(run + (scratch / "a").string() + " --max-ruling-spacing 1e-6", scratch);
  expect_one_line_failure(r, 1, "(at most 250000)", scratch / "a", "ruling spacing");
  r = test::run_cli(run + (scratch / "b").string() + " --tooth-width 1e-6", scratch);
  expect_one_line_failure(r, 1, "--tooth-width must be >= 1 mm", scratch / "b", "tooth width");
  // Absurdly large: every border was left without a joint and the run ended as if fine; a
  // spacing wider than the sheet ran every stage, then blamed the sheet's size.
  r = test::run_cli(run + (scratch / "b2").string() + " --tooth-width 1e6", scratch);
  expect_one_line_failure(r, 1, "--tooth-width must be at most 100 mm", scratch / "b2",
                          "tooth width");
  r = test::run_cli(run + (scratch / "b3").string() + " --spacing 500", scratch);
  expect_one_line_failure(r, 1,
                          "--spacing 500 mm leaves no room for a part on the 600 x 450 mm sheet",
                          scratch / "b3", "spacing");
  r = test::run_cli(run + (scratch / "b4").string() + " --kerf-width 100", scratch);
  expect_one_line_failure(r, 1, "--kerf-width: Value 100 not in range", scratch / "b4",
                          "kerf width");
  const std::string spot = test::real_mesh("spot_triangulated.obj").string();
  const std::string cage = test::real_mesh("spot_control_mesh.obj").string();
  r = test::run_cli("run --quiet --target " + spot + " --quad " + cage +
                        " --subdivide 3 --size 250 --rulings-per-quad 64 --no-coarsen --out " +
                        (scratch / "c").string(),
                    scratch);
  expect_one_line_failure(r, 1, "749568 sub-quads", scratch / "c", "rulings per quad");
}

// Joint options no joint can be made with are refused before any stage runs, naming the limit
// the sheet sets. Each ran every stage before and ended with exit 0 (or, --thickness 200, with
// "every part has nothing left" after 34 s): --min-tooth-depth 1e6 left all 443 of Spot's
// borders without a joint, --protrusion 1e6 let teeth stand out of the surface, --thickness 40
// inverted 54 quads in the flattening after 107 s. So is a minimum spacing of kerf cuts no wider
// than the laser's kerf: Spot's control mesh at 250 mm with --min-cut-spacing 0.1 ran to the end
// with exit 0 and cuts 0.43 mm apart (0.28 mm of MDF between two 0.15 mm kerfs).
TEST(HostileInput, JointAndKerfOptionsTheSheetCannotTakeAreRefusedBeforeAnyStage) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "plane.obj";
  write_mesh(test::quad_plane(100, 4).quads, target);
  const std::string run = "run --target " + target.string() + " --out ";
  const std::vector<std::array<std::string, 2>> cases = {
      {"--thickness 40",
       "--thickness 40 mm is thicker than a laser cuts MDF or plywood (at most 25 mm)"},
      {"--protrusion 1e6",
       "--protrusion 1e+06 mm lets a box tooth stand out of the surface by "
       "more than the 3 mm sheet is thick; at most 3 mm"},
      {"--material mdf2 --tab-misfit 2.5",
       "--tab-misfit 2.5 mm lets a dovetail tab stand out of "
       "the surface by more than the 2 mm sheet is thick"},
      {"--min-tooth-depth 1e6",
       "--min-tooth-depth 1e+06 mm is deeper than any box tooth in a 3 "
       "mm sheet (at most 17.28 mm, at a 170 degree fold)"},
      {"--tooth-width 1e6", "--tooth-width must be at most 100 mm"},
      {"--min-cut-spacing 0.15",
       "--min-cut-spacing 0.15 mm is no wider than the laser's kerf (--kerf-width 0.15 mm): "
       "neighbouring cuts would overlap"},
      {"--kerf-width 0.5 --min-cut-spacing 0.4",
       "--min-cut-spacing 0.4 mm is no wider than the laser's kerf (--kerf-width 0.5 mm)"}};
  int k = 0;
  auto next_out = [&] {      // o0, o1, ...: a fresh --out per run
    std::string name = "o";  // built in place: GCC 12 warns falsely on "o" + a temporary
    name += std::to_string(k++);
    return scratch / name;
  };
  for (const auto& [option, message] : cases) {
    const fs::path out = next_out();
    const auto r = test::run_cli(run + out.string() + " " + option, scratch);
    EXPECT_EQ(r.exit_code, 1) << option << ": " << r.err;
    EXPECT_NE(r.err.find("kerfab: error: " + message), std::string::npos)
        << option << ": " << r.err;
    EXPECT_EQ(r.err.find("[load]"), std::string::npos) << option << ": " << r.err;
    EXPECT_FALSE(fs::exists(out / "cut")) << option;
  }
  // At the limits, and in paper (no teeth: the tab misfit and tooth depth do not apply), the
  // run goes on.
  for (const std::string& option :
       {std::string("--thickness 25 --stop-after prepare"),
        std::string("--protrusion 3 --tab-misfit 3 --min-tooth-depth 17 --stop-after prepare"),
        std::string("--min-cut-spacing 0.16 --stop-after prepare"),
        std::string("--material paper --min-cut-spacing 0.1 --stop-after prepare"),
        std::string(
            "--material paper --tab-misfit 5 --min-tooth-depth 100 --stop-after prepare")}) {
    const fs::path out = next_out();
    const auto r = test::run_cli(run + out.string() + " --quiet " + option, scratch);
    EXPECT_EQ(r.exit_code, 0) << option << ": " << r.err;
  }
}

// Memory: --max-memory refuses work that would not fit before it starts, naming the budget; a
// limit reached during the run (here the address space, set outside kerfab, at sizes where the
// solver once crashed starting a thread and the flattening ended in an internal error) ends in
// one line and exit 1, never a signal, and writes nothing.
TEST(HostileInput, MemoryLimitsEndInOneLineNeverACrash) {
  const fs::path scratch = test::fresh_dir();
  const std::string spot = test::real_mesh("spot_triangulated.obj").string();
  const std::string cage = test::real_mesh("spot_control_mesh.obj").string();
  const std::string run = "run --quiet --no-resolve --target " + spot + " --quad " + cage +
                          " --subdivide 1 --size 250 --out ";
  // 3238 sub-quads need about 64 MB + 3238 * 4 KB = 77 MB by kerfab's own estimate.
  auto r = test::run_cli(run + (scratch / "a").string() + " --max-memory 70", scratch);
  expect_one_line_failure(r, 1, "3238 sub-quads, needing about 77 MB (over --max-memory 70 MB)",
                          scratch / "a", "budget");
  // A new --out gets the failure report only.
  auto failed_alone = [](const fs::path& out) {
    return fs::exists(out / "report.json") && test::read_report(out)["status"] == "failed" &&
           std::distance(fs::directory_iterator(out), fs::directory_iterator()) == 2;  // + marker
  };
  EXPECT_TRUE(failed_alone(scratch / "a"));
  r = test::run_cli(run + (scratch / "b").string() + " --max-memory 63", scratch);
  expect_one_line_failure(r, 1, "--max-memory", scratch / "b", "budget under 64 MB");
  for (const std::string kb : {"50000", "58000", "62000", "66000"}) {
    const fs::path out = scratch / kb;
    const std::string what = "ulimit -v " + kb;
    r = test::run_cli(run + out.string(), scratch, what);
    if (r.exit_code == 0) {  // it fitted after all: then it is a whole run (without --resolve
                             // Spot has parts that fell apart: "incomplete", as without a limit)
      const auto report = test::read_report(out);
      EXPECT_NE(report["status"], "failed") << what;
      EXPECT_TRUE(report.contains("quality")) << what;
      continue;
    }
    expect_one_line_failure(r, 1, "out of memory", out, what);
    EXPECT_NE(r.err.find("MB (--max-memory, or a lower limit set outside kerfab"),
              std::string::npos)
        << what << ": " << r.err;
    EXPECT_TRUE(failed_alone(out)) << what;
  }
}

// Paths with spaces and bytes that are not UTF-8 work like any other.
TEST(HostileInput, UnusualPathsWork) {
  const fs::path scratch = test::fresh_dir();
  const fs::path dir = scratch / "my shapes \xe9\xff";
  fs::create_directories(dir);
  const fs::path target = dir / "plane one.obj";
  write_mesh(test::quad_plane(100, 4).quads, target);
  const auto r = test::run_cli(
      "run --quiet --target '" + target.string() + "' --out '" + (dir / "out put").string() + "'",
      scratch);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::read_report(dir / "out put")["status"], "ok");
}

}  // namespace
}  // namespace kerfab

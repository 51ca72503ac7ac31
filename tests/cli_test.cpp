// End-to-end tests of the kerfab command line: exit codes, one-line errors, report files.
#include <cairo.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <tuple>

#include "cli_util.h"
#include "kerfab/adapters/target_surface.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/layout/layout.h"
#include "kerfab/pipeline/notes.h"
#include "kerfab/pipeline/stages.h"
#include "shapes.h"
#include "sheet_audit.h"
#include "test_util.h"

namespace kerfab {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::message_lines;
using test::read_report;
using test::run_cli;

// Optional extra check on the shared collection: every real mesh either loads and is summarised,
// or fails with one clear line and exit code 1.
TEST(Cli, SharedMeshesLoadOrFailWithOneClearLine) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir();
  int loaded = 0, refused = 0, mixed = 0;
  for (const auto& entry : fs::directory_iterator(test::shared_meshes())) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl") continue;
    const fs::path out = scratch / entry.path().stem();
    const CliRun r = run_cli("run --target " + entry.path().string() + " --size 200 --out " +
                                 out.string() + " --stop-after prepare",
                             scratch);
    const std::string name = entry.path().filename().string();
    ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << name << ": exit " << r.exit_code << "\n"
                                                      << r.err;
    const auto report = read_report(out);
    if (r.exit_code == 0) {
      ++loaded;
      EXPECT_EQ(report["status"], "ok") << name;
      EXPECT_NE(r.err.find("target: "), std::string::npos) << name << "\n" << r.err;
      double largest = 0;  // --size 200 makes the largest bounding-box side 200 mm
      for (const auto& side : report["input"]["bbox_mm"])
        largest = std::max(largest, side.get<double>());
      EXPECT_NEAR(largest, 200.0, 1e-6) << name;
      EXPECT_TRUE(fs::exists(out / "model" / "target.obj")) << name;
      // A mesh of triangles and quads is meshed as it stands, and the run says how to smooth
      // it as a cage instead; following that loads it too.
      const auto sizes = report["input"]["target_mesh"]["face_sizes"];
      if (sizes.size() > 1) {
        ++mixed;
        EXPECT_NE(r.err.find("pass --subdivide 1 to smooth it first"), std::string::npos)
            << name << "\n"
            << r.err;
        EXPECT_EQ(report["input"]["quad"], nullptr) << name;  // the quads stage's to make
        const CliRun again =
            run_cli("run --target " + entry.path().string() + " --subdivide 1 --size 200 --out " +
                        out.string() + " --stop-after prepare",
                    scratch);
        EXPECT_EQ(again.exit_code, 0) << name << "\n" << again.err;
        EXPECT_EQ(read_report(out)["status"], "ok") << name;
        EXPECT_GT(read_report(out)["input"]["quads"].get<int>(), 0) << name;
      }
    } else {
      ++refused;
      const auto lines = message_lines(r.err);
      ASSERT_EQ(lines.size(), 1u) << name << "\n" << r.err;
      EXPECT_EQ(lines[0].rfind("kerfab: error: ", 0), 0u) << name << "\n" << r.err;
      EXPECT_EQ(report["status"], "failed") << name;
      EXPECT_FALSE(fs::exists(out / "model")) << name;
    }
  }
  // 8 all-quad meshes load as their own quad mesh (amo_quad, cube_quad, fandisk_quads,
  // horse_quad, two inspired_mesh quads, quad-plane, spot_quadrangulated), 14 triangle-only
  // ones and 3 of triangles and quads (cylinder, quad-sphere, spot_control_mesh) load as
  // targets for the quads stage.
  EXPECT_EQ(loaded, 25);
  EXPECT_EQ(refused, 0);
  EXPECT_EQ(mixed, 3);
}

TEST(Cli, ExitCodesForMissingFileBadOptionAndUnits) {
  const fs::path scratch = test::fresh_dir();
  const std::string spot = test::real_mesh("spot_triangulated.obj").string();
  const std::string cage = test::real_mesh("spot_control_mesh.obj").string();
  CliRun r = run_cli(
      "run --target " + (scratch / "missing.obj").string() + " --out " + (scratch / "a").string(),
      scratch);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(message_lines(r.err).size(), 1u) << r.err;
  r = run_cli("run --target " + spot + " --quad " + cage + " --alignment -1 --out " +
                  (scratch / "b").string(),
              scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  // Absurd but positive numbers: --alignment 1e300 aborted inside CLP (exit 134); a cutting
  // speed of 1e-300 mm/s reported 8.6e302 minutes. Each is one line now, before any stage.
  // A 1e9 mm stroke kept the sheet writers drawing for over 5 minutes; a 1e-6 deg feature angle
  // kept the quads stage busy as long (every edge of the target sharp; the triangles alone).
  for (const char* absurd :
       {"--alignment 1e300", "--cut-speed 1e-300", "--per-cut-time 1e300", "--shear-modulus 1e-300",
        "--yield-strength 1e300", "--stroke 1e9", "--quad-feature-angle 1e-6"}) {
    const bool quads_stage = std::string(absurd).starts_with("--quad-feature");
    r = run_cli("run --target " + spot + (quads_stage ? "" : " --quad " + cage + " --subdivide 1") +
                    " --size 250 " + absurd + " --out " + (scratch / "b2").string(),
                scratch);
    EXPECT_EQ(r.exit_code, 1) << absurd << ": " << r.err;
    const auto lines = message_lines(r.err);
    ASSERT_EQ(lines.size(), 1u) << absurd << ": " << r.err;
    EXPECT_EQ(lines[0].rfind("kerfab: error: ", 0), 0u) << absurd << ": " << r.err;
  }
  r = run_cli("run --target " + spot + " --quad " + cage + " --subdivide 1 --out " +
                  (scratch / "c").string(),
              scratch);  // unit-sized model without --size
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("--size"), std::string::npos) << r.err;
  EXPECT_EQ(read_report(scratch / "c")["status"], "failed");
  // A directory that is not a kerfab output is never overwritten.
  fs::create_directories(scratch / "mine");
  test::write_text(scratch / "mine" / "notes.txt", "keep me");
  r = run_cli("run --target " + spot + " --quad " + cage + " --subdivide 1 --size 250 --out " +
                  (scratch / "mine").string(),
              scratch);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(fs::exists(scratch / "mine" / "notes.txt"));
  EXPECT_FALSE(fs::exists(scratch / "mine" / "report.json"));
  r = run_cli("--help", scratch);
  EXPECT_EQ(r.exit_code, 0);
  r = run_cli("run --help", scratch);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("[mm]"), std::string::npos);
}

TEST(Cli, SheetStyleOptionsAreCheckedAndReported) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "plane.obj";
  write_mesh(test::quad_plane(100, 8).quads, target);
  const CliRun bad =
      run_cli("run --target " + target.string() + " --out out --cut-colour red", scratch);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("#rrggbb"), std::string::npos) << bad.err;
  const CliRun bad_stroke =
      run_cli("run --target " + target.string() + " --out out --stroke 0", scratch);
  EXPECT_EQ(bad_stroke.exit_code, 1);
}

// A 120 mm cube of 4 x 4 quads a side (the grid cube scaled by 60), as a target in \p scratch.
fs::path cube_120mm(const fs::path& scratch) {
  const fs::path target = scratch / "cube.obj";
  write_mesh(test::cube_grid_mesh(4, [](const Vec3& p) { return Vec3(60 * p); }), target);
  return target;
}

// OBJ text of a box from \p lo to \p hi [mm] as 12 outward triangles (two a face, as an exporter
// writes it), its vertices numbered from \p first + 1.
std::string box_obj(const Vec3& lo, const Vec3& hi, int first = 0) {
  std::ostringstream f;
  for (int i = 0; i < 8; ++i)
    f << "v " << (i & 1 ? hi : lo).x() << " " << (i & 2 ? hi : lo).y() << " "
      << (i & 4 ? hi : lo).z() << "\n";
  for (const auto& t : std::vector<std::array<int, 3>>{{1, 3, 4},
                                                       {1, 4, 2},
                                                       {5, 6, 8},
                                                       {5, 8, 7},
                                                       {1, 2, 6},
                                                       {1, 6, 5},
                                                       {3, 7, 8},
                                                       {3, 8, 4},
                                                       {1, 5, 7},
                                                       {1, 7, 3},
                                                       {2, 4, 8},
                                                       {2, 8, 6}})
    f << "f " << t[0] + first << " " << t[1] + first << " " << t[2] + first << "\n";
  return f.str();
}

// Every vertex of \p part (read back from an SVG sheet) inside the 10 mm margins of its
// sheet of \p w x \p h mm (to 0.1 mm).
void expect_inside_margins(const test::SheetPart& part, double w, double h) {
  for (const Vec2& v : part.outline) {
    EXPECT_GE(v.x(), 10 - 0.1) << part.id;
    EXPECT_GE(v.y(), 10 - 0.1) << part.id;
    EXPECT_LE(v.x(), w - 10 + 0.1) << part.id;
    EXPECT_LE(v.y(), h - 10 + 0.1) << part.id;
  }
}

/// The run in \p out made each of a flat-faced model's \p faces one plate: that many parts, no
/// kerf cut, \p borders borders all box-jointed, the plates on the faces (Hausdorff under
/// 0.01 mm), the sheets clean. Returns the parts read back from the sheets.
std::vector<test::SheetPart> expect_one_plate_per_face(const fs::path& out, int faces,
                                                       std::size_t borders) {
  const auto report = read_report(out);
  EXPECT_EQ(report["resolve"]["parts_after"].get<int>(), faces);
  EXPECT_EQ(report["kerf"]["cuts"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders"].size(), borders);
  for (const auto& b : report["joints"]["borders"]) EXPECT_EQ(b["joint"], "box") << b;
  EXPECT_LT(report["quality"]["hausdorff_mm"].get<double>(), 0.01);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_TRUE(audit.findings.empty()) << audit.findings.front();
  return test::read_sheet_parts(out / "cut");
}

// A box, the simplest thing a maker models, from its triangles (each face 2 x 2 squares, cut
// in two, as an exporter writes it): kerfab meshed it in 8 x 8 quads a face and cut 48 strips,
// each a row of flat quads joined to the next by dovetail tabs along its whole 200 mm, where a
// maker expects 6 panels. Flat panels are now cut as one plate each: 6 parts, each a 200 mm
// square less its box joints (read back from the sheets: its area between that of the square
// cut back all round by a sheet's thickness and the square's own, plus the kerf's half round
// it), every border a box joint, no kerf cut, the sheets clean, and the plates exactly on the
// faces; in paper, 6 panels with glue tabs.
TEST(Cli, ABoxFromItsTrianglesIsCutAsOnePanelPerFace) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "box.obj";
  {
    const PolyMesh grid = test::cube_grid_mesh(2, [](const Vec3& p) { return Vec3(100 * p); });
    std::ofstream f(target);
    for (auto v : grid.vertices()) {
      const auto& p = grid.point(v);
      f << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
    }
    for (auto face : grid.faces()) {
      std::vector<int> q;
      for (auto v : face.vertices()) q.push_back(v.idx() + 1);
      ASSERT_EQ(q.size(), 4u);
      f << "f " << q[0] << " " << q[1] << " " << q[2] << "\nf " << q[0] << " " << q[2] << " "
        << q[3] << "\n";
    }
  }
  const fs::path out = scratch / "out";
  const CliRun r = run_cli("run --target " + target.string() + " --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Panels meeting at right angles are the mitres' work: no two parts closer than the sheets.
  const auto clearance = read_report(out)["quality"]["clearance"];
  EXPECT_TRUE(clearance["contacts"].empty()) << clearance.dump();
  EXPECT_GT(clearance["samples"].get<long>(), 6 * 200 * 200 / 9 / 2);
  const auto parts = expect_one_plate_per_face(out, 6, 12);
  ASSERT_EQ(parts.size(), 6u);
  // The laser path runs half the kerf (0.15 mm) outside the part: up to 0.075 mm times its
  // length more.
  const double side = 200, h = 3;
  for (const auto& p : parts) {
    const double area = std::abs(polygon_area(p.outline));
    double length = 0;
    for (std::size_t i = 0; i < p.outline.size(); ++i)
      length += (p.outline[(i + 1) % p.outline.size()] - p.outline[i]).norm();
    EXPECT_GT(area, (side - 2 * h) * (side - 2 * h)) << p.id;
    EXPECT_LT(area, side * side + 0.075 * length) << p.id;
  }
  // In paper (a 100 mm box on A4): 6 panels, every border glue-tabbed on one side, each panel
  // with a tab root folded as a mountain at every tab, no ruling scored (nothing bends).
  const fs::path paper = scratch / "paper";
  const CliRun pr = run_cli(
      "run --target " + target.string() + " --size 100 --material paper --out " + paper.string(),
      scratch);
  ASSERT_EQ(pr.exit_code, 0) << pr.err;
  const auto pj = read_report(paper);
  EXPECT_EQ(pj["resolve"]["parts_after"].get<int>(), 6);
  EXPECT_EQ(pj["joints"]["borders_without_joint"].get<int>(), 0);
  for (const auto& b : pj["joints"]["borders"]) EXPECT_EQ(b["joint"], "glue") << b;
  EXPECT_EQ(pj["joints"]["fold_lines"]["rulings"].get<int>(), 0);
  EXPECT_EQ(pj["joints"]["fold_lines"]["valley"].get<int>(), 0);
  EXPECT_GE(pj["joints"]["fold_lines"]["mountain"].get<int>(), 12);
  EXPECT_EQ(test::read_sheet_parts(paper / "cut").size(), 6u);
}

// A box exported with some triangles the wrong way round (as STL exporters do) was refused as
// "not manifold"; as a soup (each triangle with its own corners, one of them written twice) it
// was read as 48 loose triangles, cut as that many parts with no joint. Its faces are turned
// round, or its corners welded and the repeated face dropped, and the run says how many. The
// mixed box cuts the sheet the box whose faces all agree cuts, byte for byte; the soup, whose
// corners come in another order, the same six panels.
TEST(Cli, AMeshWithFacesTurnedTheWrongWayCutsTheSheetsOfTheMeshMended) {
  const fs::path scratch = test::fresh_dir();
  const PolyMesh grid = test::cube_grid_mesh(2, [](const Vec3& p) { return Vec3(50 * p); });
  std::vector<std::array<int, 3>> t;
  for (auto face : grid.faces()) {
    std::vector<int> q;
    for (auto v : face.vertices()) q.push_back(v.idx() + 1);
    t.push_back({q[0], q[1], q[2]});
    t.push_back({q[0], q[2], q[3]});
  }
  const std::set<int> turned = {1, 8, 9, 22, 40, 41, 46};
  const std::array<std::string, 3> kinds = {"clean", "mixed", "soup"};
  for (const std::string& kind : kinds) {
    std::ofstream f(scratch / (kind + ".obj"));
    const auto point = [&](int v) {
      const auto& p = grid.point(grid.vertex_handle(v - 1));
      return "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) +
             "\n";
    };
    if (kind != "soup")
      for (int v = 1; v <= static_cast<int>(grid.n_vertices()); ++v) f << point(v);
    for (int i = 0; i < static_cast<int>(t.size()) + (kind == "soup" ? 1 : 0); ++i) {
      const auto& c = t[i % t.size()];
      const bool back = kind == "mixed" && turned.count(i);
      if (kind == "soup")
        f << point(c[0]) << point(c[1]) << point(c[2]) << "f -3 -2 -1\n";
      else
        f << "f " << c[0] << " " << c[back ? 2 : 1] << " " << c[back ? 1 : 2] << "\n";
    }
  }
  std::string sheets[3];
  for (int k = 0; k < 3; ++k) {
    const fs::path out = scratch / ("out-" + kinds[k]);
    const CliRun r = run_cli("run --target " + (scratch / (kinds[k] + ".obj")).string() +
                                 " --size 150 --out " + out.string(),
                             scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto repairs = read_report(out)["input"]["target_repairs"];
    EXPECT_EQ(repairs["faces_turned"].get<int>(), k == 1 ? 7 : 0);
    EXPECT_EQ(r.err.find("7 faces turned the other way") != std::string::npos, k == 1) << r.err;
    // 49 triangles' 147 corners at the box's 26 points.
    EXPECT_EQ(repairs["vertices_welded"].get<int>(), k == 2 ? 147 - 26 : 0);
    EXPECT_EQ(repairs["duplicate_faces"].get<int>(), k == 2 ? 1 : 0);
    EXPECT_EQ(r.err.find("121 vertices at the same point") != std::string::npos, k == 2) << r.err;
    sheets[k] = test::slurp(out / "cut" / "sheet-001.svg");
  }
  EXPECT_FALSE(sheets[0].empty());
  EXPECT_TRUE(sheets[0] == sheets[1]);
  expect_one_plate_per_face(scratch / "out-soup", 6, 12);
}

// A box whose sides were cut into grids of 2, 3, 5, 7, 2 and 3 quads a side, each with its own
// vertices along the box's edges, as modellers export faces meshed one by one: every edge a
// crack, the plates on either side of it with no joint. The cracks are zipped (the run says how
// many vertices): 6 plates, box teeth on all 12 edges.
TEST(Cli, ABoxWhoseSidesWereCutDifferentlyIsZippedAndJointedAllRound) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "cracked.obj";
  write_mesh(test::box_cut_differently({2, 3, 5, 7, 2, 3}), target);
  const fs::path out = scratch / "out";
  const CliRun r = run_cli("run --target " + target.string() + " --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("61 vertices of a crack"), std::string::npos) << r.err;
  expect_one_plate_per_face(out, 6, 12);
}

// A U-shaped block as modellers export it: eight side quads and two caps, each one
// eight-cornered concave polygon (150 x 100 mm less a 50 x 50 notch, 60 mm high). It was
// refused (not all quads; --subdivide would have smoothed it into a blob). Now it is meshed as
// it stands: the caps cut by ear clipping (the fan from their first corner lays a triangle over
// the notch), then the quads stage: one plate per face, each cap the U's area.
TEST(Cli, AMeshOfQuadsAndNGonsIsMeshedAsItStands) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "u.obj";
  const std::vector<std::array<double, 2>> u = {{0, 0},    {150, 0}, {150, 100}, {100, 100},
                                                {100, 50}, {50, 50}, {50, 100},  {0, 100}};
  {
    std::ofstream f(target);
    for (const double z : {0.0, 60.0})
      for (const auto& p : u) f << "v " << p[0] << " " << p[1] << " " << z << "\n";
    f << "f 8 7 6 5 4 3 2 1\nf 9 10 11 12 13 14 15 16\n";
    for (int k = 0; k < 8; ++k)
      f << "f " << k + 1 << " " << (k + 1) % 8 + 1 << " " << (k + 1) % 8 + 9 << " " << k + 9
        << "\n";
  }
  const fs::path out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + target.string() + " --size 200 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("target has 8 quads, 2 8-gons: meshed as it stands"), std::string::npos)
      << r.err;
  const auto report = read_report(out);
  EXPECT_EQ(report["input"]["quad"], nullptr);
  EXPECT_GT(report["quads"]["quads"].get<int>(), 0);
  auto parts = expect_one_plate_per_face(out, 10, 24);
  ASSERT_EQ(parts.size(), 10u);
  // The caps are the two largest: the U's area at 200 / 150, less at most a sheet's thickness
  // (3 mm) along its 800 mm outline, plus the kerf's half round it.
  std::vector<std::pair<double, double>> area_length;
  for (const auto& p : parts) {
    double length = 0;
    for (std::size_t i = 0; i < p.outline.size(); ++i)
      length += (p.outline[(i + 1) % p.outline.size()] - p.outline[i]).norm();
    area_length.emplace_back(std::abs(polygon_area(p.outline)), length);
  }
  std::sort(area_length.rbegin(), area_length.rend());
  const double cap = (150.0 * 100 - 50 * 50) * (4.0 / 3) * (4.0 / 3);
  for (int k = 0; k < 2; ++k) {
    EXPECT_GT(area_length[k].first, cap - 3 * 800) << k;
    EXPECT_LT(area_length[k].first, cap + 0.075 * area_length[k].second) << k;
  }
  // The largest wall: 150 x 60 at 200 / 150.
  EXPECT_LT(area_length[2].first, 200.0 * 80 + 0.075 * area_length[2].second);
}

// A cube exported with two needles (a corner doubled 1e-9 mm away, as some exporters weld
// badly): the needles' area was just over the zero mark, and a CGAL construction on them ended
// the run with a segmentation fault. Their corners are merged: the run warns and cuts the cube
// as six plates.
TEST(Cli, ACubeWithNeedleTrianglesIsMendedAndCutAsSixPlates) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "needles.obj";
  test::write_text(target,
                   "v 0 0 0\nv 100 0 0\nv 100 100 0\nv 0 100 0\nv 0 0 100\nv 100 0 100\n"
                   "v 100 100 100\nv 0 100 100\nv 0.000000001 0 100\n"
                   "f 1 4 3\nf 1 3 2\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n"
                   "f 4 1 5\nf 4 5 9\nf 4 9 8\nf 5 6 7\nf 5 7 9\nf 9 7 8\n");
  const fs::path out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + target.string() + " --size 200 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("target: 2 triangles of no area"), std::string::npos) << r.err;
  EXPECT_EQ(expect_one_plate_per_face(out, 6, 12).size(), 6u);
}

// Two 100 mm cubes from their triangles, glued face to face, each its own closed piece (as a
// modeller exports two blocks): each surface on its own left the quads stage to try four
// lattices for 86 s and fail on folded quads. They are one solid to the maker: the run joins
// them into their union and cuts the six plates of one 200 x 100 x 100 box, one piece to
// assemble, the plates exactly on its faces.
TEST(Cli, TwoCubesGluedFaceToFaceAreCutAsTheSixPlatesOfOneBox) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "glued.obj";
  test::write_text(target,
                   box_obj({0, 0, 0}, {100, 100, 100}) + box_obj({100, 0, 0}, {200, 100, 100}, 8));
  const fs::path out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + target.string() + " --size 200 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("target: 2 solids that overlap or touch joined into one"), std::string::npos)
      << r.err;
  const auto report = read_report(out);
  EXPECT_EQ(report["input"]["united_solids"].get<int>(), 2);
  // The shared face, 100 x 100 mm on each cube, at the size asked (scale 1).
  EXPECT_NEAR(report["input"]["united_surface_gone_mm2"].get<double>(), 2e4, 1e-6);
  EXPECT_EQ(report["assembly"]["pieces"].get<int>(), 1);
  EXPECT_EQ(expect_one_plate_per_face(out, 6, 12).size(), 6u);
}

// A slab 120 x 60 x 1 mm from its 12 triangles, in 3 mm MDF: its top and bottom are 1 mm
// apart, so their sheets, each standing 1.5 mm to either side of its face, would overlap by
// 2 mm. The run says so, names the parts and where, and the size at which they clear
// (120 x 3 / 1 = 360 mm); the same slab 40 mm thick has no such place.
TEST(Cli, ASlabThinnerThanItsSheetsIsNamedWithTheSizeThatClearsIt) {
  const fs::path scratch = test::fresh_dir();
  for (const double thick : {1.0, 40.0}) {
    const fs::path target = scratch / "slab.obj";
    test::write_text(target, box_obj({0, 0, 0}, {120, 60, thick}));
    const fs::path out = scratch / ("out" + std::to_string(static_cast<int>(thick)));
    const CliRun r = run_cli("run --target " + target.string() + " --out " + out.string(), scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto c = read_report(out)["quality"]["clearance"];
    if (thick > 3) {
      EXPECT_TRUE(c["contacts"].empty()) << c.dump();
      EXPECT_EQ(r.err.find("thinner than its"), std::string::npos) << r.err;
      continue;
    }
    ASSERT_FALSE(c["contacts"].empty()) << r.err;
    // The faces lie on the target, so no gap is wider than the slab.
    const double gap = c["min_thin_gap_mm"].get<double>();
    EXPECT_GT(gap, 0);
    EXPECT_LE(gap, thick + 1e-6);
    EXPECT_NEAR(c["size_factor"].get<double>(), 3 / gap, 1e-9);
    for (const auto& k : c["contacts"]) {
      EXPECT_EQ(k["inside_out"].get<int>(), -1) << k;  // thin, not folded over
      // The two points lie on the slab's two faces (z = 0 and z = 1), above one another.
      EXPECT_LE(k["gap_mm"].get<double>(), thick + 1e-6) << k;
    }
    // Most of the two faces (2 x 120 x 60 mm^2) lie over the other; the rim, within the
    // mitres' reach of the edges, does not count.
    EXPECT_GT(c["area_mm2"].get<double>(), 0.5 * 2 * 120 * 60);
    EXPECT_LE(c["area_mm2"].get<double>(), 2 * 120 * 60 + 1);
    const std::string size =
        "at --size " + std::to_string(static_cast<long>(std::ceil(120 * 3 / gap)));
    EXPECT_NE(r.err.find("the shape is thinner than its 3 mm sheets"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(size), std::string::npos) << size << "\n" << r.err;
  }
}

// The bundled house (examples/house, README "Flat-faced models").
fs::path house_obj() { return fs::path(KERFAB_EXAMPLE_DIR) / "house" / "house.obj"; }

// A house from its 16 triangles (200 x 150 mm floor, walls 120 mm high, a gable roof along the
// 200 mm side): with a steep roof (ridge at 240 mm) its eaves fold 28 degrees, at 190 mm 47,
// with a flat roof (ridge at 150 mm) its ridge folds 44, all under --quad-feature-angle (60).
// Those folds are feature lines because planes reach far on both sides (docs/quad-meshing.md),
// so every face is one plate: 7 parts, nothing kerfed. Before, rows of quads crossed those
// folds and the planes beside them were cut as kerfed strips: 36 parts and 138 kerf cuts, 33
// and 339, 17 and 66; at 190 mm, until a corner could stop just short of a feature line, two
// roof quads beside the gable stayed folded 2.4 mm: 9 parts, 12 kerf cuts.
TEST(Cli, AHouseFromItsTrianglesIsCutAsOnePanelPerFace) {
  const fs::path scratch = test::fresh_dir();
  for (const double ridge : {240.0, 190.0, 150.0}) {
    SCOPED_TRACE(ridge);
    // The 190 mm one is the bundled example (README, "Flat-faced models").
    const fs::path target = ridge == 190.0 ? house_obj() : scratch / "house.obj";
    if (ridge != 190.0) {
      std::ofstream f(target);
      f << "v 0 0 0\nv 200 0 0\nv 200 150 0\nv 0 150 0\nv 0 0 120\nv 200 0 120\n"
        << "v 200 150 120\nv 0 150 120\nv 0 75 " << ridge << "\nv 200 75 " << ridge << "\n";
      // floor, front and back walls, the two roof planes, each as two triangles; the gables
      // as three.
      f << "f 1 4 3\nf 1 3 2\nf 1 2 6\nf 1 6 5\nf 3 4 8\nf 3 8 7\nf 5 6 10\nf 5 10 9\n"
        << "f 7 8 9\nf 7 9 10\nf 2 3 7\nf 2 7 6\nf 6 7 10\nf 4 1 5\nf 4 5 8\nf 8 5 9\n";
    }
    const fs::path out = scratch / ("out" + std::to_string(static_cast<int>(ridge)));
    const CliRun r = run_cli("run --target " + target.string() + " --out " + out.string(), scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(expect_one_plate_per_face(out, 7, 15).size(), 7u);
  }
  // At 150 mm the quads crossed the folds at two corners of the house (48.7 mm of its feature
  // lines ran through quads), and all seven plates at once left one defect more, so some were
  // tried one by one (at least 3 plates, under 30 parts). With the lattice lines held on the
  // feature lines no quad crosses a fold: the seven plates.
  const fs::path small = scratch / "size150";
  const CliRun r150 = run_cli(
      "run --target " + house_obj().string() + " --size 150 --out " + small.string(), scratch);
  ASSERT_EQ(r150.exit_code, 0) << r150.err;
  EXPECT_EQ(expect_one_plate_per_face(small, 7, 15).size(), 7u);
}

// An octagonal prism (radius 80, 100 high) at 250 mm: 42 mm of its edges ran through quads
// rather than along their edges, folding those quads round the rims, and the run cut 12 parts,
// 1.33 % of the diagonal off. With the lattice lines held on the feature lines: one plate per
// face, exactly on them.
TEST(Cli, APrismsEdgesRunOnQuadEdgesAndItIsCutAsOnePlatePerFace) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "prism.obj";
  {
    std::ofstream f(target);
    for (const double z : {0.0, 100.0})
      for (int k = 0; k < 8; ++k) {
        const double a = k * M_PI / 4 + M_PI / 8;
        f << "v " << 80 * std::cos(a) << " " << 80 * std::sin(a) << " " << z << "\n";
      }
    f << "v 0 0 0\nv 0 0 100\n";  // the caps as fans of triangles round their centres
    for (int k = 0; k < 8; ++k) {
      const int a = k + 1, b = (k + 1) % 8 + 1;
      f << "f 17 " << b << " " << a << "\nf 18 " << a + 8 << " " << b + 8 << "\n"
        << "f " << a << " " << b << " " << b + 8 << "\nf " << a << " " << b + 8 << " " << a + 8
        << "\n";
    }
  }
  const fs::path out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + target.string() + " --size 250 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_NEAR(report["quads"]["feature_length_on_quad_edges_mm"].get<double>(),
              report["quads"]["feature_length_mm"].get<double>(), 1e-6);
  EXPECT_EQ(expect_one_plate_per_face(out, 10, 24).size(), 10u);
}

// A square pyramid (120 mm square, 90 mm high) and a pentagonal prism (radius 70, 120 high,
// its caps pentagons), as a modeller exports them, at 250 mm: one plate per face. The pyramid
// came out as 4 plates and 28 strips: one quad of a side had three corners on a ridge, the
// middle one 0.01 mm over it, and the plate test read its triangle there, 72 degrees off, as a
// fold. The prism came out as 7 plates and two one-quad strips folded 43 and 52 degrees over its
// bottom rim round a corner of the bottom 0.64 quad sizes inside the rim, between two corners on
// it (Hausdorff 0.72 %): such a dent in a row of corners on a feature line is moved onto it.
TEST(Cli, APyramidAndAPentagonalPrismAreCutAsOnePlatePerFace) {
  const fs::path scratch = test::fresh_dir();
  const fs::path pyramid = scratch / "pyramid.obj", prism = scratch / "prism.obj";
  {
    std::ofstream f(pyramid);
    f << "v 0 0 0\nv 120 0 0\nv 120 120 0\nv 0 120 0\nv 60 60 90\n"
      << "f 4 3 2 1\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n";
  }
  {
    std::ofstream f(prism);
    for (const double z : {0.0, 120.0})
      for (int k = 0; k < 5; ++k)
        f << "v " << 70 * std::cos(2 * M_PI * k / 5) << " " << 70 * std::sin(2 * M_PI * k / 5)
          << " " << z << "\n";
    f << "f 5 4 3 2 1\nf 6 7 8 9 10\n";
    for (int k = 0; k < 5; ++k) {
      const int a = k + 1, b = (k + 1) % 5 + 1;
      f << "f " << a << " " << b << " " << b + 5 << " " << a + 5 << "\n";
    }
  }
  for (const auto& [target, faces, edges] :
       {std::tuple{pyramid, 5, 8u}, std::tuple{prism, 7, 15u}}) {
    SCOPED_TRACE(target.filename().string());
    const fs::path out = scratch / target.stem();
    const CliRun r =
        run_cli("run --target " + target.string() + " --size 250 --out " + out.string(), scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(expect_one_plate_per_face(out, faces, edges).size(), static_cast<size_t>(faces));
  }
}

// An icosahedron (20 triangles, low-poly, as makers cut them) at 250 mm: its 30 edges, all
// sharp, are 4.64 m long, more than quads of the size rule's 22.7 mm can follow (4.55 m), and
// the run was refused with "pass --quad-size 22.3 or less". The size rule now makes the size
// finer itself where the user gave none: 20 plates, box teeth on all 30 edges.
TEST(Cli, ALowPolyShapeGetsQuadsFineEnoughForItsEdges) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "icosahedron.obj";
  {
    std::ofstream f(target);
    const double p = (1 + std::sqrt(5.0)) / 2;
    for (const auto& v : std::vector<std::array<double, 3>>{{-1, p, 0},
                                                            {1, p, 0},
                                                            {-1, -p, 0},
                                                            {1, -p, 0},
                                                            {0, -1, p},
                                                            {0, 1, p},
                                                            {0, -1, -p},
                                                            {0, 1, -p},
                                                            {p, 0, -1},
                                                            {p, 0, 1},
                                                            {-p, 0, -1},
                                                            {-p, 0, 1}})
      f << "v " << 50 * v[0] << " " << 50 * v[1] << " " << 50 * v[2] << "\n";
    for (const auto& t : std::vector<std::array<int, 3>>{
             {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}})
      f << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  }
  const fs::path out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + target.string() + " --size 250 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(read_report(out)["quads"]["size_mm"].get<double>(), 22.3);
  expect_one_plate_per_face(out, 20, 30);
}

// A run's parts are \p plates flat plates and nothing else: every part a plate, no kerf cut,
// every border jointed.
void expect_all_plates(const nlohmann::json& report, int plates) {
  EXPECT_EQ(report["resolve"]["parts_after"].get<int>(), plates);
  EXPECT_EQ(test::resolve_changes(report, "plate"), plates);
  EXPECT_EQ(report["kerf"]["cuts"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
}

// A square frame from its triangles (200 mm outside, a 120 mm hole, 40 mm deep: genus one, all
// flat faces). Its walls were plates, but its top and bottom are rings, no disk, so no plate
// either, and came out a part per quad: 97 parts. A flat face with a hole is now cut in two
// across its middle, each half a plate: 12 parts (8 walls, 2 halves of each ring), nothing
// kerfed, the walls box-jointed, each ring's two cuts joined by dovetail tabs (the halves lie
// in one plane), the plates on the faces, the sheets clean.
TEST(Cli, AFrameFromItsTrianglesIsCutInPlates) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "frame.obj";
  {
    std::ofstream f(target);
    for (const double z : {0.0, 40.0})
      for (const double r : {100.0, 60.0})
        f << "v " << -r << " " << -r << " " << z << "\nv " << r << " " << -r << " " << z << "\nv "
          << r << " " << r << " " << z << "\nv " << -r << " " << r << " " << z << "\n";
    // Outer corners k (1-4 at z 0, 9-12 at z 40), inner corners 5-8 and 13-16.
    for (int k = 0; k < 4; ++k) {
      const int j = (k + 1) % 4;
      const int o0 = 1 + k, o1 = 1 + j, O0 = 9 + k, O1 = 9 + j;    // outer, bottom and top
      const int i0 = 5 + k, i1 = 5 + j, I0 = 13 + k, I1 = 13 + j;  // inner
      f << "f " << o0 << " " << o1 << " " << O1 << "\nf " << o0 << " " << O1 << " " << O0 << "\n"
        << "f " << i1 << " " << i0 << " " << I0 << "\nf " << i1 << " " << I0 << " " << I1 << "\n"
        << "f " << O0 << " " << O1 << " " << I1 << "\nf " << O0 << " " << I1 << " " << I0 << "\n"
        << "f " << o1 << " " << o0 << " " << i0 << "\nf " << o1 << " " << i0 << " " << i1 << "\n";
    }
  }
  const fs::path out = scratch / "out";
  const CliRun r = run_cli("run --target " + target.string() + " --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  expect_all_plates(report, 12);
  int box = 0, tab = 0;
  for (const auto& b : report["joints"]["borders"]) {
    box += b["joint"] == "box" ? 1 : 0;
    tab += b["joint"] == "tab" ? 1 : 0;
  }
  EXPECT_EQ(box + tab, static_cast<int>(report["joints"]["borders"].size()));
  EXPECT_EQ(tab, 4);  // each ring cut at two places, its halves in one plane
  EXPECT_LT(report["quality"]["hausdorff_mm"].get<double>(), 0.01);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_TRUE(audit.findings.empty()) << audit.findings.front();
  EXPECT_EQ(test::read_sheet_parts(out / "cut").size(), 12u);
}

// A box larger than the laser bed (a 250 mm box from its 12 triangles on a 300 x 200 mm bed,
// 280 x 180 mm inside its margins): its faces are flat panels too large for a sheet. They had
// been left as strips, 8 to a face, joined along their whole length by dovetail tabs (48 parts,
// 886 box teeth and 3444 tabs, 60 min of cutting on 12 sheets); now each face is cut in plates
// that fit, as few as take the fewest sheets: two of 250 x 125 mm, 12 parts on 12 sheets,
// 20 min of cutting, nothing kerfed, every border jointed, every part on a sheet.
TEST(Cli, ABoxLargerThanTheBedIsCutInPlatesThatFit) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "box.obj";
  {
    std::ofstream f(target);
    f << box_obj(Vec3(0, 0, 0), Vec3(250, 250, 250));
  }
  const fs::path out = scratch / "out";
  const CliRun r = run_cli(
      "run --target " + target.string() + " --sheet 300x200 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  expect_all_plates(report, 12);
  EXPECT_TRUE(report["layout"]["unplaced"].empty());
  EXPECT_LE(report["layout"]["sheets"].get<int>(), 12);
  EXPECT_LT(report["quality"]["hausdorff_mm"].get<double>(), 0.01);
  // Read back from the sheets: 12 parts, each within the bed's 280 x 180 mm inside its margins
  // and no larger than half a face with its teeth (250 x 125 mm, teeth reaching 1.5 mm).
  const auto parts = test::read_sheet_parts(out / "cut");
  ASSERT_EQ(parts.size(), 12u);
  for (const auto& part : parts) {
    const MinRect rect = min_area_rect(part.outline);
    EXPECT_LE(std::max(rect.width, rect.height), 256.0) << part.id;
    EXPECT_LE(std::min(rect.width, rect.height), 131.0) << part.id;
    EXPECT_GT(std::abs(polygon_area(part.outline)), 0.8 * 250 * 125) << part.id;
  }
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_TRUE(audit.findings.empty()) << audit.findings.front();
}

// The house at 300 mm on a 300 x 200 mm bed: each gable (225 x 285 mm) is larger than the bed,
// so it is cut in two plates, and the cut between them runs along one row of quad edges. Its
// quads are not quite in rows (bent towards the roof), and the first gap over a micrometre
// between their middles cut through a row: one quad stayed on the lower plate as a bump 25 mm
// wide, the seam's quad edges spanning 11 % of the gable's height; now 2 %. Read from
// model/quads.obj and the report's plates (the quads each holds).
TEST(Cli, AGableLargerThanTheBedIsCutAlongOneRowOfQuadEdges) {
  const fs::path scratch = test::fresh_dir();
  const fs::path out = scratch / "out";
  const CliRun r = run_cli(
      "run --target " + house_obj().string() + " --size 300 --sheet 300x200 --out " + out.string(),
      scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const PolyMesh quads = read_mesh(out / "model" / "quads.obj");
  ASSERT_GT(quads.n_faces(), 100u);
  const auto report = read_report(out);
  std::map<int, int> plate_of;  // quad -> the plate change that holds it
  int index = 0;
  for (const auto& c : report["resolve"]["changes"]) {
    if (c["action"] == "plate")
      for (const auto& q : c["quads"]) plate_of[q.get<int>()] = index;
    ++index;
  }
  // The gables: the quads in the planes x = min and x = max of the model.
  double lo = 1e300, hi = -1e300;
  for (auto v : quads.vertices())
    lo = std::min(lo, quads.point(v)[0]), hi = std::max(hi, quads.point(v)[0]);
  for (const double x : {lo, hi}) {
    SCOPED_TRACE(x);
    std::set<int> gable, plates;
    double bottom = 1e300, top = -1e300;
    for (auto f : quads.faces()) {
      bool on = true;
      for (auto v : quads.fv_range(f)) on = on && std::abs(quads.point(v)[0] - x) < 1e-6;
      if (!on) continue;
      gable.insert(f.idx());
      ASSERT_TRUE(plate_of.count(f.idx())) << f.idx();
      plates.insert(plate_of[f.idx()]);
      for (auto v : quads.fv_range(f))
        bottom = std::min(bottom, quads.point(v)[2]), top = std::max(top, quads.point(v)[2]);
    }
    ASSERT_EQ(plates.size(), 2u);
    // The quad edges between its two plates, and how far up and down they run.
    double low = 1e300, high = -1e300;
    for (auto e : quads.edges()) {
      if (quads.is_boundary(e)) continue;
      const int f0 = quads.face_handle(quads.halfedge_handle(e, 0)).idx(),
                f1 = quads.face_handle(quads.halfedge_handle(e, 1)).idx();
      if (!gable.count(f0) || !gable.count(f1) || plate_of[f0] == plate_of[f1]) continue;
      for (auto v : {quads.from_vertex_handle(quads.halfedge_handle(e, 0)),
                     quads.to_vertex_handle(quads.halfedge_handle(e, 0))})
        low = std::min(low, quads.point(v)[2]), high = std::max(high, quads.point(v)[2]);
    }
    ASSERT_LT(low, high);
    EXPECT_LT(high - low, 0.05 * (top - bottom)) << low << " .. " << high;
  }
  EXPECT_TRUE(test::audit_sheets(out / "cut").clean());
}

// Paper sizes by name; paper models go on A4 pages of true size unless told otherwise. A 120 mm
// cube (whose quality stage once needed more than 50 million distance samples and failed) runs
// in paper; the report says the sample spacing it used.
TEST(Cli, PaperSizesByNameAndA4ForPaper) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = cube_120mm(scratch);
  const CliRun paper = run_cli(
      "run --target " + target.string() + " --material paper --out " + (scratch / "a").string(),
      scratch);
  ASSERT_EQ(paper.exit_code, 0) << paper.err;
  const auto report = read_report(scratch / "a");
  EXPECT_EQ(report["layout"]["sheet_mm"], nlohmann::json::array({210.0, 297.0}));
  // Paper creases where a stiff sheet is split: its strips are split only at folds over 100
  // degrees unless told otherwise.
  EXPECT_NEAR(report["options"]["split_angle_deg"].get<double>(), 100, 1e-9);
  EXPECT_GT(report["quality"]["sample_spacing_mm"].get<double>(), 0);
  EXPECT_LE(report["quality"]["samples"].get<long>(), 10'000'000);
  EXPECT_LT(report["quality"]["hausdorff_rel"].get<double>(), 1e-6);  // flat faces, exact
  // The bound is what the search left open, at most a quarter of the spacing.
  EXPECT_NEAR(report["quality"]["hausdorff_upper_bound_mm"].get<double>(),
              report["quality"]["hausdorff_mm"].get<double>() +
                  report["quality"]["hausdorff_gap_mm"].get<double>(),
              1e-9);
  EXPECT_LE(report["quality"]["hausdorff_gap_mm"].get<double>(),
            0.25 * report["quality"]["sample_spacing_mm"].get<double>() + 1e-9);
  // The PDF page is A4 at true size: 210 x 297 mm = 595.28 x 841.89 pt.
  const std::string pdf = test::slurp(scratch / "a" / "cut" / "sheet-001.pdf");
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 595.27"), std::string::npos);
  for (const auto& [name, w, h] : {std::tuple{"letter", 215.9, 279.4}, {"a3", 297.0, 420.0}}) {
    const fs::path out = scratch / name;
    const CliRun r = run_cli("run --target " + target.string() + " --sheet " + name +
                                 " --stop-after layout --out " + out.string(),
                             scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_report(out)["layout"]["sheet_mm"], nlohmann::json::array({w, h})) << name;
    EXPECT_NEAR(read_report(out)["options"]["split_angle_deg"].get<double>(), 60, 1e-9) << name;
  }
  const fs::path asked = scratch / "split-asked";
  const CliRun split =
      run_cli("run --target " + target.string() +
                  " --material paper --split-angle 60 --stop-after strips --out " + asked.string(),
              scratch);
  ASSERT_EQ(split.exit_code, 0) << split.err;
  EXPECT_NEAR(read_report(asked)["options"]["split_angle_deg"].get<double>(), 60, 1e-9);
  const CliRun bad = run_cli(
      "run --target " + target.string() + " --sheet B5 --out " + (scratch / "b").string(), scratch);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("A4, A3, letter"), std::string::npos) << bad.err;
}

// Offcuts on the command line: --sheet 200x150,600x450 fills the 200 x 150 mm offcut first, then
// stock sheets; each sheet's files have its own size (SVG, PDF page), every part read back from
// the SVG lies inside its own sheet's margins, and the report lists the sizes. (The cube's faces
// are one plate each since flat panels are: one fits the offcut, the rest go on a stock sheet;
// the 150 x 110 offcut of before held strips, and holds no 120 mm panel.)
TEST(Cli, OffcutsComeFirstEachFileAtItsSize) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = cube_120mm(scratch);
  const fs::path out = scratch / "a";
  const CliRun r =
      run_cli("run --target " + target.string() + " --sheet 200x150,600x450 --out " + out.string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto layout = read_report(out)["layout"];
  ASSERT_GE(layout["sheets"].get<int>(), 2);
  EXPECT_EQ(layout["sheet_mm"], nlohmann::json::array({600.0, 450.0}));
  EXPECT_EQ(layout["offcuts_mm"], nlohmann::json::parse("[[200.0, 150.0]]"));
  const auto sizes = layout["sheet_sizes_mm"];
  ASSERT_EQ(sizes.size(), layout["sheets"].get<std::size_t>());
  EXPECT_EQ(sizes[0], nlohmann::json::array({200.0, 150.0}));
  for (std::size_t k = 1; k < sizes.size(); ++k)
    EXPECT_EQ(sizes[k], nlohmann::json::array({600.0, 450.0}));
  const std::string svg = test::slurp(out / "cut" / "sheet-001.svg");
  EXPECT_NE(svg.find("width=\"200mm\" height=\"150mm\" viewBox=\"0 0 200 150\""),
            std::string::npos);
  EXPECT_NE(test::slurp(out / "cut" / "sheet-002.svg").find("width=\"600mm\" height=\"450mm\""),
            std::string::npos);
  // 200 x 150 mm = 566.93 x 425.20 pt.
  EXPECT_NE(test::slurp(out / "cut" / "sheet-001.pdf").find("/MediaBox [ 0 0 566.92"),
            std::string::npos);
  int on_offcut = 0;
  for (const auto& part : test::read_sheet_parts(out / "cut")) {
    const double w = part.sheet == 1 ? 200 : 600, h = part.sheet == 1 ? 150 : 450;
    on_offcut += part.sheet == 1;
    expect_inside_margins(part, w, h);
  }
  EXPECT_GT(on_offcut, 0);
  // The contact sheet numbers its sheets in grey (r = g = b) outside them: drawn on the sheet,
  // the 20 mm number covered the parts of small offcuts. Parts are red and blue, the sheets
  // white, the background light grey; no grey ink may touch a sheet's white, and there is some.
  using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
  Surface contact(cairo_image_surface_create_from_png((out / "cut" / "contact-sheet.png").c_str()),
                  cairo_surface_destroy);
  ASSERT_EQ(cairo_surface_status(contact.get()), CAIRO_STATUS_SUCCESS);
  const int cw = cairo_image_surface_get_width(contact.get());
  const int ch = cairo_image_surface_get_height(contact.get());
  const int stride = cairo_image_surface_get_stride(contact.get());
  const unsigned char* data = cairo_image_surface_get_data(contact.get());
  auto rgb = [&](int x, int y) {  // B G R A in memory
    const unsigned char* p = data + y * stride + 4 * x;
    return std::array<int, 3>{p[2], p[1], p[0]};
  };
  long grey_ink = 0, grey_on_white = 0;
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      const auto c = rgb(x, y);
      if (!(c[0] == c[1] && c[1] == c[2] && c[0] < 150)) continue;
      ++grey_ink;
      bool by_white = false;
      for (int v = std::max(0, y - 2); v <= std::min(ch - 1, y + 2); ++v)
        for (int u = std::max(0, x - 2); u <= std::min(cw - 1, x + 2); ++u)
          by_white = by_white || rgb(u, v) == std::array<int, 3>{255, 255, 255};
      grey_on_white += by_white;
    }
  EXPECT_GT(grey_ink, 20 * layout["sheets"].get<long>());
  EXPECT_EQ(grey_on_white, 0);
  const CliRun bad = run_cli("run --target " + target.string() +
                                 " --sheet 150x110,,600x450 --out " + (scratch / "b").string(),
                             scratch);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("kerfab: error: --sheet"), std::string::npos) << bad.err;
}

// A sheet of 10 x 10 m (the largest --sheet takes): the preview stays at most 4000 px on its
// long side and the occupancy grid's cell grows to keep it at 4 million cells (at 2.5 px/mm and
// 1 mm cells Spot's run on it peaked at 2.5 GB, now 121 MB), and the parts are on the sheet.
TEST(Cli, AHugeSheetKeepsPreviewAndGridBounded) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = cube_120mm(scratch);
  const fs::path out = scratch / "a";
  const CliRun r = run_cli(
      "run --target " + target.string() + " --sheet 10000x10000 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // PNG: width and height are the big-endian words at bytes 16 and 20.
  const std::string png = test::slurp(out / "cut" / "sheet-001.png");
  ASSERT_GT(png.size(), 24u);
  auto word = [&](int at) {
    unsigned v = 0;
    for (int k = 0; k < 4; ++k) v = v << 8 | static_cast<unsigned char>(png[at + k]);
    return v;
  };
  EXPECT_EQ(word(16), 4000u);
  EXPECT_EQ(word(20), 4000u);
  const auto parts = test::read_sheet_parts(out / "cut");
  EXPECT_EQ(parts.size(), read_report(out)["layout"]["parts"].size());
  for (const auto& part : parts) expect_inside_margins(part, 10000, 10000);
}

// Paper: every part is on a page and no outline has a slit or tail a cutter cannot follow,
// read back from the SVG by the independent auditor. Tabs of two borders met at their part's
// corners in notches of 0.1-0.5 mm (111 on this sphere at 120 mm, 227 on the shared icosphere),
// and the split of parts larger than the page kept no room for the tabs: a strip that fitted A4
// until its tabs were added was left off the pages (the bunny at 250 mm), and this ring of
// radius 44 mm (one strip per row, 276 mm around; A4 is 190 x 277 mm inside its margins) failed
// the whole run ("no part fits").
TEST(Cli, PaperPartsAreAllPlacedWithOutlinesACutterCanFollow) {
  const fs::path scratch = test::fresh_dir();
  const fs::path sphere = scratch / "sphere.obj", ring = scratch / "ring.obj";
  write_mesh(test::sphere(60, 4).quads, sphere);
  write_mesh(test::open_cylinder(44, 30, 24, 3, 1).quads, ring);
  struct Case {
    const char* name;
    fs::path target;
    const char* size;
  };
  for (const Case& c : {Case{"sphere-120", sphere, " --size 120"},
                        Case{"sphere-175", sphere, " --size 175"}, Case{"ring", ring, ""}}) {
    const fs::path out = scratch / c.name;
    const CliRun r = run_cli("run --quiet --target " + c.target.string() + c.size +
                                 " --material paper --out " + out.string(),
                             scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = read_report(out);
    const std::string name = c.name;  // for the messages below
    EXPECT_TRUE(report["layout"]["unplaced"].empty()) << name << report["layout"]["unplaced"];
    const auto audit = test::audit_sheets(out / "cut");
    EXPECT_GE(audit.parts, 3) << name;
    EXPECT_EQ(audit.thin_features, 0)
        << name << ": " << (audit.findings.empty() ? "" : audit.findings[0]);
    EXPECT_EQ(
        audit.small_parts + audit.narrow_parts + audit.labels_off_part + audit.close_part_pairs, 0)
        << name << ": " << (audit.findings.empty() ? "" : audit.findings[0]);
  }
}

// `kerfab run --quiet ARGS --out OUT` (OUT in a fresh scratch directory unless given): its
// report, or null (and a failure) where the run failed. Either way, no part of a run this
// returns flattens inverted or 20 degrees or more off.
nlohmann::json run_quietly(const std::string& args, fs::path out = {}) {
  if (out.empty()) out = test::fresh_dir() / "out";
  const CliRun r = run_cli("run --quiet " + args + " --out " + out.string(), out.parent_path());
  if (r.exit_code != 0) {
    ADD_FAILURE() << args << ": exit " << r.exit_code << "\n" << r.err;
    return nullptr;
  }
  auto report = read_report(out);
  EXPECT_EQ(report["flatten"]["inverted_quads"].get<int>(), 0) << args;
  EXPECT_LT(report["flatten"]["max_angle_error_deg"].get<double>(), 20.0) << args;
  return report;
}

// A rod 300 x 5 x 5 mm at 250 mm (4.2 mm across) in 3 mm MDF: no box of 3 mm sheets is that
// thin. Since extrusions are swept (2026-12-04) the resolve stage made a facet of two of its
// sides and cut it along its outline alone, and the run "succeeded" with one part, a lens
// 246 x 44 mm (7768 mm^2 for 1556 mm^2 of surface, no corner more than 0.46 deg off: the errors
// added up along its sides). A plate more than twice its surface is not taken; the run then
// ends with the error that names the cure: no sheets, a report that says it failed. In paper
// (no mitres) the rod is 4 flat parts.
TEST(Cli, ARodThinnerThanTwoSheetsIsRefusedNotCutAsALens) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "rod.obj";
  test::write_text(target, box_obj({0, 0, 0}, {300, 5, 5}));
  const fs::path out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + target.string() + " --size 250 --out " + out.string(), scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("kerfab: error: every part has nothing left once its slots and mitres are "
                       "cut (the shape is thinner than the sheets"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("use a larger --size or a thinner --material"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "cut"));
  const auto failed = read_report(out);
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_EQ(failed["error"]["exit_code"].get<int>(), 1);
  const auto report =
      run_quietly("--target " + target.string() + " --size 250 --material paper", scratch / "p");
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["resolve"]["parts_after"].get<int>(), 4);
  // Every part no larger than the surface it stands for.
  for (const auto& f : report["flatten"]["patches"])
    EXPECT_LT(f["area_2d_mm2"].get<double>(), 1.01 * f["area_3d_mm2"].get<double>()) << f;
}

// Every part placed, none fallen apart at its slots, and the sheets in \p out, read back by
// the independent auditor, hold them all and are clean. \p name: for the messages.
void expect_all_placed_and_clean(const nlohmann::json& report, const fs::path& out,
                                 const std::string& name = "") {
  EXPECT_EQ(report["joints"]["repaired_parts"].get<int>(), 0) << name;
  EXPECT_TRUE(report["layout"]["unplaced"].empty()) << name;
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.parts, static_cast<int>(report["layout"]["parts"].size()))
      << name;  // after splits to fit
  EXPECT_TRUE(audit.clean()) << name << ": " << (audit.findings.empty() ? "" : audit.findings[0]);
}

/// \p mesh written to \p scratch / \p name.obj (or the file \p given, at its own size) and run
/// from its triangles at 250 mm in 3 mm MDF: its quads swept (their method starting with \p
/// method), Hausdorff under \p most_hausdorff of the diagonal, no critical region left, every
/// border with a joint, every part placed and its sheets, read back by the auditor, clean. The
/// report (null where the run failed).
nlohmann::json run_swept(const fs::path& scratch, const std::string& name, const TriangleMesh& mesh,
                         const std::string& method, double most_hausdorff,
                         const fs::path& given = {}) {
  const fs::path target = given.empty() ? scratch / (name + ".obj") : given, out = scratch / name;
  if (given.empty()) write_mesh(test::poly_mesh(mesh), target);
  const auto report =
      run_quietly("--target " + target.string() + (given.empty() ? " --size 250" : ""), out);
  if (report.is_null()) return report;
  EXPECT_EQ(report["quads"]["method"].get<std::string>().rfind(method, 0), 0u)
      << report["quads"]["method"];
  EXPECT_LT(report["quality"]["hausdorff_rel"].get<double>(), most_hausdorff);
  EXPECT_EQ(report["resolve"]["critical_after"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  expect_all_placed_and_clean(report, out, name);
  return report;
}

// What kerfing is most often for: a drum, a bench of C-shaped section, a pot open at the top,
// from their triangles alone. Each is a flat outline swept along an axis; its wall is swept
// in rows from its cap's border (src/kerfab/quads/sweep.h), so the strips are rings round the
// wall, bending about the axis, and each cap is one plate. Measured at 250 mm in 3 mm MDF
// before (the lattice over the whole surface): the drum 47 parts, Hausdorff 1.6 % of the
// diagonal; the bench 126 parts, 2.6 %; the pot 50 parts, 0.76 %. Now 15, 13 and 17 parts,
// 0.6 %, 0.3 % and 0.4 %, their sheets read back clean. A column (radius 30 mm, 250 high) is
// 22 rings and its two caps: every column of its swept wall lies in one plane, and until
// 2026-12-05 two of them were cut as plates 250 mm long, each ring cut in two (54 parts);
// plates are now only where the model is flat too, and none lies on a round wall. (Its
// Hausdorff, 1.05 %, is at the rim: a cap of 2800 mm^2 in quads of 11.5 mm is a 10-gon, its
// chords 2.8 mm inside the circle the rings follow.)
TEST(Cli, ADrumABenchAndAPotAreCutAsCapsAndRingsOfStrips) {
  const fs::path scratch = test::fresh_dir();
  struct Case {
    std::string name;
    TriangleMesh mesh;
    int most_parts;
    double most_hausdorff;
    double top;  // a round wall's upper rim at 250 mm [mm]; 0: the wall is not all round
  };
  for (const Case& c : {Case{"drum", test::drum(100, 120, 128), 16, 0.008, 150},
                        Case{"bench", test::c_bench(60, 100, 40, 160), 15, 0.004, 0},
                        Case{"pot", test::drum(80, 120, 96, true, false), 18, 0.005, 187.5},
                        Case{"column", test::drum(30, 250, 64), 24, 0.011, 250}}) {
    SCOPED_TRACE(c.name);
    const auto report = run_swept(scratch, c.name, c.mesh, "extrusion", c.most_hausdorff);
    ASSERT_FALSE(report.is_null());
    EXPECT_LE(report["resolve"]["parts_after"].get<int>(), c.most_parts);
    for (const auto& change : report["resolve"]["changes"]) {
      if (c.top == 0 || change["action"] != "plate") continue;
      const double z = change["centre_mm"][2].get<double>();  // a cap's, or one on the wall
      EXPECT_TRUE(std::abs(z) < 0.01 || std::abs(z - c.top) < 0.01) << change;
    }
  }
}

// A planter (a frustum closed at both ends), a vase (open at the top, its profile a sine's arc
// in 20 facets), a lampshade (open at both ends) and a stepped drum (a thinner drum on a wider
// one) from their triangles at 250 mm in 3 mm MDF: each a loft, swept, so cut as its caps, its
// step and rings round its wall. From the lattice they were 103 parts (Hausdorff 1.95 % of the
// diagonal, the planter's bottom cut in strips), 62 on the sheets (1.40 %), 32 on the sheet
// (0.53 %) and 80 (2.43 %); swept, 13 (0.30 %), 19 (0.42 %), 22 on the sheet (0.09 %: 17 rings
// and arcs, long ones split to fit one sheet) and 13 (0.42 %). Their sheets, read back by the
// auditor, are clean.
TEST(Cli, APlanterAVaseALampshadeAndAStepAreCutAsCapsAndRings) {
  const fs::path scratch = test::fresh_dir();
  const std::vector<std::array<double, 2>> vase = test::vase_profile();
  struct Case {
    std::string name;
    TriangleMesh mesh;
    int most_parts;
    double most_hausdorff;
  };
  for (const Case& c :
       {Case{"planter", test::lathe({{100, 0}, {60, 120}}, 96, true, true), 15, 0.007},
        Case{"vase", test::lathe(vase, 64, true, false), 21, 0.005},
        Case{"lampshade", test::lathe({{100, 0}, {60, 150}}, 96, false, false), 24, 0.002},
        Case{"stepped", test::lathe({{100, 0}, {100, 60}, {60, 60}, {60, 120}}, 96, true, true), 15,
             0.006}}) {
    SCOPED_TRACE(c.name);
    const auto report = run_swept(scratch, c.name, c.mesh, "loft", c.most_hausdorff);
    ASSERT_FALSE(report.is_null());
    EXPECT_LE(static_cast<int>(report["layout"]["parts"].size()), c.most_parts);  // on the sheets
  }
  // The bundled planter (README, "Round models") at its own size: 12 parts on one sheet.
  const auto report = run_swept(scratch, "bundled", {}, "loft", 0.004,
                                fs::path(KERFAB_EXAMPLE_DIR) / "planter" / "planter.obj");
  ASSERT_FALSE(report.is_null());
  EXPECT_LE(static_cast<int>(report["layout"]["parts"].size()), 12);
  EXPECT_EQ(report["layout"]["sheets"].get<int>(), 1);
}

// The bunny in paper at 200 mm, from its triangle mesh: no part flattens distorted. A strip
// of one quad (which the flattening cannot split further) whose rail collapses folded its
// sub-quads up to 160 deg against each other and flattened 216 deg off with an inverted
// sub-quad; the resolve stage now takes such a part as one a maker cannot handle and makes a
// flat plate of it and its neighbours. Its pages, read back by the auditor, have no slit or
// tail a cutter cannot follow.
TEST(Cli, NoPaperPartOfTheBunnyFlattensDistorted) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path out = test::fresh_dir() / "out";
  const auto report =
      run_quietly("--target " + (test::shared_meshes() / "bunny_closed_odedstein.obj").string() +
                      " --size 200 --material paper",
                  out);
  ASSERT_FALSE(report.is_null());
  for (const auto& p : report["flatten"]["patches"])
    EXPECT_TRUE(p["outline_simple"].get<bool>()) << p["patch"];
  EXPECT_EQ(report["resolve"]["small_parts_after"].get<int>(), 0);
  EXPECT_TRUE(report["layout"]["unplaced"].empty());
  // Its pages, read back by the auditor: no slit or tail a cutter cannot follow (3 until the
  // slits were measured as cut and the tabs' hooked tips went, 2026-11-29).
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
}

// Where two glue tabs meet at a corner of their part, the closing that fills the V between
// them gave back the V's tip as a piece of its own, touching the outline only along its sides,
// which the outline then dropped: Spot's bundled triangles in paper at 250 mm kept a slit under
// 1 mm (part 4), bob_tri at 200 mm one, fertility at 200 mm three. And a V wider than about 29
// degrees came back from the mitred closing as it was: rocker-arm and fandisk at 200 mm kept a
// slit each. Their pages, read back by the auditor: no slit or tail a cutter cannot follow
// (rocker-arm and fandisk kept a sharp corner of a strip's own body until 2026-12-05: spikes
// under 1 mm wide).
TEST(Cli, PaperTabsMeetingAtACornerLeaveNoSlit) {
  std::vector<std::pair<fs::path, std::string>> cases = {
      {test::real_mesh("spot_triangulated.obj"), "250"}};
  if (test::have_shared_meshes())
    for (const char* name : {"bob_tri.obj", "rocker-arm.obj", "fandisk.obj"})
      cases.push_back({test::shared_meshes() / name, "200"});
  for (const auto& [target, size] : cases) {
    const fs::path out = test::fresh_dir() / "out";
    const CliRun r = run_cli("run --quiet --target " + target.string() + " --size " + size +
                                 " --material paper --out " + out.string(),
                             out.parent_path());
    ASSERT_EQ(r.exit_code, 0) << target << r.err;
    EXPECT_EQ(read_report(out)["joints"]["borders_without_joint"].get<int>(), 0) << target;
    const auto audit = test::audit_sheets(out / "cut");
    EXPECT_GE(audit.parts, 40) << target;
    EXPECT_EQ(audit.thin_features, 0)
        << target << ": " << (audit.findings.empty() ? "" : audit.findings[0]);
  }
}

// scripts/shapes.py's cone at 350 mm in 3 mm plywood: a slit its first widening left 0.996 mm
// wide over 2 mm between two wider stretches (part 13), which the run neither widened nor named
// (the widening looked at the corners of what the closing fills, all at its ends). Read back by
// the auditor: no slit or tail under 1 mm (1 before 2026-12-06), and no part named as keeping
// one either.
TEST(Cli, ASlitNarrowOnlyBetweenWiderStretchesIsWidenedOnTheSheet) {
  const fs::path scratch = test::fresh_dir(), cone = scratch / "cone.obj", out = scratch / "out";
  test::write_obj(test::scripts_cone(), cone);
  const CliRun r = run_cli("run --quiet --target " + cone.string() +
                               " --size 350 --material plywood3 --out " + out.string(),
                           scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_TRUE(report["joints"]["slit_parts"].empty());
  EXPECT_TRUE(report["joints"]["thin_neck_parts"].empty());
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_GE(audit.parts, 40);
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
}

// scripts/shapes.py's terrain at 300 mm in 3 mm MDF: a facet that flattens 45 deg off (its
// corners shared with facets at other angles), cut back by its neighbours' mitres to 21.8 mm^2,
// was kept as it was, because a facet bent so is the outline cut's business; beside it a part
// of 1.4 mm^2 and one folded back 161 deg onto it stayed, all three named unresolved, and the
// auditor found two parts too small and two too narrow (2026-12-06). The facet is folded back
// onto its neighbour (the shape is thinner there than the sheets) and the parts kept stand
// within a sheet of it: left out, and its neighbours then hold. Read back by the auditor: no
// part too small or too narrow on the sheet, and none left unresolved.
TEST(Cli, AFacetFlatteningBentThatItsJointsCutToACrumbIsLeftOut) {
  const fs::path scratch = test::fresh_dir(), terrain = scratch / "terrain.obj";
  const fs::path out = scratch / "out";
  test::write_obj(test::scripts_terrain(), terrain);
  const CliRun r = run_cli(
      "run --quiet --target " + terrain.string() + " --size 300 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_TRUE(report["resolve"]["unresolved_parts"].empty())
      << report["resolve"]["unresolved_parts"];
  int omitted = 0;
  for (const auto& c : report["resolve"]["changes"])
    if (c["action"] == "omit") {
      ++omitted;
      EXPECT_LE(c["local_distance_mm"].get<double>(), 3.0) << c["reason"];
    }
  EXPECT_GE(omitted, 1);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_GE(audit.parts, 100);
  EXPECT_EQ(audit.small_parts + audit.narrow_parts, 0)
      << (audit.findings.empty() ? "" : audit.findings[0]);
}

// The same terrain at 350 mm: a strip's wedge tip ended in a tooth whose root lay 1.1 mm from
// the neck that held it, 0.23 mm wide where the slot beside it came down to the strip's other
// edge. The thin-neck pass made plain the joints within a millimetre of the neck only, so the
// tooth stayed, the neck with it, and the mend was refused: the part was named (with a second
// one, whose plain joints make it fall apart) and the auditor found the laser path passing
// within 0.5 mm of itself there (2026-12-07). Now, where those tries fail, the joints a tooth's
// width round the neck are made plain and the part judged as it will be cut, without the small
// corners that hang on a neck and hold no tooth. Read back by the auditor: no tail or slit.
TEST(Cli, AToothOnAStripsWedgeTipBesideItsNeckGoesPlain) {
  const fs::path scratch = test::fresh_dir(), terrain = scratch / "terrain.obj";
  const fs::path out = scratch / "out";
  test::write_obj(test::scripts_terrain(), terrain);
  const CliRun r = run_cli(
      "run --quiet --target " + terrain.string() + " --size 350 --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_LE(report["joints"]["thin_neck_parts"].size(), 1u) << report["joints"]["thin_neck_parts"];
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_GE(audit.parts, 50);
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
}

// Two shapes of scripts/shapes.py in paper, as a maker makes them from its files. The vase at
// 180 mm: where a tab's tail was cut off, a slot 1.13 mm wide at its flat end (two concave
// corners of about 90 degrees, its walls nearly parallel) was left 0.98 mm as cut; the mitred
// closing gave it back whole and no corner of it was under 90 degrees. The saddle at 200 mm: a
// strip's end at one of its corners, a spike of the part's body 21 degrees sharp, under 1 mm
// wide for its last 2.6 mm. Their pages, read back by the auditor: no slit or tail a cutter
// cannot follow (1 each before 2026-12-05), every border glued, every part placed.
TEST(Cli, PaperSlotEndsAndSharpTipsAreCutAsACutterSeesThem) {
  const fs::path scratch = test::fresh_dir();
  const fs::path vase = scratch / "vase.obj", saddle = scratch / "saddle.obj";
  test::write_obj(test::scripts_vase(), vase);
  test::write_obj(
      test::height_grid(50, 80, [](double x, double y) { return (x * x - y * y) / 200; }), saddle);
  for (const auto& [target, size] : {std::pair{vase, "180"}, std::pair{saddle, "200"}}) {
    const fs::path out = scratch / target.stem();
    const CliRun r = run_cli("run --quiet --target " + target.string() + " --size " + size +
                                 " --material paper --out " + out.string(),
                             scratch);
    ASSERT_EQ(r.exit_code, 0) << target << r.err;
    const auto report = read_report(out);
    EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0) << target;
    EXPECT_TRUE(report["layout"]["unplaced"].empty()) << target;
    const auto audit = test::audit_sheets(out / "cut");
    EXPECT_GE(audit.parts, 20) << target;
    EXPECT_EQ(audit.thin_features, 0)
        << target << ": " << (audit.findings.empty() ? "" : audit.findings[0]);
  }
}

// stanford-bunny (a scan) in paper at 200 mm: the resolve stage's surface of the parts kept,
// asked how far a part it would leave out lies from them, held a strip's triangle of no area
// and the run failed ("target triangle 2570 has zero area"). It runs to its sheets, and the
// parts it cannot make whole are named. Since its quads are the lattice whose corners lie
// closer to the target (Quads.TheLatticeWhoseCornersLieCloserToTheTargetIsTaken), every border
// is glued (3 bare and 7 parts named distorted before, 119 parts against 86 now), and since its
// twisted quads are creased (Joints.PaperCreasesATwistedQuadAlongItsDiagonal) at most two
// patches flatten more than 5 deg off (30 before, none now).
TEST(Cli, TheScanInPaperRunsToItsSheets) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path out = test::fresh_dir() / "out";
  const CliRun r =
      run_cli("run --quiet --target " + (test::shared_meshes() / "stanford-bunny.obj").string() +
                  " --size 200 --material paper --out " + out.string(),
              out.parent_path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_TRUE(report["layout"]["unplaced"].empty());
  // Every part that flattens distorted (a scan's strips twist more than paper bends flat
  // there) is one the run names.
  std::set<int> named;
  for (const auto& p : report["resolve"]["unresolved_parts"]) named.insert(p.get<int>());
  for (const auto& p : report["flatten"]["patches"])
    if (p["inverted_quads"].get<int>() > 0 || p["max_angle_error_deg"].get<double>() >= 20 ||
        !p["outline_simple"].get<bool>()) {
      EXPECT_TRUE(named.count(p["patch"].get<int>())) << p["patch"];
    }
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  int off = 0;
  for (const auto& p : report["flatten"]["patches"])
    off += p["max_angle_error_deg"].get<double>() > 5 ? 1 : 0;
  EXPECT_LE(off, 2);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_GE(audit.parts, 50);
  EXPECT_EQ(audit.parts, static_cast<int>(report["resolve"]["parts_after"].get<int>()));
}

// stanford-bunny from its triangles at 250 mm, 3 mm MDF: a 6.4 mm border folded 100 deg had no
// joint (every tooth on it reached 0.2-0.6 mm into a third part), and was not held at its
// corners either: its two parts are each jointed to the parts at both its ends, but two of
// those joints lay 7.7 and 10.9 mm from the corner, farther than two tooth widths. Those
// borders now take a tooth within reach of the corner where one fits (checked in 3D like a
// stub tooth), and the border is held at both its corners: none without a joint, the sheets
// clean.
TEST(Cli, TheScansShortBordersAreHeldAtTheirCorners) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path out = test::fresh_dir() / "out";
  const CliRun r =
      run_cli("run --quiet --target " + (test::shared_meshes() / "stanford-bunny.obj").string() +
                  " --size 250 --out " + out.string(),
              out.parent_path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  int held_at_both = 0;
  for (const auto& b : report["joints"]["borders"])
    if (b["joint"] == "corner" && b.contains("joined_through_far")) {
      ++held_at_both;
      EXPECT_GT(b["length_mm"].get<double>(), 6.0);
      EXPECT_LE(b["length_mm"].get<double>(), 12.0);
    }
  EXPECT_GE(held_at_both, 1);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_TRUE(audit.findings.empty()) << audit.findings.front();
}

// horse_quad at 250 mm: where many facets meet on the ears, facets capped quads tilted up to
// 85 deg from their planes and flattened 130 to 280 deg off with inverted quads (five parts
// reported unresolved, one of 22.9 mm^2 on the sheet). Cut along their outlines, they keep
// their edges' lengths and their corners' angles on the surface: every part within the
// flattening's 20 deg, none inverted, and the sheets, read back by the auditor, clean. Every
// border has a joint or is held at its corners: a 0.7 mm stub, whose two parts share a
// box-jointed border 2 mm from its end across a part left out, was counted without a joint
// while the rule asked for borders ending at the stub's corner itself.
TEST(Cli, TheHorsesEarsFlattenWithinTheLimitAndCutClean) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path out = test::fresh_dir() / "out";
  const auto report = run_quietly(
      "--target " + (test::shared_meshes() / "horse_quad.obj").string() + " --size 250", out);
  ASSERT_FALSE(report.is_null());
  for (const auto& p : report["flatten"]["patches"]) {
    EXPECT_LT(p["max_angle_error_deg"].get<double>(), 20.0) << p["patch"];
    EXPECT_EQ(p["inverted_quads"].get<int>(), 0) << p["patch"];
    EXPECT_TRUE(p["outline_simple"].get<bool>()) << p["patch"];
  }
  int outlines = 0;
  for (const auto& c : report["resolve"]["changes"]) outlines += c["action"] == "outline";
  EXPECT_GE(outlines, 1);
  EXPECT_EQ(report["resolve"]["small_parts_after"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  expect_all_placed_and_clean(report, out);
}

// The README's first example, Spot's bundled triangle mesh alone at 250 mm: the sheets, read
// back by the independent auditor, are clean, with a joint on every border and no part left
// too small or too narrow. A stub tooth's slot (one from each side of a 77 mm^2 strip end)
// once narrowed a part to under 3 mm, reported unresolved: a stub tooth that leaves a part
// too narrow that was not is now refused (the tooth the other way round is tried), and a part
// nowhere 3 mm wide takes its borders' teeth as a part too small does.
TEST(Cli, TheFirstExampleFromATriangleMeshCutsClean) {
  const fs::path out = test::fresh_dir() / "out";
  const auto report = run_quietly(
      "--target " + test::real_mesh("spot_triangulated.obj").string() + " --size 250", out);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["resolve"]["critical_after"].get<int>(), 0);
  EXPECT_EQ(report["resolve"]["small_parts_after"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  expect_all_placed_and_clean(report, out);
}

// fertility's triangle mesh in 3 mm plywood at 350 mm, a run no test had made: a 3 x 4.8 mm
// tab of part 108 hung on a neck 0.08 mm wide beside its part's slot, and the run said nothing
// (the joints' neck check opened the outline with mitred corners, which reach four times the
// offset and joined the tab to its part again). Now the morphological opening finds it and the
// thin-neck pass makes the joints there plain: the sheets, read back by the auditor, are clean
// (no laser path within half the smallest feature of itself), no part is left with a neck, and
// every border keeps a joint. The quads are those the size rule chose before its tube bound
// (21.48 mm; since 2026-12-05 it makes them 15.5 mm, 4 round fertility's thinnest arms, and the
// tab is not there to test).
TEST(Cli, NoTabHangsOnANeckTheMitredOpeningMissed) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path out = test::fresh_dir() / "out";
  const auto report =
      run_quietly("--target " + (test::shared_meshes() / "fertility.off").string() +
                      " --size 350 --material plywood3 --quad-size 21.47582039443288",
                  out);
  ASSERT_FALSE(report.is_null());
  EXPECT_TRUE(report["joints"]["thin_neck_parts"].empty());
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  expect_all_placed_and_clean(report, out);
}

// Even-odd point in polygon (the sheet reader's outlines).
bool inside_outline(const Vec2& p, const Polygon2& poly) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
        p.x() < poly[j].x() + (p.y() - poly[j].y()) / (poly[i].y() - poly[j].y()) *
                                  (poly[i].x() - poly[j].x()))
      in = !in;
  return in;
}

// Issue 16, papercraft: a paper cube's sheets, read back from the SVG: no kerf cuts; fold lines
// as <path class="fold" data-fold="mountain|valley">, mountain and valley in different colours
// and dashes; every fold line has paper on both sides (a tab root: the part on one side, its tab
// on the other), and on a cube every fold that bends is a mountain fold; the DXF has them on
// their own layers; the report counts them. The cube is cut in strips that fold round its
// edges (--no-resolve: the resolve stage would cut its flat faces as one plate each, as
// Cli.ABoxFromItsTrianglesIsCutAsOnePanelPerFace checks in paper too), so that rulings are
// scored as well.
TEST(Cli, PaperModelsGetGlueTabsAndFoldLines) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "cube.obj";
  write_mesh(test::cube_grid_mesh(4, [](const Vec3& p) { return Vec3(40 * p); }), target);
  const CliRun r = run_cli("run --target " + target.string() + " --material paper --no-resolve " +
                               "--out " + (scratch / "a").string(),
                           scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(scratch / "a");
  const auto& j = report["joints"];
  EXPECT_EQ(j["borders_without_joint"], 0);
  EXPECT_EQ(j["teeth"], 0);
  EXPECT_EQ(report["kerf"]["cuts"], 0);
  EXPECT_GE(j["glue_tabs"].get<int>(), j["border_pieces"].get<int>());
  EXPECT_EQ(report["options"]["glue_tab_mm"], 6.0);
  const auto parts = test::read_sheet_parts(scratch / "a" / "cut");
  ASSERT_FALSE(parts.empty());
  int folds = 0;
  std::set<std::string> strokes;
  for (const auto& part : parts) {
    EXPECT_TRUE(part.kerf.empty()) << part.id;
    EXPECT_FALSE(part.folds.empty()) << part.id << " has no glue tab";
    for (const auto& f : part.folds) {
      ++folds;
      ASSERT_GE(f.points.size(), 2u);
      EXPECT_TRUE(f.kind == "mountain" || f.kind == "valley") << f.kind;
      strokes.insert(f.kind + " " + f.stroke + " " + f.dashes);
      // Paper on both sides of its middle, 1 mm off.
      const Vec2 a = f.points.front(), b = f.points.back(), m = 0.5 * (a + b);
      const Vec2 n = Vec2(-(b - a).y(), (b - a).x()).normalized();
      EXPECT_TRUE(inside_outline(m + n, part.outline) && inside_outline(m - n, part.outline))
          << part.id << ": a fold line on the outline's edge, not between part and tab";
    }
  }
  // Every tab root, and the rulings where a strip folds round a cube's edge (paper creases
  // there: its strips are split only at folds over 100 degrees, and folds over 60 are scored).
  EXPECT_GT(j["fold_lines"]["rulings"].get<int>(), 0);
  EXPECT_EQ(folds, j["fold_lines"]["tab_roots"].get<int>() + j["fold_lines"]["rulings"].get<int>());
  // A cube's folds: 0 degrees between strips of a face (either sign), 90 at its edges, all
  // mountains: at least the 12 edges' worth of tabs and creases.
  EXPECT_GE(j["fold_lines"]["mountain"].get<int>(), 12);
  // Mountain and valley drawn differently (when both occur), and never in the cut colour.
  std::set<std::string> kinds;
  for (const auto& s : strokes) kinds.insert(s.substr(0, s.find(' ')));
  EXPECT_EQ(strokes.size(), kinds.size()) << "one style per kind of fold";
  for (const auto& s : strokes) EXPECT_EQ(s.find("#ff0000"), std::string::npos) << s;
  const std::string dxf = test::slurp(scratch / "a" / "cut" / "sheet-001.dxf");
  EXPECT_NE(dxf.find("FOLD_MOUNTAIN"), std::string::npos);
  // --glue-tab 0: the paper's emulation, plain borders, no folds.
  const CliRun plain = run_cli("run --target " + target.string() +
                                   " --material paper --glue-tab 0 --stop-after layout --out " +
                                   (scratch / "b").string(),
                               scratch);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(read_report(scratch / "b")["joints"]["glue_tabs"], 0);
}

// Issue 16: a part whose slots cut it apart loses its joints only where it comes apart. On the
// shared quad sphere at 250 mm (after resolve) two 171 mm borders of a narrow strip near a pole
// used to end with no joint at all (12 of 429 borders without one); then one 2.5 mm stub between
// two corners was left; now every border has a joint.
TEST(Cli, AQuadSphereKeepsAJointOnEveryLongBorder) {
  if (!test::have_shared_meshes()) GTEST_SKIP() << "no shared meshes beside the repository";
  const fs::path scratch = test::fresh_dir();
  const CliRun r =
      run_cli("run --quiet --target " + (test::shared_meshes() / "quad-sphere.off").string() +
                  " --subdivide 1 --size 250 --stop-after layout --out " + (scratch / "a").string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = read_report(scratch / "a")["joints"];
  int without = 0;
  for (const auto& b : j["borders"])
    if (b["joint"] == "none") {
      ++without;
      EXPECT_LT(b["length_mm"].get<double>(), 20.0) << b.dump();
    }
  EXPECT_EQ(without, j["borders_without_joint"].get<int>());
  EXPECT_EQ(without, 0);
}

// The bundled example end to end: report and the bending dump follow docs/outputs.md.
TEST(Cli, DemoWritesReportDumpsAndStripMesh) {
  const fs::path scratch = test::fresh_dir();
  const fs::path out = scratch / "demo";
  const CliRun r = run_cli("demo --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  // The resolve stage's rounds are reported while it runs, the first with what the first
  // build left: one line per round, numbered from 1.
  const auto resolve_at = r.err.find("[resolve] ...");
  ASSERT_NE(resolve_at, std::string::npos) << r.err;
  EXPECT_EQ(
      r.err.find("  round 1: " + std::to_string(report["resolve"]["critical_before"].get<int>()) +
                 " critical regions, "),
      r.err.find('\n', resolve_at) + 1)
      << r.err;
  int round_lines = 0;  // each round rebuilds at least once, the last one only looks
  for (auto at = r.err.find("\n  round "); at != std::string::npos;
       at = r.err.find("\n  round ", at + 1))
    ++round_lines;
  EXPECT_GE(round_lines, 2);
  EXPECT_LE(round_lines, report["resolve"]["rounds"].get<int>() + 1);
  EXPECT_EQ(report["version"], 1);
  EXPECT_EQ(report["units"], "mm");
  EXPECT_NEAR(report["input"]["bbox_mm"][2].get<double>(), 250.0, 1e-6);
  EXPECT_EQ(report["input"]["quads"], 732);
  // Every part's flattening converged: a facet's Gauss-Newton once crawled at steps of 5e-7
  // through all its 1000 iterations (energy 1.7e-5, 2.4e-6 once damped) and the run warned.
  for (const auto& patch : report["flatten"]["patches"])
    EXPECT_EQ(patch["status"], "converged") << patch["patch"];
  EXPECT_EQ(r.err.find("did not converge"), std::string::npos) << r.err;
  const auto& b = report["bending"];
  for (const char* key :
       {"edges", "bendable", "objective", "bound", "status", "w0_rel", "aligned_fraction"})
    EXPECT_TRUE(b.contains(key)) << key;
  EXPECT_EQ(b["edges"], 1464);
  EXPECT_EQ(b["status"], "optimal");
  EXPECT_GE(b["bound"].get<double>(), b["objective"].get<double>() - 1e-9);
  EXPECT_GT(b["aligned_fraction"].get<double>(), 0.8);
  // Every stage ran, timed under the name --stop-after accepts, and no other.
  EXPECT_EQ(report["timings_s"].size(), kerfab::stage_names().size() + 1);  // + "total"
  for (const auto& stage : kerfab::stage_names())
    EXPECT_TRUE(report["timings_s"].contains(stage)) << stage;
  const auto dump = nlohmann::json::parse(std::ifstream(out / "stages" / "bending.json"));
  EXPECT_EQ(dump["vertices"].size(), 734u);
  EXPECT_EQ(dump["quads"].size(), 732u);
  ASSERT_EQ(dump["edges"].size(), 1464u);
  int bendable = 0;
  for (const auto& e : dump["edges"]) {
    EXPECT_EQ(e["v"].size(), 2u);
    bendable += e["bendable"].get<bool>() ? 1 : 0;
  }
  EXPECT_EQ(bendable, b["bendable"].get<int>());
  EXPECT_DOUBLE_EQ(dump["objective"].get<double>(), b["objective"].get<double>());

  // Strips: report keys, model/strips.ply (per-face strip and colour), one OBJ per patch.
  const auto& st = report["strips"];
  for (const char* key : {"strips", "patches", "sub_quads", "vertices", "t_junction_vertices"})
    EXPECT_TRUE(st.contains(key)) << key;
  const int strips = st["patches"].get<int>();  // patch ids label the faces and files
  EXPECT_GT(strips, 10);
  EXPECT_LE(st["strips"].get<int>(), strips);
  // Strips are long chains of quads; flat facets (where 3 mm MDF cannot bend that tightly at
  // 250 mm: horns, ears, hooves, tail) cover about half of the quads (365 of 732; 340 before
  // every border got a joint: slots on both long borders of a narrow strip leave its kerf cuts
  // less room).
  int ladders = 0, facet_quads = 0;
  for (const auto& p : st["patch_list"]) {
    if (p["facet"].get<bool>())
      facet_quads += p["quads"].get<int>();
    else
      ++ladders;
  }
  EXPECT_LT(ladders, 732 / 4);
  EXPECT_LT(facet_quads, 732 * 11 / 20);
  // Joints (issue 16): every border has a tooth or tab, so nothing is glued on without something
  // that locates it.
  {
    const auto& joints = report["joints"];
    std::map<int, int> jointed;  // part -> teeth and tabs on its borders
    int without = 0;
    for (const auto& border : joints["borders"]) {
      const int n = border["teeth"].get<int>() + border["tabs"].get<int>();
      for (const auto& p : border["patches"]) jointed[p.get<int>()] += n;
      without += n == 0 ? 1 : 0;
      EXPECT_GT(n, 0) << border.dump();
    }
    EXPECT_EQ(without, joints["borders_without_joint"].get<int>());
    for (const auto& [part, n] : jointed) EXPECT_GT(n, 0) << "part " << part << " has no joint";
    // (41 of 562 without before short borders got a tooth in the room between their corners'
    // bands, 10 before teeth where the bands leave none were checked in 3D instead)
    EXPECT_EQ(without, 0);
    EXPECT_GT(joints["toothed_length_mm"].get<double>(),
              0.7 * joints["border_length_mm"].get<double>());
    // No part hangs on a neck under the smallest feature (until 2026-12-03 part 150: its joints
    // made plain there by the thin-neck pass, a stub tooth given back to a border so left bare
    // made the neck again, just under 1 mm, and the pass put everything back).
    EXPECT_TRUE(joints["thin_neck_parts"].empty()) << joints["thin_neck_parts"].dump();
  }
  // The assembly order: every part once, and every step after the first joins a part placed
  // before it, by the neighbour lists of the layout section (the borders, not the plan).
  const auto& order = report["assembly"]["order"];
  const auto& table = report["layout"]["assembly"];
  ASSERT_EQ(order.size(), table.size());
  EXPECT_EQ(report["assembly"]["pieces"], 1);
  std::set<int> placed;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int p = order[k].get<int>();
    bool joined = false;
    for (const auto& nb : table[p]["neighbours"])
      joined = joined || (nb["part"].get<int>() != p && placed.count(nb["part"].get<int>()) &&
                          nb["length_mm"].get<double>() > 0);
    if (k > 0) {
      EXPECT_TRUE(joined) << "step " << k + 1 << ", part " << p;
    }
    EXPECT_TRUE(placed.insert(p).second) << "part " << p << " twice";
  }
  EXPECT_TRUE(fs::is_regular_file(out / "assembly" / "index.html"));
  for (const char* f :
       {"bending.png", "strips.png", "kerf_density.png", "patches.png", "parts.png"})
    EXPECT_TRUE(fs::is_regular_file(out / "pictures" / f)) << f;
  const auto& q = report["quality"];
  EXPECT_GT(q["hausdorff_rel"].get<double>(), 0.0);
  EXPECT_LT(q["hausdorff_rel"].get<double>(), 0.02);
  EXPECT_LT(q["mean_distance_rel"].get<double>(), q["hausdorff_rel"].get<double>());
  std::ifstream ply(out / "model" / "strips.ply");
  ASSERT_TRUE(ply);
  std::string line;
  long nv = -1, nf = -1;
  bool strip_property = false;
  while (std::getline(ply, line) && line != "end_header") {
    if (line.rfind("element vertex ", 0) == 0) nv = std::stol(line.substr(15));
    if (line.rfind("element face ", 0) == 0) nf = std::stol(line.substr(13));
    if (line == "property int strip") strip_property = true;
  }
  EXPECT_TRUE(strip_property);
  EXPECT_EQ(nv, st["vertices"].get<long>());
  ASSERT_EQ(nf, st["sub_quads"].get<long>());
  TriangleMesh strip_mesh;
  for (long i = 0; i < nv; ++i) {
    Vec3 p;
    ply >> p.x() >> p.y() >> p.z();
    strip_mesh.vertices.push_back(p);
  }
  std::vector<int> faces_per_strip(strips, 0);
  for (long i = 0; i < nf; ++i) {
    int n = 0, v[4], strip = -1, rgb[3];
    ply >> n >> v[0] >> v[1] >> v[2] >> v[3] >> strip >> rgb[0] >> rgb[1] >> rgb[2];
    ASSERT_EQ(n, 4);
    ASSERT_GE(strip, 0);
    ASSERT_LT(strip, strips);
    ++faces_per_strip[strip];
    for (int k = 0; k < 4; ++k) ASSERT_LT(v[k], nv);
    strip_mesh.triangles.push_back({v[0], v[1], v[2]});
    strip_mesh.triangles.push_back({v[0], v[2], v[3]});
  }
  // Where the distances are largest, read back from the written meshes: the point the report
  // names on each surface lies on it, at the distance it states from the other (to 0.1 um: the
  // strip mesh is written to ten significant digits).
  {
    constexpr double kWritten = 1e-4;
    const TargetSurface strips_surface(without_degenerate(strip_mesh));
    const TargetSurface target(triangulate(read_mesh(out / "model" / "target.obj")));
    const auto at = [&](const char* key) {
      const auto& p = q[key];
      return Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    };
    const Vec3 on_strips = at("strips_to_target_max_at_mm"),
               on_target = at("target_to_strips_max_at_mm");
    EXPECT_LT(strips_surface.closest(on_strips).distance, kWritten);
    EXPECT_NEAR(target.closest(on_strips).distance, q["strips_to_target_max_mm"].get<double>(),
                kWritten);
    EXPECT_LT(target.closest(on_target).distance, kWritten);
    EXPECT_NEAR(strips_surface.closest(on_target).distance,
                q["target_to_strips_max_mm"].get<double>(), kWritten);
  }
  for (int p = 0; p < strips; ++p) {
    char name[32];
    std::snprintf(name, sizeof name, "%03d_3d.obj", p);
    std::ifstream obj(out / "stages" / "patches" / name);
    ASSERT_TRUE(obj) << name;
    int v_lines = 0, f_lines = 0;
    std::map<std::pair<int, int>, int> edge_uses;
    while (std::getline(obj, line)) {
      v_lines += line.rfind("v ", 0) == 0 ? 1 : 0;
      if (line.rfind("f ", 0) != 0) continue;
      ++f_lines;
      std::istringstream f(line.substr(2));
      std::vector<int> ids{std::istream_iterator<int>(f), std::istream_iterator<int>()};
      for (std::size_t k = 0; k < ids.size(); ++k)
        ++edge_uses[{std::min(ids[k], ids[(k + 1) % ids.size()]),
                     std::max(ids[k], ids[(k + 1) % ids.size()])}];
    }
    EXPECT_EQ(f_lines, faces_per_strip[p]) << name;
    const auto& entry = st["patch_list"][p];
    const int rows = entry["rows"].get<int>();
    if (!entry["facet"].get<bool>()) {  // a ladder: rows + 1 rails
      EXPECT_EQ(v_lines, (rows + 1) * (f_lines / rows + 1)) << name;
    } else {  // a disk of quads: V = 1 + F + (boundary edges) / 2
      int boundary = 0;
      for (const auto& [e, uses] : edge_uses) boundary += uses == 1 ? 1 : 0;
      EXPECT_EQ(v_lines, 1 + f_lines + boundary / 2) << name;
    }
    // The flattened patch: same vertex count and faces, every z = 0.
    std::snprintf(name, sizeof name, "%03d_2d.obj", p);
    std::ifstream flat(out / "stages" / "patches" / name);
    ASSERT_TRUE(flat) << name;
    int v2 = 0, f2 = 0;
    while (std::getline(flat, line)) {
      if (line.rfind("v ", 0) == 0) {
        ++v2;
        double x, y, z;
        std::istringstream(line.substr(2)) >> x >> y >> z;
        EXPECT_EQ(z, 0.0);
      }
      f2 += line.rfind("f ", 0) == 0 ? 1 : 0;
    }
    EXPECT_EQ(v2, v_lines) << name;
    EXPECT_EQ(f2, f_lines) << name;
  }
  const auto& fl = report["flatten"];
  // Strips flatten almost exactly; a facet whose corner is shared with other facets is not
  // quite planar in 3D and keeps its border lengths first.
  EXPECT_LT(fl["max_angle_error_deg"].get<double>(), 20.0);
  EXPECT_LT(fl["max_border_length_error_rel"].get<double>(), 0.01);
  // Mating borders have the same length in both parts, well within the 0.05 mm a joint fits to.
  for (const auto& border : fl["borders"])
    EXPECT_LT(
        std::abs(border["length_2d_mm"][0].get<double>() - border["length_2d_mm"][1].get<double>()),
        0.05)
        << border["patches"];
  EXPECT_EQ(fl["inverted_quads"].get<int>(), 0);
  EXPECT_EQ(fl["patches"].size(), static_cast<std::size_t>(strips));
  // Joints: report samples as in docs/outputs.md, and every part's outline in the dump.
  const auto& jt = report["joints"];
  EXPECT_EQ(jt["thickness_mm"].get<double>(), 3.0);
  EXPECT_GT(jt["teeth"].get<int>(), 100);
  ASSERT_GT(jt["samples"].size(), 0u);
  for (const auto& sample : jt["samples"]) {
    EXPECT_GE(sample["fold_deg"].get<double>(), 0.0);
    EXPECT_GE(sample["tip_mm"].get<double>(), 0.0);
    EXPECT_LT(sample["slot_mm"].get<double>(), 0.0);
  }
  // Kerf cuts and the cutting estimate.
  const auto& kf = report["kerf"];
  for (const char* key : {"cuts", "cut_length_mm", "critical_regions", "patches"})
    EXPECT_TRUE(kf.contains(key)) << key;
  EXPECT_GT(kf["cuts"].get<int>(), 100);
  EXPECT_EQ(kf["patches"].size(), static_cast<std::size_t>(strips));
  const auto& cutting = report["cutting"];
  EXPECT_GT(cutting["total_cut_length_mm"].get<double>(), kf["cut_length_mm"].get<double>());
  EXPECT_GT(cutting["estimated_minutes"].get<double>(), 0.0);
  std::ifstream density(out / "model" / "kerf_density.ply");
  ASSERT_TRUE(density);
  long density_faces = -1;
  while (std::getline(density, line) && line != "end_header")
    if (line.rfind("element face ", 0) == 0) density_faces = std::stol(line.substr(13));
  EXPECT_EQ(density_faces, st["sub_quads"].get<long>());
  // Layout: sheets written as SVG, one group per part.
  const auto& lay = report["layout"];
  ASSERT_GE(lay["sheets"].get<int>(), 1);
  EXPECT_EQ(lay["sheet_mm"][0].get<double>(), 600.0);
  EXPECT_GT(lay["utilization"].get<double>(), 0.1);
  EXPECT_TRUE(lay["unplaced"].empty());
  // One sheet: no strip is split to save one.
  EXPECT_FALSE(lay["split_to_fit"]["tried"].get<bool>());
  EXPECT_EQ(lay["split_to_fit"]["saved_sheets"].get<int>(), 0);
  EXPECT_EQ(lay["split_to_fit"]["why_not"], "no nesting uses fewer sheets");
  int groups = 0;
  for (int sheet = 1; sheet <= lay["sheets"].get<int>(); ++sheet) {
    char sheet_name[32];
    std::snprintf(sheet_name, sizeof sheet_name, "sheet-%03d.svg", sheet);
    std::ifstream svg(out / "cut" / sheet_name);
    ASSERT_TRUE(svg) << sheet_name;
    for (const char* ext : {"dxf", "pdf", "png"}) {
      std::snprintf(sheet_name, sizeof sheet_name, "sheet-%03d.%s", sheet, ext);
      EXPECT_GT(fs::file_size(out / "cut" / sheet_name), 1000u) << sheet_name;
    }
    // The PDF page is the sheet: 600 x 450 mm in points.
    std::snprintf(sheet_name, sizeof sheet_name, "sheet-%03d.pdf", sheet);
    std::ifstream pdf(out / "cut" / sheet_name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(pdf)),
                            std::istreambuf_iterator<char>());
    EXPECT_NE(bytes.find("MediaBox [ 0 0 1700.787402 1275.590551 ]"), std::string::npos);
    while (std::getline(svg, line)) groups += line.rfind("<g class=\"part\"", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(groups, strips);
  EXPECT_GT(fs::file_size(out / "cut" / "contact-sheet.png"), 1000u);
  // Assembly aid: every part listed with its neighbours, symmetric, and as a page.
  const auto& assembly = lay["assembly"];
  ASSERT_EQ(assembly.size(), static_cast<std::size_t>(strips));
  for (const auto& entry : assembly) {
    EXPECT_GE(entry["sheet"].get<int>(), 1);
    for (const auto& n : entry["neighbours"]) {
      bool back = false;
      for (const auto& m : assembly[n["part"].get<int>()]["neighbours"])
        back =
            back || (m["part"] == entry["part"] &&
                     std::abs(m["length_mm"].get<double>() - n["length_mm"].get<double>()) < 1e-9);
      EXPECT_TRUE(back) << entry["part"] << " -> " << n["part"];
    }
  }
  EXPECT_GT(fs::file_size(out / "cut" / "assembly.html"), 1000u);
  // Half the borders carry the neighbour's number (184 of 342 on Spot at 250 mm; the others
  // have no room between kerf cuts).
  EXPECT_GT(lay["border_labels"]["placed"].get<int>(),
            lay["border_labels"]["wanted"].get<int>() / 2);
  const auto parts = nlohmann::json::parse(std::ifstream(out / "stages" / "parts.json"));
  ASSERT_EQ(parts["parts"].size(), static_cast<std::size_t>(strips));
  for (const auto& part : parts["parts"]) {
    EXPECT_GE(part["cut"].size(), 4u);
    EXPECT_FALSE(part["repaired"].get<bool>());
  }
  // Buildable: every critical region resolved; the written sheets, read back by the
  // independent auditor, have no cuts closer than the laser can make, none too short, and no
  // engraving off its part, and no part too small or narrow to handle (Spot's snout, 12 quads of
  // 6-18 mm^2 at 250 mm, becomes one plate with its neighbours).
  const auto& res = report["resolve"];
  EXPECT_GT(res["critical_before"].get<int>(), 50);
  EXPECT_EQ(res["critical_after"].get<int>(), 0);
  EXPECT_EQ(report["kerf"]["critical"].size(), 0u);
  EXPECT_EQ(res["small_parts_after"].get<int>(), 0);
  EXPECT_LT(report["quality"]["hausdorff_rel"].get<double>(), 0.01);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.parts, strips);
  EXPECT_EQ(audit.close_cut_pairs, 0);
  EXPECT_EQ(audit.short_cuts, 0);
  EXPECT_EQ(audit.labels_off_part, 0);
  EXPECT_EQ(audit.small_parts + audit.narrow_parts, 0);
  // No tail or slit narrower than 1 mm: the last ones were a tooth's root narrowed to 0.53 mm
  // by a slit widened beside it, a corner joined to the part by a 0.92 mm neck, and 8 hairs of
  // 0.1-0.15 mm by 1.6-2 mm beside slots (a slot's corner wedge that the Booleans returned as a
  // spike plus a hole), which held too little area for the auditor's area rule.
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
  EXPECT_TRUE(audit.clean()) << (audit.findings.empty() ? "" : audit.findings[0]);
}

// Shapes too tight for the sheet at this size: the resolver makes every one buildable, and the
// sheets as written (read back independently) have no defect at all; with --no-resolve the
// same regions stay critical (warned about, cut at the minimum spacing).
TEST(Cli, TooTightShapesAreResolvedIntoCleanSheets) {
  const fs::path scratch = test::fresh_dir();
  struct Case {
    const char* name;
    PolyMesh quads;
    double size;
  };
  const Case cases[] = {{"sphere", test::sphere(40, 4).quads, 30},
                        {"torus", test::torus(60, 20, 16, 8).quads, 50},
                        {"ring", test::open_cylinder(12, 40, 12, 2).quads, 15}};
  for (const Case& c : cases) {
    const fs::path target = scratch / (std::string(c.name) + ".obj");
    write_mesh(c.quads, target);
    const std::string args =
        "run --target " + target.string() + " --size " + std::to_string(c.size) + " --out ";
    const fs::path out = scratch / c.name, before = scratch / (std::string(c.name) + "-paper");
    const CliRun r = run_cli(args + out.string(), scratch);
    ASSERT_EQ(r.exit_code, 0) << c.name << r.err;
    const auto report = read_report(out);
    const auto& res = report["resolve"];
    EXPECT_GT(res["critical_before"].get<int>(), 0) << c.name;
    EXPECT_EQ(res["critical_after"].get<int>(), 0) << c.name;
    EXPECT_EQ(res["small_parts_after"].get<int>(), 0) << c.name;
    EXPECT_GT(res["changes"].size(), 0u) << c.name;
    for (const auto& change : res["changes"]) EXPECT_NE(change["action"], "unresolved");
    // The size at which no change would be needed is larger than this one.
    EXPECT_GT(res["min_size_mm"].get<double>(), c.size) << c.name;
    EXPECT_EQ(report["flatten"]["inverted_quads"].get<int>(), 0) << c.name;
    EXPECT_LT(report["flatten"]["max_angle_error_deg"].get<double>(), 20.0) << c.name;
    expect_all_placed_and_clean(report, out, c.name);

    const CliRun paper = run_cli(args + before.string() + " --no-resolve", scratch);
    ASSERT_EQ(paper.exit_code, 0) << c.name << paper.err;
    const auto kept = read_report(before);
    EXPECT_EQ(kept["resolve"]["critical_after"], kept["resolve"]["critical_before"]);
    EXPECT_EQ(kept["kerf"]["critical"].size(),
              static_cast<std::size_t>(res["critical_before"].get<int>()));
    EXPECT_NE(paper.err.find("remain critical"), std::string::npos) << paper.err;
  }
}

// The resolve step keeps a time limit: with a limit shorter than its first round (the sphere
// of the test above, too tight at 30 mm) it starts no round, says so on stderr and in the
// report, and lists every region it left as unresolved, with that reason. The sheets are still
// written (the regions cut at the minimum spacing, as with --no-resolve).
TEST(Cli, TheResolveStepKeepsItsTimeLimit) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "sphere.obj", out = scratch / "out";
  write_mesh(test::sphere(40, 4).quads, target);
  const CliRun r = run_cli("run --target " + target.string() +
                               " --size 30 --resolve-time-limit 0.000001 --out " + out.string(),
                           scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  const auto& res = report["resolve"];
  EXPECT_TRUE(res["time_limited"].get<bool>());
  EXPECT_EQ(res["rounds"].get<int>(), 0);
  EXPECT_GT(res["critical_before"].get<int>(), 0);
  EXPECT_EQ(res["critical_after"], res["critical_before"]);
  int unresolved = 0;
  for (const auto& change : res["changes"]) {
    EXPECT_EQ(change["action"], "unresolved");
    EXPECT_NE(change["reason"].get<std::string>().find("time limit"), std::string::npos)
        << change["reason"];
    ++unresolved;
  }
  EXPECT_EQ(unresolved, res["critical_after"].get<int>() + res["small_parts_after"].get<int>());
  EXPECT_NE(r.err.find("stopped at its time limit"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::is_empty(out / "cut"));
  // Out of range: one line, exit 1.
  const CliRun bad = run_cli("run --target " + target.string() + " --resolve-time-limit 0 --out " +
                                 (scratch / "bad").string(),
                             scratch);
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
}

// A given quad mesh far too fine for 3 mm MDF (a ring of 2 mm rows, R 30 mm): the quads stage
// collapses rows, says so in the report and writes the mesh it used; the sheets come out clean
// with kerf cuts on bent rings. With --no-coarsen the rows stay as given (the resolve stage then
// merges them sideways instead).
TEST(Cli, AFineGivenQuadMeshIsCoarsenedIntoCleanBentStrips) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "ring.obj";
  write_mesh(test::open_cylinder(30, 60, 48, 30, 1).quads, target);
  const std::string args = "run --quiet --target " + target.string() + " --out ";
  const fs::path out = scratch / "coarse";
  ASSERT_EQ(run_cli(args + out.string(), scratch).exit_code, 0);
  const auto report = read_report(out);
  EXPECT_EQ(report["quads"]["method"], "given, coarsened");
  EXPECT_EQ(report["quads"]["given_quads"].get<int>(), 48 * 30);
  EXPECT_LT(report["quads"]["quads"].get<int>(), 48 * 8);
  EXPECT_EQ(report["options"]["coarsen"], true);
  const PolyMesh used = read_mesh(out / "model" / "quads.obj");
  EXPECT_EQ(static_cast<int>(used.n_faces()), report["quads"]["quads"].get<int>());
  EXPECT_GT(report["kerf"]["cuts"].get<int>(), 100);
  EXPECT_EQ(report["resolve"]["critical_after"].get<int>(), 0);
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_TRUE(audit.clean()) << (audit.findings.empty() ? "" : audit.findings[0]);
  const fs::path as_given = scratch / "given";
  ASSERT_EQ(run_cli(args + as_given.string() + " --no-coarsen", scratch).exit_code, 0);
  const auto given = read_report(as_given);
  EXPECT_FALSE(given.contains("quads"));
  EXPECT_FALSE(fs::exists(as_given / "model" / "quads.obj"));
  EXPECT_EQ(given["input"]["quads"].get<int>(), 48 * 30);
  EXPECT_EQ(given["options"]["coarsen"], false);
}

// Spot's fine quad mesh at 200 mm: two tooth rectangles, 0.1 and 0.16 mm thick, ran over the mouth
// of a notch of part 304's outline, hanging 0.9 mm, 0.25 mm apart, and the laser path into the
// notch passed within 0.1 mm of itself; the run named nothing there. Such slivers now go
// (tooth_slivers): the sheet, read back by the independent auditor, has no slit or tail, and
// what it finds besides is a part the run names as too small to handle.
TEST(Cli, ToothSliversOverANotchGoFromSpotsFineQuadMesh) {
  const fs::path out = test::fresh_dir() / "out";
  const auto report =
      run_quietly("--target " + test::real_mesh("spot_triangulated.obj").string() + " --quad " +
                      test::real_mesh("spot_quadrangulated.obj").string() + " --size 200",
                  out);
  ASSERT_FALSE(report.is_null());
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
  int unresolved_small = 0;
  for (const auto& c : report["resolve"]["changes"])
    if (c["action"] == "unresolved" &&
        c["reason"].get<std::string>().find("too small") != std::string::npos)
      ++unresolved_small;
  EXPECT_LE(audit.small_parts, unresolved_small) << "every small part found is one the run names";
  EXPECT_EQ(audit.narrow_parts + audit.labels_off_part + audit.close_part_pairs, 0)
      << (audit.findings.empty() ? "" : audit.findings[0]);
}

// Spot's fine quad mesh (2928 quads, coarsened) at 250 mm: no part of the written sheets hangs
// on a neck narrower than the smallest feature, read back by the independent auditor. Where the
// joints made such a neck (part 288 here: a 4 x 3 mm strip end joined by 0.95 mm, between a slot
// on one side and a tooth on the other), the intervals near it go plain; a border that so loses
// its last joint gets a tooth elsewhere if one fits (a tooth once hung on a 0.3 mm neck here,
// which the auditor's area rule missed). The borders without a joint of their own are stubs of
// 0.7-3.2 mm (6; 7 before), each held through the parts at one of its corners: in the report,
// every step of its chain is a border with a joint between those two parts. A part that ends up too
// small to handle is one the report names; the one there was (the horn's tip, 48.4 mm^2 once that
// tooth had gone) now owns its borders' teeth instead of their slots and is none.
TEST(Cli, JointsLeaveNoThinNeckOnSpotsFineQuadMesh) {
  const fs::path out = test::fresh_dir() / "out";
  const auto report =
      run_quietly("--target " + test::real_mesh("spot_triangulated.obj").string() + " --quad " +
                      test::real_mesh("spot_quadrangulated.obj").string() + " --size 250",
                  out);
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["resolve"]["critical_after"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  std::set<std::pair<int, int>> jointed;
  for (const auto& b : report["joints"]["borders"]) {
    const std::string kind = b["joint"];
    if (kind == "none" || kind == "corner") continue;
    const int p = b["patches"][0], q = b["patches"][1];
    jointed.insert({std::min(p, q), std::max(p, q)});
  }
  int stubs = 0;
  for (const auto& b : report["joints"]["borders"]) {
    if (b["joint"] != "corner") continue;
    ++stubs;
    EXPECT_LE(b["length_mm"].get<double>(), 3.5);
    const std::vector<int> chain = b["joined_through"];
    ASSERT_GE(chain.size(), 2u);
    EXPECT_EQ(chain.front(), b["patches"][0].get<int>());
    EXPECT_EQ(chain.back(), b["patches"][1].get<int>());
    for (std::size_t k = 0; k + 1 < chain.size(); ++k)
      EXPECT_TRUE(
          jointed.contains({std::min(chain[k], chain[k + 1]), std::max(chain[k], chain[k + 1])}))
          << chain[k] << " - " << chain[k + 1];
  }
  EXPECT_EQ(stubs, report["joints"]["stubs_joined_at_corners"].get<int>());
  EXPECT_LE(stubs, 7);
  const auto audit = test::audit_sheets(out / "cut");
  const std::string first = audit.findings.empty() ? "" : audit.findings[0];
  EXPECT_EQ(audit.thin_features, 0) << first;
  EXPECT_EQ(
      audit.close_cut_pairs + audit.short_cuts + audit.labels_off_part + audit.close_part_pairs, 0)
      << first;
  EXPECT_EQ(audit.small_parts + audit.narrow_parts,
            report["resolve"]["small_parts_after"].get<int>())
      << first;
  EXPECT_EQ(audit.small_parts + audit.narrow_parts, 0) << first;
}

// A triangle mesh alone, the input most users have: the prepare stage says the quads stage
// will mesh it, not "quads: 0 vertices, 0 faces ()" and distances of quads that do not exist.
TEST(Cli, ATriangleMeshAloneIsNotSummarisedAsAnEmptyQuadMesh) {
  const auto shape = test::sphere(50, 2);
  PolyMesh triangles;
  for (const auto& p : shape.target.vertices) triangles.add_vertex(to_openmesh(p));
  for (const auto& t : shape.target.triangles)
    triangles.add_face({triangles.vertex_handle(t[0]), triangles.vertex_handle(t[1]),
                        triangles.vertex_handle(t[2])});
  const PreparedInput in = prepare_input(triangles, std::nullopt, {});
  ASSERT_EQ(in.quad_summary.faces, 0);
  const StageNotes n = notes(in);
  std::string all;
  for (const auto& line : n.lines) all += line + "\n";
  EXPECT_NE(all.find("quads: none given; the quads stage makes them from the target"),
            std::string::npos)
      << all;
  EXPECT_EQ(all.find("0 faces"), std::string::npos) << all;
  EXPECT_EQ(all.find("quad vertices to target"), std::string::npos) << all;
  EXPECT_NE(all.find("target: "), std::string::npos) << all;
}

// A cup modelled for printing (80 mm across, 100 high, walls and floor 3 mm thick, its wall a
// 48-gon) at its own size: its inner and outer walls stand 3 mm apart, as thick as the sheets.
// The run failed after its resolve stage ("surface distance: sample spacing too fine for the
// model size"): the check of how far the final strips move when deformed to their flat metric
// had no sample budget, and a part flattened distorted had its deformed corners 54 m away. It
// now runs to the end and says where the shape is thinner than the sheets, and the size at
// which every gap would reach their thickness.
TEST(Cli, ACupWithWallsAsThickAsTheSheetsRunsToTheEndAndSaysSo) {
  const fs::path scratch = test::fresh_dir();
  const fs::path target = scratch / "cup.obj";
  {
    std::ofstream f(target);
    const int n = 48;
    const std::array<std::pair<double, double>, 4> rings = {
        {{40, 0}, {40, 100}, {37, 100}, {37, 3}}};  // outer bottom, outer top, inner top, floor
    for (const auto& [r, z] : rings)
      for (int k = 0; k < n; ++k)
        f << "v " << r * std::cos(2 * M_PI * k / n) << " " << r * std::sin(2 * M_PI * k / n) << " "
          << z << "\n";
    f << "v 0 0 0\nv 0 0 3\n";
    const int c0 = 4 * n + 1, c1 = 4 * n + 2;
    for (int k = 0; k < n; ++k) {
      const int a = k + 1, b = (k + 1) % n + 1;
      for (int ring = 0; ring < 3; ++ring)  // outer wall, rim, inner wall
        f << "f " << ring * n + a << " " << ring * n + b << " " << (ring + 1) * n + b << " "
          << (ring + 1) * n + a << "\n";
      f << "f " << c0 << " " << b << " " << a << "\nf " << c1 << " " << 3 * n + a << " "
        << 3 * n + b << "\n";
    }
  }
  const fs::path out = scratch / "out";
  const CliRun r = run_cli("run --target " + target.string() + " --out " + out.string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_TRUE(std::isfinite(report["flatten"]["deformed_3d_hausdorff_mm"].get<double>()));
  const auto clearance = report["quality"]["clearance"];
  EXPECT_FALSE(clearance["contacts"].empty());
  EXPECT_LT(clearance["min_thin_gap_mm"].get<double>(), 3.0);
  EXPECT_NE(r.err.find("the shape is thinner than its 3 mm sheets"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("every gap reaches the thickness"), std::string::npos) << r.err;
}

// Demosthenes' bust from its triangles alone (a model no test was written for; 845 quads of
// 15.8 mm at 250 mm, creases in its hair and faces folded back thinner than the sheets). Its
// resolve loop once went 4, 17, 4, 17 ... critical regions to its last round, listed a quad's
// facets up to five times among its changes (558 listed, 110 twice or more), and named
// "--size 55062261312" (from a strip's pointed tip, where no beam is). The loop ends where a
// round starts from a state seen before; no change is listed twice; no size past 10 m is named.
TEST(Cli, AnUnseenBustEndsItsResolveLoopAndNamesNoAbsurdSize) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir(), out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + (test::shared_meshes() / "demosthenes-low-res.obj").string() +
                  " --size 250 --out " + out.string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The rounds' progress lines: (critical, small, parts) never ends in a cycle run twice.
  std::vector<std::string> rounds;
  std::istringstream lines(r.err);
  for (std::string line; std::getline(lines, line);)
    if (const auto at = line.find("round ");
        at != std::string::npos && line.find(": ") != std::string::npos)
      rounds.push_back(line.substr(line.find(": ", at)));
  ASSERT_GE(rounds.size(), 3u) << r.err;
  for (std::size_t period = 1; period <= 3; ++period) {
    if (rounds.size() < 2 * period + 1) continue;
    bool cycle = true;
    for (std::size_t k = rounds.size() - 2 * period; k < rounds.size(); ++k)
      cycle = cycle && rounds[k] == rounds[k - period];
    EXPECT_FALSE(cycle) << "period " << period << ": " << r.err;
  }
  const auto report = read_report(out);
  std::set<std::tuple<std::string, std::vector<int>, std::string>> seen;
  for (const auto& c : report["resolve"]["changes"]) {
    auto quads = c["quads"].get<std::vector<int>>();
    std::sort(quads.begin(), quads.end());
    EXPECT_TRUE(seen.insert({c["action"], quads, c["reason"]}).second) << c;
  }
  EXPECT_GT(seen.size(), 100u);
  // Two facets of its hair flattened with an inverted quad or 12 deg off (corners shared with
  // facets at other angles). Cut along their outlines they lie flat, though one still falls
  // apart at its slots: the loop kept that only where the parts too small or distorted became
  // fewer, so both stayed distorted, with three borders beside them left without a joint
  // (6 in all, 7.9 mm^2 lost). As many defects with fewer distorted is now kept as well.
  // Since 2026-12-03 a facet its loop had grown to 91 quads, 25 mm off its plane, that still
  // flattened inverted with an outline crossing itself, is put back as it was: no part
  // flattens inverted; a part named unresolved there falls apart at its slots, 4 mm^2 lost
  // (under 1 mm^2 before).
  int outline_cuts = 0;
  for (const auto& c : report["resolve"]["changes"]) outline_cuts += c["action"] == "outline";
  EXPECT_GE(outline_cuts, 1);
  EXPECT_LE(report["joints"]["borders_without_joint"].get<int>(), 3);
  EXPECT_LT(report["joints"]["lost_area_mm2"].get<double>(), 5.0);
  // No part hangs on a neck under 1 mm that the run does not name (parts 281 and 305 until
  // 2026-12-03: the stub tooth of the 5.1 mm border between them, its only joint, made the
  // necks; that border is now held at a corner instead). Since 2026-12-04 its quads are made at
  // a feature angle of 65 deg (docs/quad-meshing.md): one part (313) is a strip end with a tooth
  // on a neck 0.94 mm wide where a slit of its flattened outline ends, and the run names it
  // (with the quads of 60 deg none here, but 4 to 6 at 150, 200 and 320 mm, where the new
  // quads leave 3, 1 and 2; 10 against 23 over the bust's eight runs measured).
  EXPECT_LE(report["joints"]["thin_neck_parts"].size(), 1u) << report["joints"]["thin_neck_parts"];
  if (!report["joints"]["thin_neck_parts"].empty()) {
    EXPECT_NE(r.err.find("joints.thin_neck_parts"), std::string::npos) << r.err;
  }
  // Its sheet, read back by the auditor: no tail or slit a cutter cannot follow (until
  // 2026-12-03 part 295 kept an L of tooth material 0.08 mm wide, and the laser path passed
  // within 0.5 mm of itself there).
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
  for (const auto& p : report["flatten"]["patches"]) {
    EXPECT_EQ(p["inverted_quads"].get<int>(), 0) << p;
    EXPECT_TRUE(p["outline_simple"].get<bool>()) << p;
  }
  for (std::size_t at = r.err.find("--size "); at != std::string::npos;
       at = r.err.find("--size ", at + 1)) {
    const std::string rest = r.err.substr(at + 7, 20);
    if (rest.empty() || !std::isdigit(static_cast<unsigned char>(rest[0]))) continue;
    EXPECT_LE(std::stod(rest), 10000.0) << r.err.substr(at, 60);
  }
}

/// The resolve loop's splits in \p report whose reason says \p phrase.
int splits_saying(const nlohmann::json& report, const std::string& phrase) {
  int n = 0;
  for (const auto& c : report["resolve"]["changes"])
    if (c["action"] == "split" && c["reason"].get<std::string>().find(phrase) != std::string::npos)
      ++n;
  return n;
}

// Fandisk from its triangles at 250 mm in 4 mm plywood (quads sized for that material): a facet
// of 6 quads narrowed to a neck 0.38 mm wide (a near-triangle quad of the mesh), whose far
// stretch the laser would burn or a maker break off. The resolve loop's cut across the neck was
// refused because the border it makes there, 0.38 mm long, has no joint; a neck that narrow
// holds none either, so the cut is now kept and that border named as too short for any tooth.
TEST(Cli, APlywoodFacetOnANeckIsCutInTwoAcrossIt) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir(), out = scratch / "out";
  const CliRun r = run_cli("run --target " + (test::shared_meshes() / "fandisk.obj").string() +
                               " --size 250 --material plywood --out " + out.string(),
                           scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  EXPECT_TRUE(report["joints"]["thin_neck_parts"].empty()) << report["joints"]["thin_neck_parts"];
  EXPECT_GE(splits_saying(report, "narrowed to a neck"), 1);
  // Every border left without a joint is shorter than the smallest feature, and said to be.
  for (const auto& b : report["joints"]["borders"]) {
    if (b["joint"] == "none") {
      EXPECT_LT(b["length_mm"].get<double>(), 1.0) << b;
    }
  }
  if (report["joints"]["borders_without_joint"].get<int>() > 0) {
    EXPECT_NE(r.err.find("shorter than the smallest feature"), std::string::npos) << r.err;
  }
  // Read back from the sheet: no tail, slit or part a cutter or a maker cannot handle (the neck
  // was a tail under 1 mm, and the laser path passed within 0.5 mm of itself there).
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_TRUE(audit.clean()) << (audit.findings.empty() ? "" : audit.findings[0]);
}

// Demosthenes from its triangles at 250 mm in 2 mm MDF: a notch 4.4 mm deep tapering to 0.79 mm
// at its end (part 402). The outline cleanup widened it once, by what it lacked on average, and
// left its end under the smallest feature; the auditor, reading the laser path, found a slit
// under 1 mm on a part the run did not name. The cleanup now widens again until none is left.
// Since the bust's quads are made with its feature angle raised to 65 deg (its lattice pairs
// there), the same run found a spike 1.4 mm long and 0.6 mm wide at its root (part 293) that
// the cleanup's opening kept on the outline as designed and the auditor's took off the outline
// as cut, where the laser path's offset had merged two corners 0.04 mm apart. The cleanup now
// looks again at the outline as cut.
TEST(Cli, ATaperingSlitIsWidenedAllTheWayToItsEnd) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir(), out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + (test::shared_meshes() / "demosthenes-low-res.obj").string() +
                  " --size 250 --material mdf2 --out " + out.string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json quads = read_report(out)["quads"];
  EXPECT_NEAR(quads["feature_angle_deg"].get<double>(), 65, 1e-9) << quads;
  EXPECT_EQ(quads["unpaired_triangles"].get<int>(), 0) << quads;
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
}

// Demosthenes from its triangles at 500 mm (3 mm MDF): a slit widened beside a box tooth 0.56 mm
// deep at a part's corner (part 328) narrowed the material under it to a stalk 1 mm wide, and the
// tooth hung over it, its overhang under 1 mm thick: a tail the auditor found on a part the run
// did not name. The cleanup's pass after the widening took the tails it made but spared tooth
// material; it now takes a tooth's slivers there too, as its first pass does.
TEST(Cli, AToothLeftOverhangingAWidenedSlitLosesItsOverhang) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir(), out = scratch / "out";
  const CliRun r =
      run_cli("run --target " + (test::shared_meshes() / "demosthenes-low-res.obj").string() +
                  " --size 500 --out " + out.string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto audit = test::audit_sheets(out / "cut");
  EXPECT_EQ(audit.thin_features, 0) << (audit.findings.empty() ? "" : audit.findings[0]);
  EXPECT_EQ(read_report(out)["resolve"]["critical_after"].get<int>(), 0);
}

// Fandisk from its triangles at 250 mm: a strip runs between a sharp fold and a part folded back
// onto it, whose mitres cut across it (one 17 mm deep); even with plain borders it came apart,
// and the run kept its larger piece only: 594 mm^2 of surface lost, with three borders beside it
// left without a joint. The resolve loop now splits such a strip at the coarse edge where it
// comes apart, so that the piece it lost is a part of its own, kept where the two pieces then
// hold at least the part's area and half of what it lost. (Since its flat sides are cut as one
// plate each, fandisk's run no longer needs that split; horse_quad's does, and loses nothing.)
// A facet that only narrows to a thin neck is cut in two facets there (fandisk, below).
TEST(Cli, APartThatFallsApartIsSplitWhereItComesApart) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir(), out = scratch / "out";
  {
    const fs::path horse = scratch / "horse";
    const CliRun h = run_cli("run --target " + (test::shared_meshes() / "horse_quad.obj").string() +
                                 " --size 250 --out " + horse.string(),
                             scratch);
    ASSERT_EQ(h.exit_code, 0) << h.err;
    const auto report = read_report(horse);
    EXPECT_GE(splits_saying(report, "fell apart"), 1);
    EXPECT_LT(report["joints"]["lost_area_mm2"].get<double>(), 1.0);
    EXPECT_EQ(report["resolve"]["critical_after"].get<int>(), 0);
  }
  const CliRun r = run_cli("run --target " + (test::shared_meshes() / "fandisk.obj").string() +
                               " --size 250 --out " + out.string(),
                           scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(out);
  // What is still lost: pieces at the end of a coarse quad, which no split along a coarse edge
  // frees (87.5 mm^2 at most); before, 612 mm^2 in all.
  EXPECT_LT(report["joints"]["lost_area_mm2"].get<double>(), 200.0);
  EXPECT_LT(report["joints"]["largest_lost_piece_mm2"].get<double>(), 100.0);
  EXPECT_LE(report["joints"]["borders_without_joint"].get<int>(), 3);
  EXPECT_EQ(report["resolve"]["critical_after"].get<int>(), 0);
  // A facet of 9 quads narrowed to 0.75 mm where a sharp fold's mitre reached across it (part
  // 100 until 2026-12-03, named in joints.thin_neck_parts): the loop now cuts it in two facets
  // there, and no part hangs on a neck.
  EXPECT_EQ(splits_saying(report, "narrowed to a neck"), 1);
  EXPECT_TRUE(report["joints"]["thin_neck_parts"].empty()) << report["joints"]["thin_neck_parts"];
}

// The sizes the resolve warning names are what a user types after --size: whole millimetres,
// never in exponent notation (horse_quad's said "would hold at --size 1.224e+04": a line keeps
// four digits). Past 10 m no size is named (Demosthenes' bust said "--size 55062261312": a
// strip's pointed tip, and faces folded back thinner than the sheets), only that none up to
// 10 m would do; a material is named where it does at 10 m or less.
// The loop here changed no region (its changes are the parts it left unresolved) and none
// stays critical, as on a paper model whose parts stay too small: the warning begins with its
// count, not with a bare "; " (horse_quad in paper at 250 mm said "kerfab: warning: ; 18 parts
// stay too small ...").
// The clearance warnings: thin places name the parts, where, and the size that clears them;
// parts inside out are named apart, with no size (their quads fold over their neighbours).
TEST(Cli, ClearanceWarningsNameThinPlacesAndPartsInsideOut) {
  ShellClearance c;
  c.thickness = 3;
  c.samples = 100;
  c.spacing = 3;
  EXPECT_TRUE(notes(c, 250, true).warnings.empty());
  c.contacts.push_back({4, 9, 0.05, Vec3(1, 2, 3), Vec3(1, 2, 3.05), 40, 9});
  c.contacts.push_back({2, 7, 1.5, Vec3(4, 5, 6), Vec3(4, 5, 7.5), 300, -1});
  const auto w = notes(c, 250, true).warnings;
  ASSERT_EQ(w.size(), 2u);
  // 250 x 3 / 1.5 = 500: the part inside out asks for no size.
  EXPECT_NE(w[0].find("the shape is thinner than its 3 mm sheets in 1 place (300 mm^2"),
            std::string::npos)
      << w[0];
  EXPECT_NE(w[0].find("parts 2 and 7 1.5 mm apart at (4, 5, 6) mm"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("at --size 500 every gap reaches the thickness"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("1 part lies inside out over the parts beside it"), std::string::npos)
      << w[1];
  EXPECT_NE(w[1].find("part 9 over part 4 0.05 mm apart"), std::string::npos) << w[1];
  EXPECT_NE(w[1].find("which no --size cures"), std::string::npos) << w[1];
  EXPECT_NE(w[1].find("model/quads.obj"), std::string::npos) << w[1];
  EXPECT_EQ(notes(c, 250, false).warnings[1].find("model/quads.obj"), std::string::npos);
}

// bunny_closed from its triangles at 250 mm: two quads of the mesh kerfab made bridge the base
// of an ear, folded over their neighbours. The parts cut from them lay inside out, 0.04 and
// 0.58 mm over three others and facing them (the clearance check found them; nothing else
// did), and a border beside them had no joint. They are left out now (their surface lies
// within 4.3 mm of the parts kept): no part lies inside out, and every border has a joint.
TEST(Cli, PartsInsideOutAreLeftOutWhereTheyLieOverTheirNeighbours) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir();
  const CliRun r =
      run_cli("run --target " + (test::shared_meshes() / "bunny_closed_odedstein.obj").string() +
                  " --size 250 --out " + (scratch / "b").string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(scratch / "b");
  int inside_out = 0;
  for (const auto& c : report["resolve"]["changes"])
    if (c["action"] == "omit" &&
        c["reason"].get<std::string>().find("inside out") != std::string::npos) {
      ++inside_out;
      EXPECT_LE(c["local_distance_mm"].get<double>(), 2 * 3.0) << c;
    }
  EXPECT_GE(inside_out, 1);
  for (const auto& k : report["quality"]["clearance"]["contacts"])
    EXPECT_EQ(k["inside_out"].get<int>(), -1) << k;
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  EXPECT_EQ(r.err.find("inside out over"), std::string::npos) << r.err;
}

// bunny_closed at 200 mm: where a part was too small to handle, the resolve stage grew a facet
// round it over curved ground to make it bigger, taking in the facets beside it whole, to 105
// quads 43 mm off their plane under the base, and still not big enough once cut back: it
// flattened with 26 inverted quads and an outline crossing itself, its strips 19 mm off the
// target (Hausdorff 6.2 %), six borders beside it without a joint. A facet that grows past 16
// quads without becoming big enough is put back as it was: no part flattens inverted or with
// an outline crossing itself, no facet has more than 16 quads, and the strips lie within
// 5.5 % of the diagonal.
TEST(Cli, AFacetThatCannotGrowBigEnoughIsNotSpreadOverTheShape) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir();
  const CliRun r =
      run_cli("run --target " + (test::shared_meshes() / "bunny_closed_odedstein.obj").string() +
                  " --size 200 --out " + (scratch / "b").string(),
              scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(scratch / "b");
  for (const auto& p : report["flatten"]["patches"]) {
    EXPECT_EQ(p["inverted_quads"].get<int>(), 0) << p;
    EXPECT_TRUE(p["outline_simple"].get<bool>()) << p;
  }
  for (const auto& p : report["strips"]["patch_list"]) {
    if (p["facet"].get<bool>()) {
      EXPECT_LE(p["quads"].get<int>(), 16) << p;
    }
  }
  EXPECT_LT(report["quality"]["hausdorff_rel"].get<double>(), 0.055);
}

TEST(Cli, SizesToRunAtReadAsWholeMillimetres) {
  ResolveResult r;
  r.current_size_mm = 250;
  r.small_parts_after = 8;
  r.small_parts_size_mm = 9239.2;
  r.min_size_mm = 9233.4;
  r.materials = {{"mdf2", 2.0, 5705.1}};
  r.changes.resize(8);
  for (RegionChange& c : r.changes) c.action = "unresolved";
  // The one warning the notes give, never in exponent notation, beginning with its count.
  auto warning = [&r] {
    const StageNotes n = notes(r, KerfOptions{});
    EXPECT_EQ(n.warnings.size(), 1u);
    const std::string w = n.warnings.at(0);
    EXPECT_EQ(w.find("e+"), std::string::npos) << w;
    EXPECT_EQ(w.rfind("8 parts stay too small or narrow to handle", 0), 0u) << w;
    return w;
  };
  std::string w = warning();
  EXPECT_NE(w.find("would hold at --size 9240"), std::string::npos) << w;
  EXPECT_NE(w.find("need no change at --size 9234"), std::string::npos) << w;
  EXPECT_NE(w.find("(in --material mdf2 at 5706)"), std::string::npos) << w;
  r.small_parts_size_mm = 29679;
  r.min_size_mm = 55062261311.4;
  r.materials = {{"mdf2", 2.0, 46075818663.2}};
  w = warning();
  EXPECT_NE(w.find("which no --size up to 10 m would hold"), std::string::npos) << w;
  EXPECT_NE(w.find("need a change at every --size up to 10 m"), std::string::npos) << w;
  EXPECT_EQ(w.find("--material"), std::string::npos) << w;
  EXPECT_EQ(w.find("29679"), std::string::npos) << w;
  r.materials = {{"mdf2", 2.0, 9705.1}};
  w = warning();
  EXPECT_NE(w.find("up to 10 m (in --material mdf2 at 9706)"), std::string::npos) << w;
  EXPECT_EQ(w.find("--quad"), std::string::npos) << w;
  // Quads kerfab made from the triangles: a size named holds for these quads (the bunny's
  // "would hold at --size 3837" did, 0 unresolved, with its quads.obj passed back); a run from
  // the triangles at that size would make others. Named only where a size is named: here
  // the material's 9706, then none.
  EXPECT_NE(notes(r, KerfOptions{}, true).warnings.at(0).find("--quad"), std::string::npos);
  r.materials.clear();
  EXPECT_EQ(notes(r, KerfOptions{}, true).warnings.at(0).find("--quad"), std::string::npos);
  r.small_parts_size_mm = 3836.2;
  const std::string made = notes(r, KerfOptions{}, true).warnings.at(0);
  EXPECT_NE(made.find("would hold at --size 3837"), std::string::npos) << made;
  EXPECT_NE(made.find("with this run's quads: add --quad model/quads.obj"), std::string::npos)
      << made;
  EXPECT_EQ(notes(r, KerfOptions{}).warnings.at(0).find("--quad"), std::string::npos);
  // Parts that flatten distorted are named apart, with no size: their quads' angles are the
  // same at every scale (Cli.DistortedPartsAreNotPromisedASize).
  r.distorted_parts_after = 3;
  const std::string apart = notes(r, KerfOptions{}, true).warnings.at(0);
  EXPECT_EQ(apart.rfind("5 parts stay too small or narrow to handle", 0), 0u) << apart;
  EXPECT_NE(apart.find("which would hold at --size 3837; 3 parts flatten distorted"),
            std::string::npos)
      << apart;
  EXPECT_NE(apart.find("which no --size cures: the quads there would need to lie flatter "
                       "(model/quads.obj edited, passed back with --quad)"),
            std::string::npos)
      << apart;
  r.distorted_parts_after = 8;
  r.small_parts_size_mm = 0;
  const std::string all = notes(r, KerfOptions{}).warnings.at(0);
  EXPECT_EQ(all.rfind("8 parts flatten distorted", 0), 0u) << all;
  EXPECT_EQ(all.find("would hold"), std::string::npos) << all;
  EXPECT_NE(all.find("would need to lie flatter (the quad mesh edited there)"), std::string::npos)
      << all;
  // Parts that fell apart where their joints leave them whole have no size: it is named for
  // the others alone.
  r.distorted_parts_after = 0;
  r.unsized_parts_after = 2;
  r.small_parts_size_mm = 819.2;
  const std::string unsized = notes(r, KerfOptions{}).warnings.at(0);
  EXPECT_NE(unsized.find("8 parts stay too small or narrow to handle (resolve.changes, "
                         "\"unresolved\"), 6 of which would hold at --size 820; for 2 no size "
                         "is known"),
            std::string::npos)
      << unsized;
  r.unsized_parts_after = 8;
  const std::string none = notes(r, KerfOptions{}).warnings.at(0);
  EXPECT_EQ(none.find("would hold"), std::string::npos) << none;
  EXPECT_NE(none.find("; for 8 no size is known"), std::string::npos) << none;
  // Regions left critical where a cut does not fit between the joints are named apart, with
  // the size from which their cuts fit (Cli.ACutThatDoesNotFitBetweenTheJointsNamesTheSize).
  ResolveResult c;
  c.current_size_mm = 200;
  c.critical_after = 3;
  c.narrow_after = 2;
  c.narrow_size_mm = 202.39;
  c.changes.resize(3);
  for (RegionChange& change : c.changes) change.action = "unresolved";
  const std::string narrow = notes(c, KerfOptions{}).warnings.at(0);
  EXPECT_NE(narrow.find("3 remain critical (kerf.critical): 1 where the cuts keep 0.9 mm but the "
                        "bend overstresses the beams, 2 where a cut the bend needs does not fit "
                        "between the part's joints"),
            std::string::npos)
      << narrow;
  EXPECT_NE(narrow.find("which --size 203 would fit"), std::string::npos) << narrow;
  c.narrow_size_mm = 0;  // unknown: none named
  EXPECT_EQ(notes(c, KerfOptions{}).warnings.at(0).find("would fit"), std::string::npos);
  c.narrow_after = 0;  // as before: the overstressed beams alone
  EXPECT_NE(notes(c, KerfOptions{})
                .warnings.at(0)
                .find("3 remain critical: their cuts keep 0.9 mm but the bend overstresses"),
            std::string::npos);
}

// A torus from its triangles at 200 mm in 3 mm MDF kept two critical regions that the resolve
// loop could not mend (16 rounds, every change undone), named as beams the bend overstresses
// "even at the minimum spacing": their cuts were 1.05 and 1.12 mm apart. What was short there
// is the strip's width: 9.4 mm across, the slots on both its borders, the margins and the bridge
// left 1.9 mm of a cut that must be 2 mm long, so the cuts were skipped. The regions now say so
// (cause too_narrow, and the reason), with the size from which such a cut fits: the strip grows
// with the model, its joints, margins and bridge do not (--size 203). Run there with the quads
// passed back, no region is critical and the sheets are clean to the auditor.
TEST(Cli, ACutThatDoesNotFitBetweenTheJointsNamesTheSize) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir();
  const std::string torus = (test::shared_meshes() / "torus.obj").string();
  const CliRun r =
      run_cli("run --target " + torus + " --size 200 --out " + (scratch / "t").string(), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(scratch / "t");
  int narrow = 0;
  for (const auto& c : report["kerf"]["critical"]) {
    if (c["cause"] != "too_narrow") continue;
    ++narrow;
    EXPECT_GT(c["fit_factor"].get<double>(), 1.0) << c;
    EXPECT_LT(c["fit_factor"].get<double>(), 1.1) << c;  // 0.1 mm short on a 9.4 mm strip
  }
  ASSERT_GE(narrow, 1);
  EXPECT_EQ(report["resolve"]["narrow_after"].get<int>(), narrow);
  int named = 0;
  for (const auto& c : report["resolve"]["changes"])
    if (c["action"] == "unresolved")
      named +=
          c["reason"].get<std::string>().find("does not fit the part there") != std::string::npos;
  EXPECT_EQ(named, narrow);
  const double size = report["resolve"]["narrow_min_size_mm"].get<double>();
  ASSERT_GT(size, 200.0);
  const std::string at = std::to_string(static_cast<int>(std::ceil(size)));
  EXPECT_NE(r.err.find("which --size " + at + " would fit"), std::string::npos) << r.err;
  const CliRun there = run_cli("run --target " + torus + " --quad " +
                                   (scratch / "t" / "model" / "quads.obj").string() + " --size " +
                                   at + " --out " + (scratch / "u").string(),
                               scratch);
  ASSERT_EQ(there.exit_code, 0) << there.err;
  const auto fitted = read_report(scratch / "u");
  EXPECT_EQ(fitted["resolve"]["critical_after"].get<int>(), 0);
  EXPECT_EQ(fitted["resolve"]["narrow_after"].get<int>(), 0);
  EXPECT_TRUE(test::audit_sheets(scratch / "u" / "cut").clean());
}

// The parts \p resolve (a report's "resolve") left out: each within two 3 mm sheets of the
// parts kept, and beyond one only where it fell apart at its slots or is inside out (a part its
// joints left nothing of goes wherever it is). Returns how many fell apart and lie beyond one
// sheet (with \p also in their reason, where given).
int omitted_beyond_a_sheet_that_fell_apart(const nlohmann::json& resolve,
                                           const std::string& also = "") {
  int apart = 0;
  for (const auto& c : resolve["changes"]) {
    if (c["action"] != "omit") continue;
    const std::string why = c["reason"].get<std::string>();
    if (why.find("nothing of it was left") != std::string::npos) continue;
    const double distance = c["local_distance_mm"].get<double>();
    EXPECT_LE(distance, 2 * 3.0) << why;
    if (distance <= 3.0) continue;
    const bool fell = why.find("fell apart at its slots") != std::string::npos;
    EXPECT_TRUE(fell || why.find("inside out") != std::string::npos) << why;
    apart += fell && why.find(also) != std::string::npos;
  }
  return apart;
}

// Parts that flatten distorted are no matter of size: their quads' angles are the same at
// every scale. Fertility from its triangles at 250 mm leaves four parts unresolved, two of them
// facets flattening 44 deg off and with an inverted quad; its warning named --size 336 for all
// four, and run there with its quads passed back the twisted facet was still 36 deg off. The
// size is now named for the parts too small alone, the distorted ones are counted apart
// (resolve.distorted_parts_after) with no size factor, and the warning says no size cures them.
// Since 2026-12-05 (fertility's quads 4 round its arms) the one part left too small was a part
// 10.5 mm across where the statue is thin, cut back 1.8 mm by the mitre beside a facet folded
// onto the other side: it fell apart at its slots, its largest piece alone was cut, and its
// border where it broke had no joint, the one such border on the shared meshes at 250 mm (the
// size named, 758 mm, held it). Its surface lies within 4.1 mm of the parts kept, less than two
// sheets: a part that fell apart is now left out where the parts kept stand within two sheets
// of it (one, where it is only folded back or a sliver), and no border is left without a joint,
// nothing falls apart, and the sheets are clean. (The part folded back beside it, fallen apart
// too and 4.0 mm from the parts kept, is left out first; after it no part is left too small.)
TEST(Cli, DistortedPartsAreNotPromisedASize) {
  KERFAB_SKIP_WITHOUT_SHARED_MESHES();
  const fs::path scratch = test::fresh_dir();
  const CliRun r = run_cli("run --target " + (test::shared_meshes() / "fertility.off").string() +
                               " --size 250 --out " + (scratch / "f").string(),
                           scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_report(scratch / "f");
  const auto& res = report["resolve"];
  int distorted = 0, small = 0;
  const int apart = omitted_beyond_a_sheet_that_fell_apart(res);
  for (const auto& c : res["changes"]) {
    if (c["action"] != "unresolved") continue;
    const std::string why = c["reason"].get<std::string>();
    if (why.find(" flattens ") != std::string::npos) {
      ++distorted;
      EXPECT_EQ(c["size_factor"].get<double>(), 0.0) << why;
    } else {
      ++small;
    }
  }
  ASSERT_GE(distorted, 1);
  EXPECT_EQ(res["distorted_parts_after"].get<int>(), distorted);
  EXPECT_EQ(res["small_parts_after"].get<int>(), distorted + small);
  EXPECT_NE(r.err.find(std::to_string(distorted) + " parts flatten distorted"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("which no --size cures"), std::string::npos) << r.err;
  EXPECT_EQ(small, 0);
  EXPECT_EQ(res["small_parts_min_size_mm"].get<double>(), 0.0);  // no size is promised
  EXPECT_EQ(r.err.find("would hold at --size"), std::string::npos) << r.err;
  EXPECT_GE(apart, 1);
  EXPECT_NE(r.err.find("that fell apart at their slots where the shape is thinner than two "
                       "sheets"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(report["joints"]["borders_without_joint"].get<int>(), 0);
  EXPECT_EQ(report["joints"]["lost_area_mm2"].get<double>(), 0.0);
  expect_all_placed_and_clean(report, scratch / "f");
  // At 200 mm a part folded back 177 deg that fell apart is left out 4.8 mm from the parts
  // kept (with one sheet's reach it was kept: 301 parts against 300).
  const CliRun at200 =
      run_cli("run --target " + (test::shared_meshes() / "fertility.off").string() +
                  " --size 200 --out " + (scratch / "g").string(),
              scratch);
  ASSERT_EQ(at200.exit_code, 0) << at200.err;
  const auto smaller = read_report(scratch / "g");
  EXPECT_GE(omitted_beyond_a_sheet_that_fell_apart(smaller["resolve"], "folded back"), 1);
  EXPECT_TRUE(test::audit_sheets(scratch / "g" / "cut").clean());
}

// Kerf options that leave no room for the cuts a bend needs are named. A ring of radius 44 mm,
// 30 mm high, bends in one strip: 57 cuts at the defaults. --bridge 30 leaves none of them room
// (30 mm less two 1 mm margins and a 30 mm bridge), and the resolve stage then cut the ring as
// 24 flat facets with only "1 regions were changed" to say why; the cuts the options took are
// now counted against the defaults (kerf.skipped_by_options) and the options named with them.
TEST(Cli, KerfOptionsThatLeaveNoRoomForCutsAreNamed) {
  const fs::path scratch = test::fresh_dir();
  const fs::path ring = scratch / "ring.obj";
  write_mesh(test::open_cylinder(44, 30, 24, 3, 1).quads, ring);
  const std::string run = "run --target " + ring.string() + " --out ";
  const CliRun plain = run_cli(run + (scratch / "d").string(), scratch);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto defaults = read_report(scratch / "d");
  const int planned = defaults["kerf"]["cuts"].get<int>();
  ASSERT_GT(planned, 20);
  EXPECT_EQ(defaults["kerf"]["skipped_cuts"], 0);
  EXPECT_EQ(defaults["kerf"]["skipped_by_options"], 0);
  EXPECT_EQ(plain.err.find("found no room"), std::string::npos) << plain.err;
  const std::string named = " of the " + std::to_string(planned) +
                            " kerf cuts the bends asked for found no room in their parts with "
                            "--bridge 30 mm (default 2) but would with the defaults";
  // As built: every cut the bend asked for is left out, each for the options alone.
  const CliRun kept =
      run_cli(run + (scratch / "k").string() + " --bridge 30 --no-resolve", scratch);
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  const auto bare = read_report(scratch / "k");
  EXPECT_EQ(bare["kerf"]["cuts"], 0);
  EXPECT_EQ(bare["kerf"]["skipped_cuts"].get<int>(), planned);
  EXPECT_EQ(bare["kerf"]["skipped_by_options"].get<int>(), planned);
  EXPECT_NE(kept.err.find(std::to_string(planned) + named), std::string::npos) << kept.err;
  // Resolved into flat facets, the warning of the first build is kept.
  const CliRun resolved = run_cli(run + (scratch / "r").string() + " --bridge 30", scratch);
  ASSERT_EQ(resolved.exit_code, 0) << resolved.err;
  EXPECT_NE(resolved.err.find("at first, " + std::to_string(planned) + named), std::string::npos)
      << resolved.err;
  // A margin that takes the room does the same; the shape alone takes none at the defaults.
  const CliRun margin =
      run_cli(run + (scratch / "m").string() + " --kerf-margin 14 --no-resolve", scratch);
  ASSERT_EQ(margin.exit_code, 0) << margin.err;
  EXPECT_EQ(read_report(scratch / "m")["kerf"]["skipped_by_options"].get<int>(), planned);
  EXPECT_NE(margin.err.find("--kerf-margin 14 mm (default 1)"), std::string::npos) << margin.err;
}

// Issue 14, item 3: a part that its joints cut away is reported with the size at which it would
// hold, and that size is checked by running there. A thin wedge 60 mm long, its faces opening
// 4 degrees from an edge 0.6 mm wide to a back 1.6 mm wide, 14 mm deep, as its own quad mesh:
// at 60 mm its narrow faces are cut back from both sides by more than they are wide. The size
// the run names (stderr and resolve.small_parts_min_size_mm), 2 % larger, leaves no part too
// small or narrow on the sheets, read back by the independent auditor, and none missing. Its
// narrow faces are 0.6-1.6 mm across: with the default --min-part-width (3 mm) they are slivers
// the run leaves out (below); here a maker who handles 1 mm parts keeps them.
TEST(Cli, APartCutAwayByItsJointsNamesTheSizeAtWhichItHolds) {
  const fs::path scratch = test::fresh_dir();
  const fs::path wedge = scratch / "wedge.obj";
  {
    const double length = 60, deep = 14, edge = 0.6, opening = std::tan(2 * M_PI / 180);
    const std::array<std::array<double, 2>, 4> section = {{{-edge / 2, 0},
                                                           {edge / 2, 0},
                                                           {edge / 2 + deep * opening, deep},
                                                           {-edge / 2 - deep * opening, deep}}};
    std::ofstream f(wedge);
    const int n = 4;
    for (int i = 0; i <= n; ++i)
      for (const auto& [z, y] : section)
        f << "v " << length * i / n << " " << y << " " << z << "\n";
    auto at = [](int i, int k) { return 4 * i + k + 1; };
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 4; ++k)
        f << "f " << at(i, k) << " " << at(i + 1, k) << " " << at(i + 1, (k + 1) % 4) << " "
          << at(i, (k + 1) % 4) << "\n";
    f << "f " << at(0, 0) << " " << at(0, 1) << " " << at(0, 2) << " " << at(0, 3) << "\n";
    f << "f " << at(n, 3) << " " << at(n, 2) << " " << at(n, 1) << " " << at(n, 0) << "\n";
  }
  // The default: the slivers are left out, the sheets are clean and nothing is missing.
  const CliRun left = run_cli(
      "run --target " + wedge.string() + " --size 60 --out " + (scratch / "d").string(), scratch);
  ASSERT_EQ(left.exit_code, 0) << left.err;
  EXPECT_NE(left.err.find("parts were left out"), std::string::npos) << left.err;
  {
    const auto report = read_report(scratch / "d");
    int omitted = 0;
    for (const auto& c : report["resolve"]["changes"]) {
      EXPECT_NE(c["action"], "unresolved") << c;
      if (c["action"] != "omit") continue;
      ++omitted;
      EXPECT_NE(c["reason"].get<std::string>().find("a sliver"), std::string::npos) << c;
      EXPECT_LE(c["local_distance_mm"].get<double>(), 3.0) << c;  // within a sheet's thickness
    }
    EXPECT_GE(omitted, 2);
    EXPECT_EQ(report["resolve"]["small_parts_after"], 0);
    EXPECT_EQ(report["joints"]["repaired_parts"], 0);
    EXPECT_TRUE(report["layout"]["empty"].empty()) << report["layout"]["empty"];
    EXPECT_TRUE(report["layout"]["unplaced"].empty()) << report["layout"]["unplaced"];
    const auto audit = test::audit_sheets(scratch / "d" / "cut");
    EXPECT_EQ(audit.small_parts + audit.narrow_parts + audit.thin_features, 0);
    EXPECT_EQ(audit.parts, report["resolve"]["parts_after"].get<int>());
  }
  const std::string width = " --min-part-width 1";
  const CliRun small = run_cli(
      "run --target " + wedge.string() + width + " --size 60 --out " + (scratch / "a").string(),
      scratch);
  ASSERT_EQ(small.exit_code, 0) << small.err;
  const auto report = read_report(scratch / "a");
  const double size = report["resolve"]["small_parts_min_size_mm"].get<double>();
  ASSERT_GT(size, 60.0);
  // The faces their joints cut away entirely are missing from the sheets either way: they are
  // left out, so their neighbours are neither cut back for them nor left with borders that
  // have no joint, and the run names the size that keeps them.
  const std::string at_size = std::to_string(static_cast<int>(std::ceil(size)));
  EXPECT_NE(small.err.find("nothing left once their joints were cut, which --size " + at_size +
                           " would keep"),
            std::string::npos)
      << small.err;
  int cut_away = 0;
  for (const auto& c : report["resolve"]["changes"]) {
    if (c["action"] != "omit" && c["action"] != "unresolved") continue;
    ++cut_away;
    EXPECT_GT(c["size_factor"].get<double>(), 1.0);
    EXPECT_LE(c["size_factor"].get<double>() * 60, size + 1e-6);
    EXPECT_NE(c["reason"].get<std::string>().find("cut it back up to"), std::string::npos)
        << c["reason"];
  }
  EXPECT_GT(cut_away, 0);
  EXPECT_EQ(report["resolve"]["gone_parts"].get<int>(), cut_away);
  EXPECT_NEAR(report["resolve"]["gone_parts_min_size_mm"].get<double>(), size, 1e-6);
  EXPECT_EQ(report["joints"]["borders_without_joint"], 0);  // 12 of 17 when they were kept
  EXPECT_TRUE(report["layout"]["empty"].empty()) << report["layout"]["empty"];
  const int at = static_cast<int>(std::ceil(1.02 * size));
  const CliRun large = run_cli("run --target " + wedge.string() + width + " --size " +
                                   std::to_string(at) + " --out " + (scratch / "b").string(),
                               scratch);
  ASSERT_EQ(large.exit_code, 0) << large.err;
  const auto there = read_report(scratch / "b");
  EXPECT_EQ(there["resolve"]["small_parts_after"], 0);
  EXPECT_TRUE(there["layout"]["unplaced"].empty()) << there["layout"]["unplaced"];
  test::AuditLimits limits;
  limits.min_part_width = 1;  // what this maker handles
  const auto audit = test::audit_sheets(scratch / "b" / "cut", limits);
  EXPECT_EQ(audit.small_parts, 0);
  EXPECT_EQ(audit.narrow_parts, 0);
  EXPECT_EQ(audit.parts, there["resolve"]["parts_after"].get<int>());
}

}  // namespace
}  // namespace kerfab

namespace kerfab {
namespace {

// Issue 18, sheets saved: Spot (control mesh, one Catmull-Clark step) at 500 mm on the default
// 600 x 450 mm sheets. Its long strips leave gaps no other part fills, and nested whole they need
// 4 sheets (the last about 4 % used), two over the area bound. Split at their middle rulings,
// the parts fit 3, the spaced bound; everything else the same: no critical region, no part too
// small, no border without a joint more, the sheets read back clean by the auditor, and the
// parts' area on the sheets within 1 % of the whole strips' (a split costs only its joint).
TEST(Cli, LongStripsAreSplitWhereThatSavesASheet) {
  const std::string args = "--target " + test::real_mesh("spot_triangulated.obj").string() +
                           " --quad " + test::real_mesh("spot_control_mesh.obj").string() +
                           " --subdivide 1 --size 500";
  const fs::path whole_out = test::fresh_dir() / "whole", split_out = test::fresh_dir() / "split";
  const auto whole = run_quietly(args + " --keep-strips-whole", whole_out);
  const auto split = run_quietly(args, split_out);
  ASSERT_FALSE(whole.is_null());
  ASSERT_FALSE(split.is_null());
  const auto& s = split["layout"]["split_to_fit"];
  EXPECT_EQ(whole["layout"]["sheets"].get<int>(), 4);
  EXPECT_FALSE(whole["layout"]["split_to_fit"]["tried"].get<bool>());
  EXPECT_EQ(split["layout"]["sheets"].get<int>(), 3);
  EXPECT_LE(split["layout"]["sheets"].get<int>(),
            split["layout"]["sheets_lower_bound"].get<int>() + 1);
  EXPECT_EQ(s["sheets_before"].get<int>(), 4);
  EXPECT_EQ(s["sheets_after"].get<int>(), 3);
  EXPECT_EQ(s["saved_sheets"].get<int>(), 1);
  // The attempt that saves the sheet is built: the screen before it (halves_in_plane) lets it
  // through.
  EXPECT_EQ(s["screened"].get<int>(), 0);
  EXPECT_EQ(s["attempts"].get<int>(), 1);
  const int parts = static_cast<int>(split["layout"]["parts"].size());
  EXPECT_EQ(s["parts_before"].get<int>(), static_cast<int>(whole["layout"]["parts"].size()));
  EXPECT_EQ(s["parts_after"].get<int>(), parts);
  // Each split makes at most one part more (a strip the flattening split already may be cut
  // where it was).
  EXPECT_GT(parts, s["parts_before"].get<int>());
  EXPECT_LE(parts, s["parts_before"].get<int>() + s["strips_split"].get<int>());
  for (const auto* r : {&whole, &split}) {
    EXPECT_EQ((*r)["kerf"]["critical_regions"].get<int>(), 0);
    EXPECT_EQ((*r)["resolve"]["small_parts_after"].get<int>(), 0);
  }
  EXPECT_LE(split["joints"]["borders_without_joint"].get<int>(),
            whole["joints"]["borders_without_joint"].get<int>());
  EXPECT_EQ(split["flatten"]["patches"].size(), static_cast<std::size_t>(parts));
  EXPECT_EQ(split["joints"]["repaired_parts"].get<int>(), 0);
  // From outside: the written sheets.
  double area[2] = {0, 0};
  int k = 0;
  for (const fs::path& out : {whole_out, split_out}) {
    const auto audit = test::audit_sheets(out / "cut");
    EXPECT_TRUE(audit.clean()) << out << ": " << (audit.findings.empty() ? "" : audit.findings[0]);
    EXPECT_EQ(audit.sheets, k == 0 ? 4 : 3);
    EXPECT_EQ(audit.parts, k == 0 ? static_cast<int>(whole["layout"]["parts"].size()) : parts);
    for (const test::SheetPart& p : test::read_sheet_parts(out / "cut"))
      area[k] += std::abs(polygon_area(p.outline));
    ++k;
  }
  EXPECT_NEAR(area[1], area[0], 0.01 * area[0]);
  // The surface is the same: the strips split, not moved.
  EXPECT_NEAR(split["quality"]["hausdorff_rel"].get<double>(),
              whole["quality"]["hausdorff_rel"].get<double>(), 1e-3);
}

}  // namespace
}  // namespace kerfab

// Reproduces the paper's Table 1 trend and the ruling-count sweep for issue 4: on spot
// (control mesh + 1 Catmull-Clark step, 250 mm) and fandisk_quads (200 mm), prints markdown
// tables of alignment c against aligned fraction, strips, Hausdorff and mean distance, and of
// the rulings per quad / max ruling spacing against quality and sub-quad count.
// Usage: kerfab_strips_tables [--quick]   (--quick: spot only, fewer rows)
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "kerfab/eval/surface_distance.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "kerfab/strips/strips.h"
#include "mesh_path.h"

namespace {

using namespace kerfab;

struct Model {
  std::string name;
  PreparedInput input;
};

Model load(const std::string& name, const std::string& target, const std::string& quad,
           int subdivide, double size) {
  InputOptions in;
  in.subdivide = subdivide;
  in.size = size;
  std::optional<PolyMesh> q;
  if (!quad.empty()) q = read_mesh(bench::mesh_path(quad));
  return {name, prepare_input(read_mesh(bench::mesh_path(target)), q, in)};
}

SurfaceDistance quality(const Model& m, const Strips& s) {
  const double diag = bounding_box(m.input.surface.mesh()).diagonal();
  return surface_distance(triangulate(s), m.input.surface.mesh(), {.sample_spacing = 0.002 * diag});
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::vector<Model> models;
  models.push_back(load("spot", "spot_triangulated.obj", "spot_control_mesh.obj", 1, 250));
  if (!quick) models.push_back(load("fandisk_quads", "fandisk_quads.off", "", 0, 200));
  for (const Model& m : models) {
    const double diag = bounding_box(m.input.surface.mesh()).diagonal();
    std::printf(
        "\n### %s: %zu quads, %d quad rows, naive row layout %d strips, diagonal %.1f mm\n\n",
        m.name.c_str(), m.input.quads.n_faces(), quad_rows(m.input.quads),
        static_cast<int>(
            build_strips(m.input.quads, naive_row_bending(m.input.quads), m.input.surface, {})
                .patches.size()),
        diag);
    std::printf("| c | aligned | strips | Hausdorff %% | mean %% | ILP status | ILP s |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    const std::vector<double> cs =
        quick ? std::vector<double>{0.0, 0.3} : std::vector<double>{0.0, 0.1, 0.3, 0.5, 0.9};
    std::optional<BendingResult> default_bending;
    for (double c : cs) {
      BendingOptions b;
      b.alignment = c;
      const BendingResult r = choose_bending_edges(m.input.quads, m.input.surface, b);
      const Strips s = build_strips(m.input.quads, r, m.input.surface, {});
      const SurfaceDistance d = quality(m, s);
      std::printf("| %.1f | %.3f | %zu | %.3f | %.4f | %s | %.2f |\n", c, r.aligned_fraction,
                  s.patches.size(), 100 * d.hausdorff / diag, 100 * d.mean / diag,
                  to_string(r.status).c_str(), r.solve_seconds);
      std::fflush(stdout);
      if (c == 0.3) default_bending = r;
    }
    std::printf("\n| rulings/quad | max spacing mm | sub-quads | Hausdorff %% | mean %% | s |\n");
    std::printf("|---|---|---|---|---|---|\n");
    struct Row {
      int k;
      double spacing;
    };
    std::vector<Row> rows = {{1, 1e9}, {2, 1e9}, {3, 1e9}, {4, 1e9}, {6, 1e9}, {8, 1e9},
                             {1, 10},  {1, 5},   {1, 3},   {4, 5},   {4, 3}};
    if (quick) rows = {{1, 1e9}, {4, 1e9}, {4, 5}};
    for (const Row& row : rows) {
      StripsOptions o;
      o.rulings_per_quad = row.k;
      o.max_ruling_spacing = row.spacing;
      const auto t0 = std::chrono::steady_clock::now();
      const Strips s = build_strips(m.input.quads, *default_bending, m.input.surface, o);
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const SurfaceDistance d = quality(m, s);
      std::printf("| %d | %s | %zu | %.3f | %.4f | %.3f |\n", row.k,
                  row.spacing > 1e8 ? "-" : std::to_string(static_cast<int>(row.spacing)).c_str(),
                  s.faces.size(), 100 * d.hausdorff / diag, 100 * d.mean / diag, secs);
      std::fflush(stdout);
    }
  }
}

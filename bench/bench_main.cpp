// Benchmarks: closest-point queries and the bending integer program on real meshes.
// Run: build/bench/kerfab_bench  (speed targets live here, never in unit tests)
#include <benchmark/benchmark.h>

#include "kerfab/bending/bending.h"
#include "kerfab/flatten/flatten.h"
#include "kerfab/input/prepare.h"
#include "kerfab/io/mesh_io.h"
#include "mesh_path.h"

namespace {

using kerfab::bench::mesh_path;

kerfab::PreparedInput load(const std::string& target, const std::string& quad, int subdivide) {
  kerfab::InputOptions opt;
  opt.size = 250.0;
  opt.subdivide = subdivide;
  return kerfab::prepare_input(kerfab::read_mesh(mesh_path(target)),
                               kerfab::read_mesh(mesh_path(quad)), opt);
}

bool available(benchmark::State& state, const std::string& target, const std::string& quad) {
  if (!mesh_path(target).empty() && !mesh_path(quad).empty()) return true;
  state.SkipWithError("mesh not found (optional ../shared/data/meshes absent)");
  return false;
}

void BM_ClosestPoint(benchmark::State& state) {
  const auto in = load("spot_triangulated.obj", "spot_quadrangulated.obj", 0);
  std::size_t i = 0;
  const auto& verts = in.surface.mesh().vertices;
  for (auto _ : state) {
    const kerfab::Vec3 q = verts[i % verts.size()] + kerfab::Vec3(1.0, -2.0, 0.5);
    benchmark::DoNotOptimize(in.surface.closest(q));
    ++i;
  }
}
BENCHMARK(BM_ClosestPoint);

void BM_Bending(benchmark::State& state, const char* target, const char* quad, int subdivide) {
  if (!available(state, target, quad)) return;
  const auto in = load(target, quad, subdivide);
  for (auto _ : state) {
    const auto r = kerfab::choose_bending_edges(in.quads, in.surface, {});
    state.counters["ilp_s"] = r.solve_seconds;
    state.counters["optimal"] = r.status == kerfab::PackingStatus::kOptimal ? 1 : 0;
    state.counters["quads"] = static_cast<double>(in.quads.n_faces());
  }
}
BENCHMARK_CAPTURE(BM_Bending, spot_cc1, "spot_triangulated.obj", "spot_control_mesh.obj", 1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Bending, spot_quadrangulated, "spot_triangulated.obj",
                  "spot_quadrangulated.obj", 0)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Bending, inspired_conjugate, "inspired_mesh.obj",
                  "inspired_mesh_quads_Conjugate.off", 0)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Bending, fandisk_quads, "fandisk.obj", "fandisk_quads.off", 0)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// Flattening every patch of spot (control mesh + 1 Catmull-Clark step, 250 mm) at default
// settings; arg 0: Eq. 2 only, arg 1: also the 3D deformation to the flat metric.
void BM_FlattenSpot(benchmark::State& state) {
  const auto in = load("spot_triangulated.obj", "spot_control_mesh.obj", 1);
  const auto bending = kerfab::choose_bending_edges(in.quads, in.surface, {});
  const auto strips = kerfab::build_strips(in.quads, bending, in.surface, {});
  kerfab::FlattenOptions opt;
  opt.mimic_3d = state.range(0) != 0;
  opt.threads = 1;
  for (auto _ : state) {
    const auto flat = kerfab::flatten_patches(strips, opt);
    state.counters["patches"] = static_cast<double>(flat.patches.size());
    state.counters["unconverged"] = flat.unconverged;
  }
}
BENCHMARK(BM_FlattenSpot)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

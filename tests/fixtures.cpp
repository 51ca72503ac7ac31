#include "fixtures.h"

#include <stdexcept>

#include "kerfab/io/mesh_io.h"
#include "test_util.h"

namespace kerfab::test {

BendingOptions force_bendable(const PolyMesh& quads,
                              const std::function<bool(const Vec3&, const Vec3&)>& pick) {
  BendingOptions options;
  for (auto e : quads.edges()) {
    const auto h = quads.halfedge_handle(e, 0);
    const auto a = quads.from_vertex_handle(h), b = quads.to_vertex_handle(h);
    if (pick(to_eigen(quads.point(a)), to_eigen(quads.point(b))))
      options.guidance.push_back({a.idx(), b.idx(), true});
  }
  return options;
}

std::vector<Shape> end_to_end_shapes() {
  std::vector<Shape> shapes;
  shapes.push_back(quad_plane(150, 6));
  shapes.push_back(open_cylinder(40, 80, 12, 3));
  shapes.push_back(closed_cylinder(40, 80, 3));
  shapes.push_back(sphere(60, 3));
  shapes.push_back(torus(70, 25, 16, 8));
  return shapes;
}

RunResult run_shape(const Shape& shape, const PipelineOptions& options,
                    const std::filesystem::path& dir) {
  PolyMesh target;
  for (const auto& v : shape.target.vertices) target.add_vertex(to_openmesh(v));
  for (const auto& t : shape.target.triangles)
    target.add_face(
        {target.vertex_handle(t[0]), target.vertex_handle(t[1]), target.vertex_handle(t[2])});
  std::filesystem::create_directories(dir);
  write_mesh(target, dir / "target.obj");
  write_mesh(shape.quads, dir / "quads.obj");
  return run_pipeline({.target = dir / "target.obj", .quad = dir / "quads.obj"}, options, {});
}

RealModel spot() { return {"spot_triangulated.obj", "spot_control_mesh.obj", 1, 250}; }
RealModel fandisk() { return {"fandisk_quads.off", "", 0, 200}; }

PreparedInput load(const RealModel& model) {
  InputOptions in;
  in.subdivide = model.subdivide;
  if (model.size > 0) in.size = model.size;
  std::optional<PolyMesh> quad;
  if (!model.quad.empty()) quad = read_mesh(real_mesh(model.quad));
  return prepare_input(read_mesh(real_mesh(model.target)), quad, in);
}

Strips real_strips(const PreparedInput& model) {
  BendingOptions bending;
  bending.time_limit_s = 300;
  const BendingResult chosen = choose_bending_edges(model.quads, model.surface, bending);
  if (chosen.status != PackingStatus::kOptimal)
    throw std::runtime_error("the test model's bending program was not proven optimal (" +
                             to_string(chosen.status) +
                             "): its strips would depend on the machine's speed");
  return build_strips(model.quads, chosen, model.surface, {});
}

}  // namespace kerfab::test

#include "fixtures.h"

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
  bending.time_limit_s = 10;
  return build_strips(model.quads, choose_bending_edges(model.quads, model.surface, bending),
                      model.surface, {});
}

}  // namespace kerfab::test

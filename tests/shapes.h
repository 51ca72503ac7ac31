#pragma once
// Test shapes generated in code, each with a coarse quad mesh on the surface, a fine
// triangulation of the same surface as target, and the exact analytic signed distance.
#include <array>
#include <filesystem>
#include <functional>
#include <string>

#include "kerfab/core/mesh.h"

namespace kerfab::test {

struct Shape {
  std::string name;
  PolyMesh quads;       ///< coarse all-quad mesh, vertices on the surface [mm]
  TriangleMesh target;  ///< fine triangulation of the same surface [mm]
  std::function<double(const Vec3&)> signed_distance;  ///< analytic, positive outside [mm]
};

/// Square [0, size]^2 in the plane z = 0, n x n quads, normal +z. Open.
Shape quad_plane(double size, int n, int target_refine = 4);

/// Open cylinder (ring) of radius r around the z axis, z in [0, height]; `around` quads around
/// the axis, `along` quads along it. Outward normals.
Shape open_cylinder(double r, double height, int around, int along, int target_refine = 8);

/// Closed cylinder (caps included) of radius r, z in [-height/2, height/2], all quads
/// (a cube grid mapped onto the cylinder), n cells per cube side.
Shape closed_cylinder(double r, double height, int n, int target_refine = 8);

/// Sphere of radius r about the origin from a cube grid with n cells per side.
Shape sphere(double r, int n, int target_refine = 8);

/// Torus around the z axis, major radius R, minor r; nu x nv quads.
Shape torus(double R, double r, int nu, int nv, int target_refine = 6);

/// A drum: the circle of radius r in n segments about the z axis swept from z = 0 to height,
/// its top circle draft_deg narrower (a taper), closed by fans where asked (an extrusion,
/// src/kerfab/quads/sweep.h, unless tapered or open at both ends). Outward normals.
TriangleMesh drum(double r, double height, int n, bool bottom = true, bool top = true,
                  double draft_deg = 0);

/// A surface of revolution about the z axis: a ring of radius profile[k][0] at height
/// profile[k][1] for each k, every ring in n segments at the same angles, neighbouring rings
/// joined by two triangles per segment, and fans over the first ring and the last where asked
/// (a loft, src/kerfab/quads/sweep.h). Outward normals for heights rising along the profile.
TriangleMesh lathe(const std::vector<std::array<double, 2>>& profile, int n, bool bottom = true,
                   bool top = true);

/// A vase's profile for lathe(): radius 60 + 25 sin(pi z / 200) mm over z = 0 to 200 mm, in
/// 20 facets of 10 mm height.
std::vector<std::array<double, 2>> vase_profile();

/// scripts/shapes.py's vase, triangle for triangle in its order: open at the top, a fan at the
/// bottom, r(z) = 50 + 25 sin(1.5 pi z / 200) + 10 cos(3 pi z / 200) mm in 40 rings of 64.
TriangleMesh scripts_vase();

/// scripts/shapes.py's cone, triangle for triangle in its order: base radius 80 mm, height 150
/// mm, its apex a point (a fan of 64), 30 rings of 64, its base disc a fan.
TriangleMesh scripts_cone();

/// scripts/shapes.py's grid(): an open square patch of n x n cells over [-extent, extent]^2 mm,
/// z = height(x, y), two triangles per cell, column by column (its saddle: 50, 80, (x^2 -
/// y^2)/200).
TriangleMesh height_grid(int n, double extent, const std::function<double(double, double)>& height);

/// scripts/shapes.py's terrain: height_grid(60, 100, 25 sin(x/30) cos(y/40) + 10 exp(-(x^2 +
/// y^2)/800)).
TriangleMesh scripts_terrain();

/// \p mesh as an OBJ file as scripts/shapes.py writes it (6 decimals): a run on it is a run on
/// the script's file.
void write_obj(const TriangleMesh& mesh, const std::filesystem::path& path);

/// A bench of C-shaped section: the ring between radii r_in and r_out from angle 0.3 to
/// 2 pi - 0.3 (its gap facing +x), swept from z = 0 to height, n segments per arc.
TriangleMesh c_bench(double r_in, double r_out, double height, int n);

/// The triangles of \p mesh as a polygon mesh (what prepare_input takes as a target).
PolyMesh poly_mesh(const TriangleMesh& mesh);

/// Quad mesh of a (u, v) grid with nu x nv cells in [0,1]^2, optionally periodic, mapped by f.
PolyMesh grid_mesh(int nu, int nv, bool periodic_u, bool periodic_v,
                   const std::function<Vec3(double, double)>& f);

/// Quad mesh of the surface of the cube [-1,1]^3 with n cells per side, mapped by f
/// (faces oriented away from the origin after mapping).
PolyMesh cube_grid_mesh(int n, const std::function<Vec3(const Vec3&)>& f);

/// The box [0, 100]^3 mm whose sides (bottom, top, front, back, left, right) are grids of
/// n[k] x n[k] quads with their own vertices along its edges (only its 8 corners shared): a
/// side cut differently from its neighbour leaves their common edge a crack, the
/// inner points of each lying on the other's edges (T-junctions) or, where both sides have
/// a point there, at the same point.
PolyMesh box_cut_differently(const std::array<int, 6>& n);

}  // namespace kerfab::test

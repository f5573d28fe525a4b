#pragma once
// Filling a closed triangle mesh with particles on a lattice: what the paper's mesh scenes and
// the meshes of a case file (box_case.hpp) share.
#include <cstdint>
#include <vector>

#include "io/obj_mesh.hpp"
#include "scenes/mesh_inside.hpp"

namespace sph {

// The paper's meshes are Y-up; the solver's gravity is along -z. Rotates y up to z up (when
// y_up), then scales the mesh to `height` along its up axis.
TriangleMesh z_up_scaled(const TriangleMesh& in, double height, bool y_up = true);

// The mesh moved by `shift` (its bounds too).
TriangleMesh translated(const TriangleMesh& in, const Vec3d& shift);

// The lattice points origin + dp * (i, j, k) inside the mesh, over the mesh's bounding box:
// point (i, j, k) of the fill is at `first` + dp * (i, j, k), flagged at (i*n[1] + j)*n[2] + k.
struct MeshFill {
    Vec3d first;
    long first_index[3] = {0, 0, 0};  // lattice index of `first` from the origin
    int n[3] = {0, 0, 0};
    std::vector<std::uint8_t> inside;
    long long count = 0;
};
MeshFill fill_mesh(const TriangleMesh& mesh, const MeshInsideTest& test, double dp, const Vec3d& origin);

}  // namespace sph

#pragma once
// Inside/outside classification of points against a closed (or nearly closed) triangle mesh,
// used to fill a mesh with particles on a regular lattice.
#include <array>
#include <cstdint>
#include <vector>

#include "io/obj_mesh.hpp"

namespace sph {

// Parity of ray crossings along the three coordinate axes, combined by majority vote: a ray
// that slips through a small hole gets the wrong parity and is outvoted by the other two.
// Rays through a shared edge or vertex are counted once (exactly antisymmetric edge tests with
// a symbolic perturbation of the ray), so lattice lines through mesh vertices are safe.
// The object keeps its own copy of the geometry; all queries are const and thread-safe.
class MeshInsideTest {
public:
    explicit MeshInsideTest(const TriangleMesh& mesh);

    // True when p is inside by at least two of the three axis rays.
    bool contains(Vec3d p) const;

    // One flag (0/1) per lattice point origin + spacing*(ix, iy, iz), stored at
    // (ix*ny + iy)*nz + iz (z fastest). Whole lattice lines are classified at once.
    std::vector<uint8_t> lattice_inside(Vec3d origin, double spacing, int nx, int ny, int nz) const;

private:
    // Triangles projected along axis `a` onto (u, v) = ((a+1)%3, (a+2)%3), binned by their
    // projected bounding boxes into a uniform 2D grid (compressed rows: start/items).
    struct AxisGrid {
        double lo_u = 0, lo_v = 0, hi_u = -1, hi_v = -1;  // projected bounds (empty: hi < lo)
        double inv_u = 0, inv_v = 0;                      // bins per unit length
        int nu = 1, nv = 1;
        std::vector<int> start;  // nu*nv + 1 offsets into items
        std::vector<int> items;  // triangle indices
    };

    // Coordinates along the ray (axis a, through (pu, pv)) where it crosses the mesh, unsorted.
    void crossings(int a, double pu, double pv, std::vector<double>& out) const;

    std::vector<std::array<double, 9>> tri_;  // x0 y0 z0 x1 y1 z1 x2 y2 z2
    std::array<AxisGrid, 3> grid_;
};

}  // namespace sph

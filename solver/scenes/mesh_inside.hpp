#pragma once
// Inside/outside classification of points against a closed (or nearly closed) triangle mesh,
// used to fill a mesh with particles on a regular lattice.
#include <array>
#include <cstdint>
#include <vector>

#include "io/obj_mesh.hpp"
#include "scenes/winding_number.hpp"

namespace sph {

// Parity of ray crossings along the three coordinate axes. Where the mesh is closed the three
// agree; a hole shows itself as a line with an odd number of crossings, whose parity is then
// wrong for every point beyond it, and a majority of three rays rescues only points with one
// bad ray. So a point whose rays disagree, or that lies on a line with an odd count, is inside
// only when its generalised winding number (winding_number.hpp) is above 1/2 and the rays of
// its even lines do not say outside by a majority. The winding number alone would fill the
// space between two holes that face each other (across a tunnel), and the even lines alone
// are fooled by a line through two holes; both are needed for water. A closed mesh has no
// disputed points and is classified by the rays alone, as before.
class MeshInsideTest {
public:
    explicit MeshInsideTest(const TriangleMesh& mesh);

    // True when all three axis rays find p inside on lines with even crossing counts; for a
    // disputed point, by the rule above.
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

    // The winding number with the mesh's orientation taken out (inward-facing meshes read 1
    // inside too): what decides a disputed point.
    bool inside_by_winding(Vec3d p) const;
    // `rays`: bit a set when axis a's ray found p inside, bit 3 + a when its line was odd.
    bool decide(unsigned rays, Vec3d p) const;

    std::vector<std::array<double, 9>> tri_;  // x0 y0 z0 x1 y1 z1 x2 y2 z2
    std::array<AxisGrid, 3> grid_;
    WindingNumber winding_;
    double orientation_ = 1;  // -1 for a mesh whose triangles face inwards
};

}  // namespace sph

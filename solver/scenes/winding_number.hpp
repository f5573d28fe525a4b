#pragma once
// Generalised winding number of a triangle soup (Jacobson et al. 2013): the solid angle the
// triangles subtend at a point, over 4 pi. 1 inside a closed outward-facing mesh, 0 outside,
// and near those values away from small holes, which is why the inside test asks it when the
// ray votes cannot be trusted. Far clusters of triangles are summed as one dipole (Barill et
// al. 2018, first order), near ones exactly, so a query costs about log(triangles).
#include <array>
#include <vector>

#include "io/obj_mesh.hpp"

namespace sph {

class WindingNumber {
public:
    // Triangles as x0 y0 z0 x1 y1 z1 x2 y2 z2.
    explicit WindingNumber(std::vector<std::array<double, 9>> triangles);

    // Clusters farther than `accuracy` times their radius count as dipoles; accuracy <= 0 sums
    // every triangle exactly.
    double at(Vec3d p, double accuracy = 3.0) const;

private:
    struct Node {
        double c[3];      // area-weighted centre of its triangles
        double n[3];      // their summed vector area (area times unit normal)
        double r;         // radius around c that holds every vertex
        int first, count;  // leaf: its triangles in tri_[first, first + count)
        int left, right;   // children; -1 for a leaf
    };
    int build(int first, int count);

    std::vector<std::array<double, 9>> tri_;
    std::vector<Node> nodes_;
};

}  // namespace sph

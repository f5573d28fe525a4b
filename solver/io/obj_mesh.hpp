#pragma once
// Reading closed triangle meshes from Wavefront OBJ files (the fluid bodies of mesh scenes).
#include <array>
#include <string>
#include <vector>

namespace sph {

struct Vec3d {
    double x, y, z;
};

struct TriangleMesh {
    std::vector<Vec3d> vertices;
    std::vector<std::array<int, 3>> triangles;  // 0-based vertex indices
    Vec3d lo{}, hi{};                           // bounding box of the vertices used by triangles

    // Enclosed volume by the divergence theorem (sum of signed tetrahedra), as an absolute
    // value so that inward-facing meshes give the same number. Exact only for closed meshes.
    double volume() const;
};

// How strictly read_obj insists on a watertight surface.
//  RequireClosed:   every undirected edge must be shared by exactly 2 triangles.
//  AllowSmallHoles: at most 1% of the edges may be open (shared by 1 or by more than 2
//                   triangles); MeshInsideTest's three-axis majority vote copes with these.
enum class MeshCheck { RequireClosed, AllowSmallHoles };

// Reads `v x y z` and `f a b c ...` lines (indices as a, a/b, a/b/c or a//c; negative
// indices count back from the last vertex; polygons are fan-triangulated; triangles that
// repeat a vertex index are dropped). Other lines are ignored. Throws InputError naming the
// file for: an unreadable file, no triangles, a non-finite or malformed coordinate, a bad
// or out-of-range face index, open edges beyond what `check` allows, and a volume of ~0.
TriangleMesh read_obj(const std::string& path, MeshCheck check = MeshCheck::RequireClosed);

}  // namespace sph

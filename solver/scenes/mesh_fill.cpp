#include "scenes/mesh_fill.hpp"

#include <algorithm>
#include <cmath>

namespace sph {

static void reset_bounds(TriangleMesh& m) {
    m.lo = {1e300, 1e300, 1e300};
    m.hi = {-1e300, -1e300, -1e300};
    for (const auto& v : m.vertices) {
        m.lo = {std::min(m.lo.x, v.x), std::min(m.lo.y, v.y), std::min(m.lo.z, v.z)};
        m.hi = {std::max(m.hi.x, v.x), std::max(m.hi.y, v.y), std::max(m.hi.z, v.z)};
    }
}

TriangleMesh z_up_scaled(const TriangleMesh& in, double height, bool y_up) {
    TriangleMesh m = in;
    const double scale = height / (y_up ? in.hi.y - in.lo.y : in.hi.z - in.lo.z);
    for (auto& v : m.vertices) v = y_up ? Vec3d{v.x * scale, -v.z * scale, v.y * scale} : Vec3d{v.x * scale, v.y * scale, v.z * scale};
    reset_bounds(m);
    return m;
}

TriangleMesh translated(const TriangleMesh& in, const Vec3d& shift) {
    TriangleMesh m = in;
    for (auto& v : m.vertices) v = {v.x + shift.x, v.y + shift.y, v.z + shift.z};
    reset_bounds(m);
    return m;
}

MeshFill fill_mesh(const TriangleMesh& m, const MeshInsideTest& test, double dp, const Vec3d& origin) {
    MeshFill f;
    const double lo[3] = {m.lo.x - origin.x, m.lo.y - origin.y, m.lo.z - origin.z};
    const double hi[3] = {m.hi.x - origin.x, m.hi.y - origin.y, m.hi.z - origin.z};
    for (int a = 0; a < 3; ++a) {
        f.first_index[a] = long(std::floor(lo[a] / dp));
        f.n[a] = int(std::ceil(hi[a] / dp) - f.first_index[a]) + 1;
    }
    f.first = {origin.x + f.first_index[0] * dp, origin.y + f.first_index[1] * dp, origin.z + f.first_index[2] * dp};
    f.inside = test.lattice_inside(f.first, dp, f.n[0], f.n[1], f.n[2]);
    for (auto b : f.inside) f.count += b;
    return f;
}

}  // namespace sph

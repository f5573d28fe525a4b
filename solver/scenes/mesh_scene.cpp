// The paper's scenes: a closed mesh (the Stanford Armadillo or Bunny) filled with fluid on a
// lattice, standing a little above the floor of a closed box of boundary particles, falling
// and collapsing under gravity.
#include <cmath>

#include "core/error.hpp"
#include "io/obj_mesh.hpp"
#include "scenes/lattice.hpp"
#include "scenes/mesh_fill.hpp"

namespace sph {
namespace {

Scene make_mesh_scene(SceneOptions& opt, const std::string& name, const std::string& default_mesh) {
    Scene s;
    s.name = name;
    const std::string path = find_mesh(opt.text("mesh", default_mesh));
    const TriangleMesh mesh = z_up_scaled(read_obj(path, MeshCheck::AllowSmallHoles), opt.number("height", 1.0, 1e-3, 1e3));
    const MeshInsideTest test(mesh);
    const Vec3d lattice_origin{0, 0, 0};  // the fill and the box share one lattice
    const long long target = opt.integer("particles", 100000, 100, 2'000'000'000LL);
    if (opt.has("dp")) throw InputError("scene '" + name + "' takes 'particles', not 'dp'");
    s.dp = pick_spacing(std::cbrt(mesh.volume() / double(target)), target,
                        [&](double dp) { return fill_mesh(mesh, test, dp, lattice_origin).count; }, name);
    const MeshFill fill = fill_mesh(mesh, test, s.dp, lattice_origin);
    const double dp = s.dp;
    const double drop = opt.number("drop", 0.1, 0, 100) * (mesh.hi.z - mesh.lo.z);
    const double spread = opt.number("spread", 0.5, 0.05, 100);  // box = mesh footprint grown by this on each side
    const int layers = int(opt.integer("layers", 2, 1, 5));
    const double origin[3] = {0, 0, 0};
    const double ex = (mesh.hi.x - mesh.lo.x) * spread, ey = (mesh.hi.y - mesh.lo.y) * spread;
    LatticeBox box{{long(std::floor((mesh.lo.x - ex) / dp)), long(std::floor((mesh.lo.y - ey) / dp)),
                    long(std::floor((mesh.lo.z - drop) / dp)) - 1},
                   {long(std::ceil((mesh.hi.x + ex) / dp)), long(std::ceil((mesh.hi.y + ey) / dp)),
                    long(std::ceil((mesh.hi.z + 0.1 * (mesh.hi.z - mesh.lo.z)) / dp)) + 1}};
    add_box_boundary(s, origin, box, layers, false);
    s.n_boundary = s.size();
    s.bodies = {{"tank", 0, s.n_boundary}};  // the closed box
    for (int i = 0; i < fill.n[0]; ++i)
        for (int j = 0; j < fill.n[1]; ++j)
            for (int k = 0; k < fill.n[2]; ++k)
                if (fill.inside[(std::size_t(i) * fill.n[1] + j) * fill.n[2] + k]) {
                    s.position.push_back({fill.first.x + i * dp, fill.first.y + j * dp, fill.first.z + k * dp});
                    s.velocity.push_back({0, 0, 0});
                }
    const double g = opt.number("gravity", 9.81, 0, 1e3);
    const double fall = mesh.hi.z - box.lo[2] * dp;  // the highest water above the floor
    set_common_physics(s, opt, opt.number("c0_factor", 20, 1, 1000) * std::sqrt(g * fall), "wendland");
    const double m = (layers + 1) * dp;
    for (int a = 0; a < 3; ++a) {
        s.lo[a] = box.lo[a] * dp - m;
        s.hi[a] = box.hi[a] * dp + m;
    }
    opt.finish(name);
    s.settings = opt.resolved();
    s.settings["mesh_path"] = path;
    return s;
}

}  // namespace

Scene make_armadillo(SceneOptions& opt) { return make_mesh_scene(opt, "armadillo", "armadillo.obj"); }
Scene make_bunny(SceneOptions& opt) { return make_mesh_scene(opt, "bunny", "bunny.obj"); }

}  // namespace sph

#include "core/error.hpp"
#include "scenes/scene.hpp"

namespace sph {

Scene make_dsph_dambreak(SceneOptions&);
Scene make_dambreak(SceneOptions&);
Scene make_tank(SceneOptions&);
Scene make_armadillo(SceneOptions&);
Scene make_bunny(SceneOptions&);
Scene make_taylor_green(SceneOptions&);

const std::vector<SceneInfo>& scene_catalogue() {
    static const std::vector<SceneInfo> scenes = {
        {"armadillo", "the paper's armadillo: the Stanford Armadillo mesh filled with water, collapsing in a closed box",
         make_armadillo},
        {"bunny", "the paper's bunny: the Stanford Bunny mesh filled with water, collapsing in a closed box", make_bunny},
        {"dambreak", "a water column collapsing in an open tank (Martin and Moyce's geometry)", make_dambreak},
        {"dsph-dambreak", "DualSPHysics' example 01_DamBreak: tank, water column and obstacle, its parameters",
         make_dsph_dambreak},
        {"tank", "still water in an open tank, started hydrostatic", make_tank},
        {"taylor-green", "the decaying 2D Taylor-Green vortex in a periodic box (exact solution in time)",
         make_taylor_green},
    };
    return scenes;
}

Scene make_scene(const std::string& name, const std::map<std::string, std::string>& options) {
    for (const auto& info : scene_catalogue()) {
        if (info.name != name) continue;
        SceneOptions opt(options);
        Scene s = info.build(opt);
        if (s.fluid_count() == 0) throw InputError("scene '" + name + "' has no fluid particles");
        return s;
    }
    std::string known;
    for (const auto& info : scene_catalogue()) known += (known.empty() ? "" : ", ") + info.name;
    throw InputError("unknown scene '" + name + "' (known scenes: " + known + ")");
}

}  // namespace sph

#pragma once
// Initial conditions: a scene is particles (boundary first, then fluid), the physical
// parameters that go with them, and the domain box the grid covers.
#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/params.hpp"
#include "core/smoothing_kernels.hpp"

namespace sph {

// A named group of boundary particles (a tank, an obstacle): particles [first, first + count)
// of the scene, whose indices are the ids the particles keep through the run, so that a
// force gauge can sum over a body without a per-particle array on the device.
struct BoundaryBody {
    std::string name;
    std::size_t first = 0, count = 0;
};

struct Scene {
    std::string name;
    PhysicsParams params;
    KernelType kernel = KernelType::wendland;
    double dp = 0;                        // lattice spacing
    std::array<double, 3> lo{}, hi{};     // domain: particles leaving it are counted and dropped
    std::array<bool, 3> periodic{};       // per axis: [lo, hi) is one period, particles wrap around
    std::vector<std::array<double, 3>> position;
    std::vector<std::array<float, 3>> velocity;
    std::vector<float> density;           // empty: rho0 everywhere
    std::size_t n_boundary = 0;           // the first n_boundary particles are boundary
    std::vector<BoundaryBody> bodies;     // disjoint ranges of the boundary; may be empty
    double cfl = 0.2;                     // the scene's default CFL number
    std::map<std::string, std::string> settings;  // every option as resolved, for provenance

    std::size_t size() const { return position.size(); }
    std::size_t fluid_count() const { return size() - n_boundary; }
    const BoundaryBody* body(const std::string& body_name) const {
        for (const auto& b : bodies)
            if (b.name == body_name) return &b;
        return nullptr;
    }
};

// Scene options as key = value text, from the command line or a spec. Each scene reads the
// keys it knows; finish() refuses any key nobody read, naming it and the known ones.
class SceneOptions {
public:
    explicit SceneOptions(std::map<std::string, std::string> values = {}) : values_(std::move(values)) {}
    double number(const std::string& key, double fallback, double lo, double hi);
    long long integer(const std::string& key, long long fallback, long long lo, long long hi);
    std::string text(const std::string& key, const std::string& fallback);
    bool has(const std::string& key) const { return values_.count(key) > 0; }
    void finish(const std::string& scene) const;
    const std::map<std::string, std::string>& resolved() const { return resolved_; }

private:
    std::map<std::string, std::string> values_, resolved_;
};

struct SceneInfo {
    std::string name, description;
    std::function<Scene(SceneOptions&)> build;
};

const std::vector<SceneInfo>& scene_catalogue();
// Builds a scene by name; throws InputError for an unknown scene or option.
Scene make_scene(const std::string& name, const std::map<std::string, std::string>& options);

// Where meshes are looked for: $SPH_MESH_DIR, then ../shared/meshes beside the source tree
// and beside the working directory. Throws InputError listing the places tried.
std::string find_mesh(const std::string& file_name);

}  // namespace sph

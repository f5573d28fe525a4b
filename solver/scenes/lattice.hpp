#pragma once
// Building blocks of scenes: particles on a lattice of spacing dp, boxes of boundary
// layers, and the search for the spacing that hits a target particle count.
#include <functional>

#include "scenes/scene.hpp"

namespace sph {

struct LatticeBox {
    long lo[3], hi[3];  // inclusive lattice indices; a point is origin + dp * index
};

// Adds the boundary shell of a box: every lattice point within `layers` of its faces,
// outward from lo/hi. With open_top there is no lid.
void add_box_boundary(Scene& s, const double origin[3], const LatticeBox& box, int layers, bool open_top);

// Adds the surface points of a solid box standing on the floor (its bottom face omitted).
void add_solid_box_surface(Scene& s, const double origin[3], const LatticeBox& box);

// Adds fluid at every lattice point of the box (all indices inclusive).
void add_fluid_box(Scene& s, const double origin[3], const LatticeBox& box);

// The spacing whose count(dp) is within 1% of target: count is monotone decreasing in dp.
// Throws InputError when no spacing gets within 1% (a target too small to resolve).
double pick_spacing(double first_guess, long long target, const std::function<long long(double)>& count,
                    const std::string& scene);

// Sets the parameters every scene shares from dp, rho0 and the sound speed, and reads the
// options common to all scenes (kernel, viscosity, density diffusion).
void set_common_physics(Scene& s, SceneOptions& opt, double c0, const char* default_kernel);

long lattice_index(double x, double dp);  // nearest lattice index of a length

}  // namespace sph

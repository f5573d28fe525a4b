#pragma once
// Cases without C++: a scene described by data, as DualSPHysics' GenCase builds one from its
// drawbox commands. A tank (box walls of boundary particles, open top or closed), boxes of fluid
// (at rest and hydrostatic, or moving), solid boxes as obstacles (named bodies) and meshes
// filled with fluid, all in metres. The harness reads one from a case file (harness/case_file.hpp).
//
// Every particle sits on one lattice whose origin is the tank's `min` corner: a coordinate x
// maps to the nearest lattice index round((x - min) / dp). The tank's innermost wall layer lies
// on its faces, further layers outward. A fluid box takes every lattice point of its closed box
// that is not a wall, not on an obstacle and not already fluid (so a box from the floor to the
// walls loses the points on the walls, as the C++ scenes' fluid does). An obstacle is a shell of
// `layers` points inward from its faces, without the points that are the tank's walls.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "scenes/scene.hpp"

namespace sph {

struct CaseBox {
    std::array<double, 3> min{}, max{};  // metres
    std::string where;                   // "FILE:LINE: [[case.fluid]] 2", for messages
};

struct CaseTank : CaseBox {
    bool open_top = true;
    int layers = 2;  // wall layers, outward
    std::string name = "tank";
};

struct CaseFluid : CaseBox {
    bool hydrostatic = true;  // density from the depth below the box's free surface
    std::array<double, 3> velocity{};
};

struct CaseObstacle : CaseBox {
    std::string name;
    int layers = 0;  // shell layers, inward; 0: the tank's
};

struct CaseMesh {
    std::string file, where;
    double height = 0;               // scaled to this along its up axis (m)
    std::array<double, 3> min{};     // where its bounding box's low corner goes
    bool y_up = true;                // rotated so that its y axis points up (z)
};

struct BoxCase {
    std::string name;    // the scene's name (the harness's: "case:FILE")
    std::string source;  // the case file, for messages and provenance
    double dp = 0;
    std::string dp_where;
    bool has_domain = false;  // `domain` given: its corners
    std::array<double, 3> domain_lo{}, domain_hi{};
    double domain_top = 0;    // > 0: the default domain's top (room above an open tank)
    std::string domain_where;
    CaseTank tank;
    std::vector<CaseFluid> fluids;
    std::vector<CaseObstacle> obstacles;
    std::vector<CaseMesh> meshes;
    std::map<std::string, std::string> options;  // scene options of the case (kernel, alpha, ...)
};

// The scene options a case takes (from the case or from --set): dp and the physics of every scene.
const std::vector<std::string>& box_case_option_keys();

// The checks that need no spacing: max above min, the fluid and the obstacles inside the tank,
// no fluid box overlapping an obstacle. Throws InputError naming the box and its key.
void check_box_case(const BoxCase& c);

// The particles of the case: the tank's walls (body tank.name), each obstacle (a body), then
// the fluid. `options` (dp, kernel, alpha, ...) override the case's own. Throws InputError for
// a box smaller than one spacing, a mesh outside the tank or over an obstacle, a domain that
// does not hold every particle, or an unknown option.
Scene build_box_case(const BoxCase& c, const std::map<std::string, std::string>& options);

}  // namespace sph

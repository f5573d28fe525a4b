#pragma once
// Options shared by the commands that run the solver: backend, device, search strategy.
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "simulation.hpp"

namespace sph {

struct SolverCli {
    std::string backend = "auto";
    int device = 0;
    int cells_per_support = 1;
    bool merge = false;
    double fixed_dt = 0;
    double cfl = 0;
    bool no_diffusion = false;
    bool verlet = false;
    double skin = 0.1;
    int rebuild_every = 0;
    int devices = 1;
    std::vector<int> device_map;
    std::string balancer = "none";
    std::string transport = "auto";
};

void add_solver_options(CLI::App& cmd, SolverCli& o);
// "auto" means CUDA when a GPU is present, else the host.
SolverOptions solver_options(const SolverCli& o);
std::string backend_name(BackendKind b);
// Parses key=value pairs; throws InputError naming the malformed one.
std::map<std::string, std::string> parse_settings(const std::vector<std::string>& pairs);

}  // namespace sph

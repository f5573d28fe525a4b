#include "cli_options.hpp"

#include "core/error.hpp"
#include "multi/particle_transport.hpp"

namespace sph {

void add_solver_options(CLI::App& cmd, SolverCli& o) {
    cmd.add_option("--backend", o.backend, "where to run: cuda, host, or auto (CUDA when a GPU is present)")
        ->check(CLI::IsMember({"auto", "cuda", "host"}))
        ->capture_default_str();
    cmd.add_option("--device", o.device, "GPU index for the CUDA backend")->capture_default_str();
    cmd.add_option("--devices", o.devices,
                   "subdomains (X slabs, one per logical device): on N GPUs, on one GPU, or on the host")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd.add_option("--device-map", o.device_map, "GPU of each subdomain, e.g. --device-map 0 1 (default: d mod GPUs)");
    cmd.add_option("--balancer", o.balancer, "load balancing: none, simple, every:K or threshold (paper 5.2), or equal-time[:F] (moves as many slices as the measured rates call for)")
        ->capture_default_str();
    cmd.add_option("--transport", o.transport,
                   "how particles travel between subdomains: auto, host, peer (GPU to GPU), staged (through host "
                   "memory) or nccl")
        ->check(CLI::IsMember({"auto", "host", "peer", "staged", "nccl"}))
        ->capture_default_str();
    cmd.add_option("--cells-per-support", o.cells_per_support,
                   "Smaller Cell's n: cell size = support radius / n (1 to 4)")
        ->check(CLI::Range(1, 4))
        ->capture_default_str();
    cmd.add_flag("--merge", o.merge, "Cell Merging: search z-runs of cells as one range");
    cmd.add_option("--fixed-dt", o.fixed_dt, "fixed time step in seconds (benchmarks); default: CFL-limited")
        ->check(CLI::PositiveNumber);
    cmd.add_option("--cfl", o.cfl, "CFL number (default: the scene's, 0.2)")->check(CLI::Range(1e-4, 1.0));
    cmd.add_flag("--no-diffusion", o.no_diffusion, "compile out delta-SPH density diffusion");
    cmd.add_flag("--verlet", o.verlet, "Verlet lists: store neighbour lists and reuse them between rebuilds");
    cmd.add_option("--skin", o.skin, "Verlet skin as a fraction of the support radius")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd.add_option("--rebuild-every", o.rebuild_every,
                   "rebuild Verlet lists every k steps (default: when particles may have moved half the skin)")
        ->check(CLI::NonNegativeNumber);
}

std::string backend_name(BackendKind b) { return b == BackendKind::cuda ? "cuda" : "host"; }

SolverOptions solver_options(const SolverCli& o) {
    SolverOptions s;
    if (o.backend == "cuda") s.backend = BackendKind::cuda;
    else if (o.backend == "host") s.backend = BackendKind::host;
    else s.backend = cuda_backend_available() ? BackendKind::cuda : BackendKind::host;
    s.device = o.device;
    s.search.cells_per_support = o.cells_per_support;
    s.search.merge = o.merge;
    s.fixed_dt = o.fixed_dt;
    s.cfl = o.cfl;
    s.diffusion = !o.no_diffusion;
    s.search.verlet = o.verlet;
    s.search.skin = o.skin;
    s.search.rebuild_every = o.rebuild_every;
    s.subdomains = o.devices;
    s.device_map = o.device_map;
    s.balancer = o.balancer;
    s.transport = parse_transport(o.transport);
    if (s.backend == BackendKind::cuda) {
        const int gpus = cuda_device_count();
        for (int g : s.device_map)
            if (g < 0 || g >= gpus)
                throw InputError("the device map names GPU " + std::to_string(g) + ", but this machine has " +
                                 std::to_string(gpus) + " GPU(s)");
    }
    return s;
}

std::map<std::string, std::string> parse_settings(const std::vector<std::string>& pairs) {
    std::map<std::string, std::string> out;
    for (const auto& p : pairs) {
        const auto eq = p.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("setting '" + p + "' is not of the form key=value");
        out[p.substr(0, eq)] = p.substr(eq + 1);
    }
    return out;
}

}  // namespace sph

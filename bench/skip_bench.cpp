// What skipping work a scene does not need saves (DESIGN: "skip what a scene does not need"),
// each against the variant that does the work for nothing, on DualSPHysics' dam break:
//   forces/diffusion_*      delta-SPH diffusion compiled out, against compiled in with
//                           coefficient 0 (same result), and on with 0.1 for scale;
//   integrate/boundary_*    boundary particles' positions not integrated, against moved like
//                           fluid under their zero acceleration (same result);
//   step/grid_*             whole steps with the grid over the scene's domain, against over the
//                           particles' bounding box grown by one support (same result while no
//                           fluid leaves that box; the dam break's domain has 0.2 m of headroom).
// On the CUDA backend when a GPU is present (CUDA events, manual time), else the host.
//   SPH_BENCH_PARTICLES   fluid particles (default 1e6 on a GPU, 2e4 on the host)
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "backend/subdomain.hpp"
#include "scenes/scene.hpp"
#include "simulation.hpp"

namespace {

using namespace sph;

bool on_gpu() { return cuda_backend_available(); }

const Scene& dambreak() {
    static const Scene scene = [] {
        const char* env = std::getenv("SPH_BENCH_PARTICLES");
        const long long particles = env ? std::atoll(env) : (on_gpu() ? 1000000 : 20000);
        return make_scene("dsph-dambreak", {{"particles", std::to_string(particles)}});
    }();
    return scene;
}

// A subdomain in the scene's initial state, sorted, with its forces computed once.
std::unique_ptr<Subdomain> prepared(bool diffusion, double delta, bool integrate_boundary) {
    const Scene& s = dambreak();
    PhysicsParams p = s.params;
    p.delta = real(delta);
    const Grid g = make_grid(s.lo.data(), s.hi.data(), p.support, 1);
    SubdomainConfig cfg{p, g.view, s.kernel, diffusion, SearchOptions{}};
    cfg.integrate_boundary = integrate_boundary;
    auto sub = on_gpu() ? make_cuda_subdomain(cfg, s.size(), 0) : make_host_subdomain(cfg, s.size());
    sub->upload(make_particle_arrays(s, g));
    sub->sort_by_cell();
    sub->advance(euler_step(0));
    sub->compute_forces();
    return sub;
}

void label(benchmark::State& state, const std::string& device) {
    const Scene& s = dambreak();
    state.counters["particles"] = double(s.size());
    state.counters["boundary_fraction"] = double(s.n_boundary) / double(s.size());
    state.SetLabel(device);
}

void forces(benchmark::State& state, bool diffusion, double delta) {
    auto sub = prepared(diffusion, delta, false);
    PhaseClock& clock = sub->clock();
    for (auto _ : state) {
        clock.begin(Phase::forces);
        sub->compute_forces();
        clock.end(Phase::forces);
        state.SetIterationTime(clock.collect()[std::size_t(Phase::forces)] * 1e-3);
    }
    label(state, sub->device_name());
}

// The update of one step, with dt = 0 so that every iteration does the same work on the
// same state.
void integrate(benchmark::State& state, bool integrate_boundary) {
    auto sub = prepared(true, dambreak().params.delta, integrate_boundary);
    PhaseClock& clock = sub->clock();
    for (auto _ : state) {
        clock.begin(Phase::integrate);
        sub->advance(verlet_step(0, 0));
        clock.end(Phase::integrate);
        state.SetIterationTime(clock.collect()[std::size_t(Phase::integrate)] * 1e-3);
    }
    label(state, sub->device_name());
}

// Whole steps (every phase, as the step records time them) at a small fixed time step.
void step(benchmark::State& state, bool grid_fits_particles) {
    SolverOptions opt;
    opt.backend = on_gpu() ? BackendKind::cuda : BackendKind::host;
    opt.fixed_dt = 1e-5;
    opt.grid_fits_particles = grid_fits_particles;
    Simulation sim(dambreak(), opt);
    double sort_ms = 0;
    for (auto _ : state) {
        const StepRecord& r = sim.step();
        sort_ms += r.phase_ms[std::size_t(Phase::neighbour_list)];
        state.SetIterationTime(r.step_ms() * 1e-3);
    }
    const GridView& g = sim.grid().view;
    state.counters["cells"] = double(g.cell_count());
    state.counters["neighbour_list_ms"] = sort_ms / double(state.iterations());
    label(state, sim.device_name());
}

const int registered = [] {
    auto reg = [](const char* name, auto fn, auto... args) {
        benchmark::RegisterBenchmark(name, fn, args...)->UseManualTime()->Unit(benchmark::kMillisecond);
    };
    reg("skip/forces/diffusion_compiled_out", forces, false, 0.0);
    reg("skip/forces/diffusion_on_coefficient_0", forces, true, 0.0);
    reg("skip/forces/diffusion_on_0.1", forces, true, 0.1);
    reg("skip/integrate/boundary_skipped", integrate, false);
    reg("skip/integrate/boundary_integrated", integrate, true);
    reg("skip/step/grid_domain", step, false);
    reg("skip/step/grid_particles", step, true);
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();

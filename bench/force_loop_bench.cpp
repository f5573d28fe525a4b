// Google Benchmark micro-benchmarks of the hot kernels: the neighbour search with the force
// loop, one benchmark per search strategy, and the build of Verlet lists, on the CUDA backend
// when a GPU is present (timed with CUDA events, as manual time) and on the host otherwise.
// JSON output (--benchmark_format=json) is what `sphbench compare` reads.
//   SPH_BENCH_PARTICLES   fluid particles of the dam break (default 1e6 on a GPU, 2e4 on the host)
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

// One prepared subdomain per strategy: sorted, P / rho^2 set, lists built where needed.
struct Prepared {
    Scene scene;
    std::unique_ptr<Subdomain> sub;
};

Prepared& prepared(const SearchOptions& s) {
    static std::map<std::string, Prepared> cache;
    const std::string key = std::to_string(s.cells_per_support) + (s.merge ? "m" : "") +
                            (s.verlet ? "v" + std::to_string(s.skin) : "");
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    const bool gpu = cuda_backend_available();
    const char* env = std::getenv("SPH_BENCH_PARTICLES");
    const long long particles = env ? std::atoll(env) : (gpu ? 1000000 : 20000);
    Prepared p;
    p.scene = make_scene("dsph-dambreak", {{"particles", std::to_string(particles)}});
    const Grid g = make_grid(p.scene.lo.data(), p.scene.hi.data(), search_reach(p.scene.params.support, s),
                             s.cells_per_support);
    const SubdomainConfig cfg{p.scene.params, g.view, p.scene.kernel, true, s};
    p.sub = gpu ? make_cuda_subdomain(cfg, p.scene.size(), 0) : make_host_subdomain(cfg, p.scene.size());
    p.sub->upload(make_particle_arrays(p.scene, g));
    p.sub->sort_by_cell();
    p.sub->advance(euler_step(0));
    if (s.verlet) p.sub->build_neighbour_list(real(s.skin * p.scene.params.support));
    return cache.emplace(key, std::move(p)).first->second;
}

void force_loop(benchmark::State& state, SearchOptions s) {
    Prepared& p = prepared(s);
    PhaseClock& clock = p.sub->clock();
    for (auto _ : state) {
        clock.begin(Phase::forces);
        s.verlet ? p.sub->compute_forces_listed() : p.sub->compute_forces();
        clock.end(Phase::forces);
        state.SetIterationTime(clock.collect()[std::size_t(Phase::forces)] * 1e-3);
    }
    const WorkCounters w = p.sub->count_work();
    state.counters["particles"] = double(p.scene.size());
    state.counters["neighbour_pairs_per_s"] =
        benchmark::Counter(double(w.neighbours) * double(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["candidates_per_particle"] = double(w.candidates) / double(p.scene.size());
    state.SetLabel(p.sub->device_name());
}

// One rebuild of the Verlet lists (the list build kernel and the longest-list reduction, on
// the sorted particles; the sort is the cell search's and not timed here).
void list_build(benchmark::State& state, SearchOptions s) {
    Prepared& p = prepared(s);
    PhaseClock& clock = p.sub->clock();
    const real skin = real(s.skin * p.scene.params.support);
    for (auto _ : state) {
        clock.begin(Phase::neighbour_list);
        p.sub->build_neighbour_list(skin);
        clock.end(Phase::neighbour_list);
        state.SetIterationTime(clock.collect()[std::size_t(Phase::neighbour_list)] * 1e-3);
    }
    state.counters["particles"] = double(p.scene.size());
    state.counters["list_bytes_per_particle"] = double(p.sub->neighbour_list_bytes()) / double(p.scene.size());
    state.SetLabel(p.sub->device_name());
}

// Verlet lists as the README's benchmarks run them: cells of the support with a skin of 0.1
// supports, and half-size cells with a skin of 0.05 (--cells-per-support 2 --skin 0.05).
SearchOptions verlet_options(int cells_per_support, double skin) {
    SearchOptions s;
    s.cells_per_support = cells_per_support;
    s.verlet = true;
    s.skin = skin;
    return s;
}

const int registered = [] {
    for (int n = 1; n <= 4; ++n)
        for (bool merge : {false, true}) {
            const std::string name = "force_loop/n" + std::to_string(n) + (merge ? "_merged" : "_cells");
            benchmark::RegisterBenchmark(name.c_str(), force_loop, SearchOptions{n, merge})
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
        }
    for (const auto& [suffix, options] :
         {std::pair{"", verlet_options(1, 0.1)}, std::pair{"_n2", verlet_options(2, 0.05)}}) {
        benchmark::RegisterBenchmark((std::string("force_loop/verlet_list") + suffix).c_str(), force_loop, options)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((std::string("list_build/verlet_list") + suffix).c_str(), list_build, options)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
    }
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();

// Run under mpirun: the same scene with the same subdomains, once spread over the MPI ranks
// and once in this process alone (the reference, without paper 5.3's overlap; the MPI run
// overlaps unless the fourth argument is no-overlap), stepped side by side. Every step, every
// particle (by id) must have bitwise the same position, velocity and density, each id held
// once, and the time steps must agree. Arguments: subdomains, balancer, steps.
// Exit 0 when all agree; 1, with the first difference, otherwise (every rank sees the same
// gathered snapshots, so every rank exits the same way). Words after the three arguments:
// no-overlap (the MPI run without paper 5.3's order), cuda (both runs on the CUDA backend;
// tools/mpi-cuda-check.sh runs it on a GPU machine), share-gpus (ranks may share a GPU),
// verlet (both runs on Verlet lists rebuilt every 5 steps, whose ghosts are refreshed in place
// between rebuilds: the lists must also have been rebuilt during the run, so that a refresh across a rebuild,
// with its repartition, is compared).
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "multi/rank_group.hpp"
#include "scenes/scene.hpp"
#include "simulation.hpp"

namespace {

struct State {
    double x, y, z, u, v, w, rho;
    bool operator==(const State&) const = default;
};

// Positions, velocities and densities by id; an id held twice is an error.
std::map<std::uint32_t, State> by_id(const sph::SnapshotData& s, std::string& error) {
    std::map<std::uint32_t, State> m;
    for (std::size_t i = 0; i < s.id.size(); ++i) {
        const State st{s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2], s.velocity[3 * i],
                       s.velocity[3 * i + 1], s.velocity[3 * i + 2], s.density[i]};
        if (!m.emplace(s.id[i], st).second) error = "particle " + std::to_string(s.id[i]) + " is held twice";
    }
    return m;
}

bool same_or_both_nan(const State& a, const State& b) {
    auto eq = [](double p, double q) { return p == q || (p != p && q != q); };  // out-of-domain: NaN
    return eq(a.x, b.x) && eq(a.y, b.y) && eq(a.z, b.z) && a.u == b.u && a.v == b.v && a.w == b.w && a.rho == b.rho;
}

}  // namespace

int main(int argc, char** argv) {
    auto mpi = sph::make_mpi_rank_group(argc, argv);
    bool overlap = true, cuda = false, share = false, verlet = false, usage = argc < 4;
    for (int i = 4; i < argc; ++i) {
        const std::string w = argv[i];
        if (w == "no-overlap") overlap = false;
        else if (w == "cuda") cuda = true;
        else if (w == "share-gpus") share = true;
        else if (w == "verlet") verlet = true;
        else usage = true;
    }
    if (usage) {
        std::fprintf(stderr, "usage: mpirun -np R mpi_equivalence SUBDOMAINS BALANCER STEPS [no-overlap] [cuda] [share-gpus] [verlet]\n");
        return 2;
    }
    const int subdomains = std::atoi(argv[1]);
    const std::string balancer = argv[2];
    const long steps = std::atol(argv[3]);
    auto alone = sph::make_single_process_group();
    int code = 0;
    try {
        const sph::Scene scene = sph::make_scene("dambreak", {{"dp", "0.04"}, {"length", "1.0"}, {"column_height", "0.6"}, {"height", "0.8"}});
        sph::SolverOptions distributed;
        distributed.subdomains = subdomains;
        distributed.balancer = balancer;
        distributed.ranks = mpi.get();
        distributed.overlap = overlap;  // paper 5.3's order unless no-overlap
        distributed.backend = cuda ? sph::BackendKind::cuda : sph::BackendKind::host;
        distributed.share_gpus = share;
        distributed.search.verlet = verlet;
        // 40 steps from rest move too little for the skin to expire: rebuild every 5 steps, so
        // that refreshes, rebuilds and the repartitions they carry alternate.
        if (verlet) distributed.search.rebuild_every = 5;
        sph::SolverOptions reference = distributed;
        reference.ranks = alone.get();
        reference.overlap = false;  // the order without overlap, in one process
        sph::Simulation a(scene, reference), b(scene, distributed);
        long moved = 0;
        unsigned long long migrated = 0;
        for (long k = 1; k <= steps && code == 0; ++k) {
            const double dt_a = a.step().dt;
            const sph::StepRecord& rb = b.step();
            moved += rb.slices_moved;
            migrated += rb.exchange.particles_migrated;
            std::string error;
            const auto pa = by_id(a.snapshot(), error), pb = by_id(b.snapshot(), error);
            std::size_t differ = 0;
            for (const auto& [id, st] : pa) {
                const auto it = pb.find(id);
                if (it == pb.end() || !same_or_both_nan(st, it->second)) ++differ;
            }
            if (pa.size() != scene.size() || pb.size() != scene.size())
                error = "step " + std::to_string(k) + ": " + std::to_string(pb.size()) + " particles held, the scene has " +
                        std::to_string(scene.size());
            if (differ) error = "step " + std::to_string(k) + ": " + std::to_string(differ) + " particles differ";
            if (dt_a != rb.dt) error = "step " + std::to_string(k) + ": the time steps differ";
            if (!error.empty()) {
                std::fprintf(stderr, "rank %d: %s\n", mpi->rank(), error.c_str());
                code = 1;
            }
        }
        if (mpi->rank() == 0)
            std::printf("%d ranks, %d subdomains, %s backend, %s, balancer %s, overlap %s: %ld steps bitwise equal to "
                        "one process without overlap; %ld slices moved, %llu particles migrated; rank_transport %s\n",
                        mpi->size(), subdomains, cuda ? "cuda" : "host",
                        verlet ? ("Verlet lists built " + std::to_string(b.neighbour_list_builds()) + " times").c_str()
                               : "cell search",
                        balancer.c_str(), distributed.overlap ? "on" : "off", code ? 0L : steps, moved, migrated,
                        b.rank_transport_name().c_str());
        if (code == 0 && verlet && a.neighbour_list_builds() != b.neighbour_list_builds()) {
            std::fprintf(stderr, "the lists were built %ld times over the ranks and %ld times in one process\n",
                         long(b.neighbour_list_builds()), long(a.neighbour_list_builds()));
            code = 1;
        }
        if (code == 0 && verlet && b.neighbour_list_builds() < 2) {
            std::fprintf(stderr, "the lists were never rebuilt, so no refresh across a rebuild was tested\n");
            code = 1;
        }
        if (code == 0 && balancer != "none" && moved == 0) {
            std::fprintf(stderr, "the balancer never moved a slice, so no repartition was tested\n");
            code = 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rank %d: %s\n", mpi->rank(), e.what());
        mpi->abort(3);
    }
    return code;
}

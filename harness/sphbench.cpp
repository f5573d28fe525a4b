// sphbench: the project's one program. Subcommands run scenes, experiments and comparisons.
#include <cstdio>
#include <new>
#include <string>

#include "commands.hpp"
#include "core/error.hpp"
#include "multi/rank_group.hpp"
#include "out_of_memory.hpp"

namespace {

// Under mpirun each rank runs the whole program on its share of the subdomains; rank 0 alone
// prints and writes. An error on any rank stops the whole job (MPI_Abort): a rank that
// returned would leave the others waiting in a collective.
int fail(const char* what, int code) {
    sph::RankGroup& ranks = sph::process_ranks();
    if (ranks.size() == 1) {
        std::fprintf(stderr, "sphbench: %s\n", what);
        return code;
    }
    std::fprintf(stderr, "sphbench (rank %d of %d): %s\n", ranks.rank(), ranks.size(), what);
    std::fflush(stderr);
    ranks.abort(code);
    return code;  // not reached: abort stops the job
}

int run(int argc, char** argv) {
    CLI::App app{"sphbench: a multi-GPU SPH solver and the benchmark harness that recreates the figures of "
                 "Hu, Shen and Long's multi-GPU SPH paper"};
    app.require_subcommand(1);
    sph::CommandContext ctx{argc, argv};
    sph::add_simulate_command(app, ctx);
    sph::add_info_command(app, ctx);
    sph::add_run_command(app, ctx);
    sph::add_list_command(app, ctx);
    sph::add_compare_command(app, ctx);
    sph::add_stability_command(app, ctx);
    try {
        sph::check_subcommand(app, argc, argv);
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);  // --help
    } catch (const CLI::ParseError& e) {
        // One line naming the flag and the value; CLI11's own exit() adds a second about --help.
        std::fprintf(stderr, "sphbench: %s\n", e.what());
        return sph::exit_usage;
    } catch (const sph::InputError& e) {
        return fail(e.what(), sph::exit_usage);
    } catch (const sph::RunError& e) {
        return fail(e.what(), sph::exit_run_failed);
    } catch (const std::bad_alloc&) {
        // Past the scene's and the run's start (which name the scene): arrays that grew during
        // the run, such as neighbour lists on the host.
        const std::string what = std::string("ran out of host memory during the run; ") + sph::coarser_scene_advice;
        return fail(what.c_str(), sph::exit_run_failed);
    } catch (const std::exception& e) {
        return fail(e.what(), sph::exit_run_failed);
    }
    return ctx.exit_code;
}

}  // namespace

int main(int argc, char** argv) {
    if (sph::started_by_mpirun()) {
        try {
            sph::set_process_ranks(sph::make_mpi_rank_group(argc, argv));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "sphbench: %s\n", e.what());
            return sph::exit_usage;
        }
        if (sph::process_ranks().rank() != 0 && !std::freopen("/dev/null", "w", stdout))
            std::fprintf(stderr, "sphbench: rank %d could not silence its output\n", sph::process_ranks().rank());
    }
    const int code = run(argc, argv);
    sph::set_process_ranks(nullptr);  // MPI_Finalize
    return code;
}

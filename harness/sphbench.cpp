// sphbench: the project's one program. Subcommands run scenes, experiments and comparisons.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
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
        std::fprintf(stderr, "sphbench: %s\n", e.what());
        return sph::exit_usage;
    } catch (const sph::RunError& e) {
        std::fprintf(stderr, "sphbench: %s\n", e.what());
        return sph::exit_run_failed;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sphbench: %s\n", e.what());
        return sph::exit_run_failed;
    }
    return ctx.exit_code;
}

// sphbench info: what this build is, what it can run on, and which scenes it knows.
#include <cstdio>

#include "cli_options.hpp"
#include "commands.hpp"
#include "provenance.hpp"
#include "scenes/scene.hpp"

namespace sph {

void add_info_command(CLI::App& app, CommandContext& ctx) {
    CLI::App* cmd = app.add_subcommand("info", "show the build, the backends and devices, and the scenes");
    cmd->callback([&ctx] {
        const BuildInfo b = build_info();
        std::printf("commit %s (%s), %s build, %s, CUDA backend compiled: %s\n", b.git_commit.c_str(),
                    b.git_dirty.c_str(), b.build_type.c_str(), b.precision.c_str(), b.cuda_compiled.c_str());
        const std::string cuda = cuda_device_summary();
        std::printf("GPUs: %s\n", cuda_backend_available() ? cuda.c_str() : "none visible (host backend only)");
        std::printf("scenes:\n");
        for (const auto& s : scene_catalogue()) std::printf("  %-14s %s\n", s.name.c_str(), s.description.c_str());
        std::printf("  %-14s a case file: a tank, boxes of fluid, obstacles and meshes in metres, no C++ "
                    "(experiments/cases/)\n", "case:FILE");
        ctx.exit_code = exit_ok;
    });
}

}  // namespace sph

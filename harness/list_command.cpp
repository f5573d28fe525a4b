// sphbench list: the experiment specs, what each reproduces, how many runs, and whether
// results exist for it.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "core/error.hpp"
#include "experiment_runner.hpp"

namespace sph {
namespace {

struct ListArgs {
    std::string dir = "experiments";
    std::string results = "results";
};

void list_specs(const ListArgs& a, CommandContext& ctx) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(a.dir)) throw InputError("experiment folder '" + a.dir + "' does not exist");
    std::vector<std::string> paths;
    for (const auto& e : fs::directory_iterator(a.dir))
        if (e.is_regular_file() && e.path().extension() == ".toml") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) {
        std::printf("no experiment specs (*.toml) in %s\n", a.dir.c_str());
        ctx.exit_code = exit_ok;
        return;
    }
    std::printf("%-16s %5s  %-9s %s\n", "name", "runs", "results", "reproduces");
    int broken = 0;
    for (const auto& path : paths) {
        try {
            const ExperimentSpec spec = load_spec(path);
            // Runs as planned without a GPU or overrides: the count does not depend on them.
            const std::size_t runs = expand(spec, ExpandOptions{}).size();
            // `sphbench run` writes runs.csv last; `sphbench stability` writes summary.csv last.
            const char* last_written = spec.stability ? "summary.csv" : "runs.csv";
            const bool done = fs::exists(fs::path(experiment_dir(a.results, spec)) / last_written);
            std::printf("%-16s %5zu  %-9s %s\n", spec.name.c_str(), runs, done ? "yes" : "no", spec.reproduces.c_str());
        } catch (const InputError& e) {
            std::printf("%-16s %5s  %-9s invalid spec: %s\n", fs::path(path).stem().string().c_str(), "-", "-", e.what());
            ++broken;
        }
    }
    ctx.exit_code = broken ? exit_usage : exit_ok;
}

}  // namespace

void add_list_command(CLI::App& app, CommandContext& ctx) {
    auto a = std::make_shared<ListArgs>();
    CLI::App* cmd = app.add_subcommand("list", "list the experiment specs: what each reproduces, its runs, and "
                                               "whether results exist");
    cmd->add_option("--dir", a->dir, "folder of experiment specs")->capture_default_str();
    cmd->add_option("--results", a->results, "results folder that `run --out` wrote into")->capture_default_str();
    cmd->callback([a, &ctx] { list_specs(*a, ctx); });
}

}  // namespace sph

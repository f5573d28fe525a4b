#pragma once
// Each sphbench subcommand registers itself on the app and sets the exit code when it runs.
#include <CLI/CLI.hpp>

namespace sph {

struct CommandContext {
    int argc;
    char** argv;
    int exit_code = 0;
};

void add_simulate_command(CLI::App& app, CommandContext& ctx);
void add_info_command(CLI::App& app, CommandContext& ctx);
void add_run_command(CLI::App& app, CommandContext& ctx);
void add_list_command(CLI::App& app, CommandContext& ctx);
void add_compare_command(CLI::App& app, CommandContext& ctx);
void add_stability_command(CLI::App& app, CommandContext& ctx);

// Throws InputError naming argv[1] when it is neither an option nor a subcommand of `app`.
void check_subcommand(CLI::App& app, int argc, char** argv);

// Exit codes of every command.
constexpr int exit_ok = 0;
constexpr int exit_regression = 1;
constexpr int exit_usage = 2;
constexpr int exit_run_failed = 3;
// 4, exit_inconclusive (regression_compare.hpp): `compare` could not tell, and said what to do.

}  // namespace sph

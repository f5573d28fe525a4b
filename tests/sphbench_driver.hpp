#pragma once
// `sphbench ARGS...` inside a test, through the real command registrations and main's check of
// the subcommand: returns the exit code main would give and, where one is asked for, the
// message of what was refused (empty when nothing was).
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "commands.hpp"
#include "core/error.hpp"

namespace sph::test {

inline int sphbench(std::vector<std::string> args, std::string* message = nullptr) {
    args.insert(args.begin(), "sphbench");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    CLI::App app{"sphbench"};
    app.require_subcommand(1);
    CommandContext ctx{int(argv.size()), argv.data()};
    add_simulate_command(app, ctx);
    add_run_command(app, ctx);
    add_info_command(app, ctx);
    add_compare_command(app, ctx);
    add_stability_command(app, ctx);
    std::string refused;
    int code = -1;
    try {
        check_subcommand(app, int(argv.size()), argv.data());
        app.parse(int(argv.size()), argv.data());
    } catch (const CLI::ParseError& e) {
        refused = e.what();
        code = app.exit(e) == 0 ? exit_ok : exit_usage;  // --help is a parse "error" that succeeds
    } catch (const InputError& e) {
        refused = e.what();
        code = exit_usage;
    } catch (const std::exception& e) {
        refused = e.what();
        code = exit_run_failed;
    }
    if (message) *message = refused;
    return code >= 0 ? code : ctx.exit_code;
}

inline int sphbench(std::vector<std::string> args, std::string& message) { return sphbench(std::move(args), &message); }

}  // namespace sph::test

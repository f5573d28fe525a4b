// Names the word that is not a subcommand: CLI11 alone answers "A subcommand is required" for
// `sphbench frobnicate`, since it takes the word for a stray argument.
#include <string>

#include "commands.hpp"
#include "core/error.hpp"

namespace sph {

void check_subcommand(CLI::App& app, int argc, char** argv) {
    std::string known;
    bool is_known = false;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        known += (known.empty() ? "" : ", ") + sub->get_name();
        is_known = is_known || (argc >= 2 && sub->check_name(argv[1]));
    }
    if (argc < 2) throw InputError("a subcommand is required (one of: " + known + ")");
    const std::string word = argv[1];
    if (word.empty() || word[0] == '-') return;  // --help and the like: CLI11's
    if (!is_known)
        throw InputError("unknown subcommand '" + word + "' (known: " + known + ")");
}

}  // namespace sph

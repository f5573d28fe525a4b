#pragma once
// Command-line flags made from the solver settings table (solver_settings.hpp), and the
// checks every command shares: numeric flags, output folders, key=value pairs.
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "simulation.hpp"
#include "solver_settings.hpp"

namespace sph {

// One flag per setting of the table that applies on the command line; each value given is
// checked as the spec's key is and stored, in its normal form, in `given` under the key.
void add_solver_options(CLI::App& cmd, SettingMap& given);
// The given settings completed with the defaults; "auto" means CUDA when a GPU is present.
// (A device map naming a GPU a rank lacks is refused by the simulation: multi/gpu_choice.hpp.)
SolverOptions solver_options(const SettingMap& given);
std::string backend_name(BackendKind b);

// A CLI11 check that words its refusal as the spec keys' checks do ("--steps: ...").
CLI::Validator in_range(const ValueRange& range);

// A CLI11 check of a flag that takes the values of the setting `key` (as `--backend` does).
CLI::Validator setting_validator(const std::string& key);

// Throws InputError before any work starts when `path` (given by `flag`) cannot be an output
// folder: it, or the nearest part of it that exists, is not a folder.
void check_output_folder(const std::string& flag, const std::string& path);

// Parses key=value pairs; throws InputError naming the malformed one.
std::map<std::string, std::string> parse_settings(const std::vector<std::string>& pairs);

}  // namespace sph

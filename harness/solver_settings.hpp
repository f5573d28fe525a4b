#pragma once
// Solver settings by name, as specs, sweeps and `--set` give them: which keys exist, what
// type each takes, how text is checked, and how the settings become SolverOptions.
#include <map>
#include <string>
#include <vector>

#include "simulation.hpp"

namespace sph {

// Settings as validated text ("2", "true", "0.0001"), keyed by their spec names.
using SettingMap = std::map<std::string, std::string>;

enum class SettingKind { text, integer, number, boolean };

// backend, devices (X-slab subdomains), device (GPU of a one-subdomain run), balancer (none,
// simple, every:K, threshold, equal-time[:F]), transport (auto, host, peer, staged, nccl), cells_per_support (1..4), merge, verlet, skin (fraction of the
// support), rebuild_every (0: on displacement), fixed_dt (0: CFL-limited), cfl (0: the
// scene's), diffusion, precision (float32 or float64; default: this binary's): the column
// order of runs.csv.
const std::vector<std::string>& solver_setting_keys();
bool is_solver_setting(const std::string& key);
SettingKind solver_setting_kind(const std::string& key);

// Checks a value given as text and returns its normal form ("yes" -> "true", "2.50" -> "2.5").
// Throws InputError naming the key and the allowed values.
std::string check_solver_value(const std::string& key, const std::string& text);

// Every solver key with its value: the given one, else the solver's default.
SettingMap complete_solver_settings(const SettingMap& given);

// "auto" resolves to CUDA when gpu_available, else the host.
SolverOptions to_solver_options(const SettingMap& complete, bool gpu_available);

// "float32", or "float64" in a build with -DSPH_DOUBLE=ON. Precision is fixed when the solver
// is compiled, so a run asking for the other one needs the other build (precision_delegate.hpp).
const char* build_precision();

// Shortest text that reads back as the same double.
std::string format_number(double value);
// Letters, digits, '.', '_' and '-' kept; anything else becomes '-'.
std::string filename_safe(const std::string& text);

}  // namespace sph

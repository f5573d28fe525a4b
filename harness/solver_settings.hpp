#pragma once
// Solver settings by name, as specs, sweeps and `--set` give them: which keys exist, what
// type each takes, how text is checked, and how the settings become SolverOptions.
#include <map>
#include <string>
#include <vector>

#include "simulation.hpp"
#include "value_range.hpp"

namespace sph {

// Settings as validated text ("2", "true", "0.0001"), keyed by their spec names.
using SettingMap = std::map<std::string, std::string>;

enum class SettingKind { text, integer, number, boolean, integer_list };

// One solver setting: the spec key, the `simulate` flag and the `--set` key are all made from
// it, so the command line and the specs cannot disagree on a name, a range or a default.
struct SolverSetting {
    const char* key;                   // spec key and runs.csv column
    SettingKind kind;
    const char* fallback;              // the default, as text
    ValueRange range;                  // integer and number kinds (each element of a list)
    std::vector<std::string> choices;  // text kinds with a fixed set of values
    void (*check_text)(const std::string&);  // other text kinds: throws InputError
    const char* help;
    bool on_command_line;              // false: specs and `--set` only (precision is a build property)
};

// The table, in the column order of runs.csv: backend, devices (X-slab subdomains), gpu (GPU
// of a one-subdomain run), device_map (GPU of each subdomain), share_gpus (MPI ranks sharing
// a node's GPUs), balancer, transport, gpu_direct (GPU memory to MPI), overlap
// (paper 5.3's communication hidden under the inner update), cells_per_support, merge, verlet, skin, rebuild_every, fixed_dt (0: CFL-limited), cfl (0:
// the scene's), diffusion, precision, then the implementation variants of the CUDA backend
// (backend/implementation_variants.hpp: force_loop, list_build, list_entries; text settings
// whose values and default come from that registry).
const std::vector<SolverSetting>& solver_settings_table();
const SolverSetting* find_solver_setting(const std::string& key);

const std::vector<std::string>& solver_setting_keys();
bool is_solver_setting(const std::string& key);
SettingKind solver_setting_kind(const std::string& key);

// The flag of a setting on the command line: "--cells-per-support"; booleans that are on by
// default are turned off with "--no-KEY".
std::string setting_flag(const SolverSetting& s);
// What the setting accepts, as a user would write it: "a whole number from 1 to 4".
std::string describe_allowed(const SolverSetting& s);

// Checks a value given as text and returns its normal form ("yes" -> "true", "2.50" -> "2.5").
// Throws InputError "NAME: VALUE ... (allowed: ...)"; NAME is the key unless given (a flag).
std::string check_solver_value(const std::string& key, const std::string& text, const std::string& name = "");

// Every solver key with its value: the given one, else the solver's default.
SettingMap complete_solver_settings(const SettingMap& given);

// "auto" resolves to CUDA when gpu_available, else the host. Throws InputError when the
// device map does not give one GPU per subdomain.
SolverOptions to_solver_options(const SettingMap& complete, bool gpu_available);

// A setting of a run rather than of the solver: how many steps, how many of them first and not
// recorded, how often a snapshot, how many repetitions (whole numbers), and the simulated time
// to stop at (a number; its default 0, outside the range, means none). Each is read from a
// spec's top level, from `--set` and (not repetitions) from a `simulate` flag, all checked
// against the one range here.
struct RunSetting {
    const char* key;               // spec key and `--set` key
    ValueRange range;
    const char* fallback;          // a spec's default; nullptr: the spec must give it
    const char* simulate_default;  // `simulate`'s default (it warms up by default); nullptr: no flag
    bool settable;                 // a `--set` key
    const char* help;
};

// steps, warmup, snapshot_every, repetitions, max_repetitions, end_time.
const std::vector<RunSetting>& run_settings_table();
// Throws std::logic_error for a key not in the table (a programming error).
const RunSetting& run_setting(const std::string& key);
const RunSetting* find_run_setting(const std::string& key);
// "--snapshot-every".
std::string setting_flag(const RunSetting& s);
// Checks a value given as text; throws InputError "NAME: ..." as check_solver_value does.
long check_run_value(const std::string& key, const std::string& text, const std::string& name);
// The same for a setting that takes any number (end_time).
double check_run_number(const std::string& key, const std::string& text, const std::string& name);

// "float32", or "float64" in a build with -DSPH_DOUBLE=ON. Precision is fixed when the solver
// is compiled, so a run asking for the other one needs the other build (precision_delegate.hpp).
const char* build_precision();

// Letters, digits, '.', '_' and '-' kept; anything else becomes '-'.
std::string filename_safe(const std::string& text);

}  // namespace sph

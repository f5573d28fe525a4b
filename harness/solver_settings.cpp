#include "solver_settings.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "core/error.hpp"
#include "multi/load_balancer.hpp"
#include "multi/particle_transport.hpp"

namespace sph {
namespace {

void check_balancer(const std::string& text) { make_balancer(text); }  // throws naming the allowed forms

// Ranges: skin wider than the support grows the lists by (1 + skin)^3 for nothing, and a skin
// of 0 would rebuild every step (verlet = false does that without the lists); fixed_dt and
// cfl are "absent" at 0, so 0 itself is refused.
const std::vector<SolverSetting>& solver_option_settings() {
    static const std::vector<SolverSetting> table = {
        {"backend", SettingKind::text, "auto", {}, {"auto", "cuda", "host"}, nullptr,
         "where to run: cuda, host, or auto (CUDA when a GPU is present)", true},
        {"devices", SettingKind::integer, "1", whole_from(1, 1024), {}, nullptr,
         "subdomains (X slabs, one per logical device): on N GPUs, on one GPU, or on the host", true},
        {"gpu", SettingKind::integer, "0", whole_from(0, 1023), {}, nullptr,
         "GPU index of a one-subdomain run on the CUDA backend", true},
        {"device_map", SettingKind::integer_list, "", whole_from(0, 1023), {}, nullptr,
         "GPU of each subdomain, e.g. 0,1, among those its MPI rank sees on its node (default: subdomain d on GPU d "
         "mod GPUs; under MPI each rank on GPUs of its own)",
         true},
        {"share_gpus", SettingKind::boolean, "false", {}, {}, nullptr,
         "let MPI ranks of one node share its GPUs when they outnumber them (refused otherwise)", true},
        {"balancer", SettingKind::text, "none", {}, {}, check_balancer,
         "load balancing: none, simple, every:K or threshold (paper 5.2), or equal-time[:F] (moves as many slices as the measured rates call for)", true},
        {"transport", SettingKind::text, "auto", {}, {"auto", "host", "peer", "staged", "nccl"}, nullptr,
         "how particles travel between subdomains: auto, host, peer (GPU to GPU), staged (through host memory) or "
         "nccl",
         true},
        {"gpu_direct", SettingKind::boolean, "false", {}, {}, nullptr,
         "between MPI ranks, GPU memory to a CUDA-aware MPI: checked and refused where the MPI library lacks CUDA "
         "support (particles are staged through pinned host memory either way so far)",
         true},
        {"overlap", SettingKind::boolean, "true", {}, {}, nullptr,
         "the communication optimisation of paper 5.3 (several subdomains): boundary slices updated first and sent "
         "whole while the inner slices are updated, the repartition decided under the forces; off: balance and "
         "exchange at the start of each step, nothing overlapped (the particles are the same)",
         true},
        {"cells_per_support", SettingKind::integer, "1", whole_from(1, 4), {}, nullptr,
         "Smaller Cell's n: cell size = support radius / n", true},
        {"merge", SettingKind::boolean, "false", {}, {}, nullptr, "Cell Merging: search z-runs of cells as one range",
         true},
        {"verlet", SettingKind::boolean, "false", {}, {}, nullptr,
         "Verlet lists: store neighbour lists and reuse them between rebuilds", true},
        {"skin", SettingKind::number, "0.1", number_above(0, 1), {}, nullptr,
         "Verlet skin as a fraction of the support radius", true},
        {"rebuild_every", SettingKind::integer, "0", whole_from(0, 1e9), {}, nullptr,
         "rebuild Verlet lists every k steps (0: when particles may have moved half the skin)", true},
        {"fixed_dt", SettingKind::number, "0", number_above(0, 1e3), {}, nullptr,
         "fixed time step in seconds (benchmarks); default: CFL-limited", true},
        {"cfl", SettingKind::number, "0", number_above(0, 1), {}, nullptr, "CFL number; default: the scene's, 0.2",
         true},
        {"diffusion", SettingKind::boolean, "true", {}, {}, nullptr, "delta-SPH density diffusion", true},
        {"precision", SettingKind::text, build_precision(), {}, {"float32", "float64"}, nullptr,
         "float32 or float64: fixed when sphbench is compiled, so a spec's float64 runs need a float64 build",
         false},
    };
    return table;
}

// The table: the settings above, then one text setting per implementation variant, made from
// its registry (backend/implementation_variants.hpp) so that a name, a value or a default is
// written once.
const std::vector<SolverSetting>& settings() {
    static const std::vector<SolverSetting> table = [] {
        std::vector<SolverSetting> t = solver_option_settings();
        for (const ImplementationVariant& v : implementation_variant_registry())
            t.push_back({v.name, SettingKind::text, v.fallback().c_str(), {}, v.values, nullptr, v.why, true});
        return t;
    }();
    return table;
}

const std::vector<RunSetting>& run_settings() {
    static const std::vector<RunSetting> table = {
        {"steps", whole_from(1), nullptr, "100", true, "steps to record"},
        {"warmup", whole_from(0), "0", "10", true, "steps run first and not recorded"},
        {"snapshot_every", whole_from(0), "0", "0", false, "write an HDF5 snapshot every K steps (0: none)"},
        {"repetitions", whole_from(1), "1", nullptr, true, "runs of each configuration, each its own row"},
        {"max_repetitions", whole_from(1), "16", nullptr, false,
         "most repetitions of a configuration that `run --baseline` runs while its verdict is inconclusive"},
        // 0, outside the range, is "absent" (as fixed_dt's): the run is then `steps` steps long.
        {"end_time", number_above(0), "0", "0", true,
         "stop at the first step whose simulated time reaches T seconds (steps is then a cap)"},
    };
    return table;
}

std::string quoted_list(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i)
        out += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + ("\"" + items[i] + "\"");
    return out;
}

std::string list_element(const std::string& text, std::size_t& at) {
    while (at < text.size() && (text[at] == ',' || text[at] == ' ')) ++at;
    const std::size_t start = at;
    while (at < text.size() && text[at] != ',' && text[at] != ' ') ++at;
    return text.substr(start, at - start);
}

}  // namespace

const std::vector<SolverSetting>& solver_settings_table() { return settings(); }

const SolverSetting* find_solver_setting(const std::string& key) {
    for (const auto& s : settings())
        if (key == s.key) return &s;
    return nullptr;
}

const std::vector<std::string>& solver_setting_keys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k;
        for (const auto& s : settings()) k.emplace_back(s.key);
        return k;
    }();
    return keys;
}

bool is_solver_setting(const std::string& key) { return find_solver_setting(key) != nullptr; }

SettingKind solver_setting_kind(const std::string& key) {
    const SolverSetting* s = find_solver_setting(key);
    if (!s) throw InputError("unknown solver setting '" + key + "'");
    return s->kind;
}

std::string setting_flag(const SolverSetting& s) {
    std::string flag = s.key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    const bool off_switch = s.kind == SettingKind::boolean && std::string(s.fallback) == "true";
    return (off_switch ? "--no-" : "--") + flag;
}

std::string describe_allowed(const SolverSetting& s) {
    switch (s.kind) {
    case SettingKind::boolean: return "true or false";
    case SettingKind::integer_list: return "a list, each " + s.range.describe();
    case SettingKind::integer:
    case SettingKind::number: return s.range.describe();
    case SettingKind::text: break;
    }
    return s.choices.empty() ? std::string() : "one of " + quoted_list(s.choices);  // else: its own check's words
}

std::string check_solver_value(const std::string& key, const std::string& text, const std::string& given_name) {
    const SolverSetting* info = find_solver_setting(key);
    if (!info) throw InputError("unknown solver setting '" + key + "'");
    const std::string name = given_name.empty() ? key : given_name;
    switch (info->kind) {
    case SettingKind::text:
        if (!info->choices.empty() &&
            std::find(info->choices.begin(), info->choices.end(), text) == info->choices.end())
            throw InputError(name + ": '" + text + "' is not " + describe_allowed(*info));
        if (info->check_text) {
            try {
                info->check_text(text);
            } catch (const InputError& e) {
                throw InputError(name + ": " + e.what());
            }
        }
        return text;
    case SettingKind::boolean: {
        std::string t = text;
        std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (t == "true" || t == "1" || t == "yes" || t == "on") return "true";
        if (t == "false" || t == "0" || t == "no" || t == "off") return "false";
        throw InputError(name + ": '" + text + "' is not true or false");
    }
    case SettingKind::integer_list: {
        std::string out;
        for (std::size_t at = 0; at < text.size();) {
            const std::string item = list_element(text, at);
            if (!item.empty()) out += (out.empty() ? "" : ",") + info->range.check(name, item);
        }
        return out;
    }
    case SettingKind::integer:
    case SettingKind::number: break;
    }
    return info->range.check(name, text);
}

SettingMap complete_solver_settings(const SettingMap& given) {
    SettingMap out;
    for (const auto& s : settings()) {
        const auto it = given.find(s.key);
        out[s.key] = it != given.end() ? it->second : s.fallback;
    }
    return out;
}

SolverOptions to_solver_options(const SettingMap& c, bool gpu_available) {
    SolverOptions o;
    const std::string& backend = c.at("backend");
    o.backend = backend == "cuda" || (backend == "auto" && gpu_available) ? BackendKind::cuda : BackendKind::host;
    o.subdomains = std::stoi(c.at("devices"));
    o.device = std::stoi(c.at("gpu"));
    const std::string& map = c.at("device_map");
    for (std::size_t at = 0; at < map.size();) {
        const std::string item = list_element(map, at);
        if (!item.empty()) o.device_map.push_back(std::stoi(item));
    }
    if (!o.device_map.empty() && int(o.device_map.size()) != o.subdomains)
        throw InputError("device_map: '" + map + "' names " + std::to_string(o.device_map.size()) + " GPU(s) for " +
                         std::to_string(o.subdomains) + " subdomain(s) (allowed: one GPU per subdomain)");
    o.balancer = c.at("balancer");
    o.share_gpus = c.at("share_gpus") == "true";
    o.transport = parse_transport(c.at("transport"));
    o.gpu_direct = c.at("gpu_direct") == "true";
    o.overlap = c.at("overlap") == "true";
    o.search.cells_per_support = std::stoi(c.at("cells_per_support"));
    o.search.merge = c.at("merge") == "true";
    o.search.verlet = c.at("verlet") == "true";
    o.search.skin = std::stod(c.at("skin"));
    o.search.rebuild_every = std::stoi(c.at("rebuild_every"));
    o.fixed_dt = std::stod(c.at("fixed_dt"));
    o.cfl = std::stod(c.at("cfl"));
    o.diffusion = c.at("diffusion") == "true";
    for (const ImplementationVariant& v : implementation_variant_registry())
        set_implementation_variant(o.variants, v.name, c.at(v.name));
    return o;
}

const std::vector<RunSetting>& run_settings_table() { return run_settings(); }

const RunSetting* find_run_setting(const std::string& key) {
    for (const auto& s : run_settings())
        if (key == s.key) return &s;
    return nullptr;
}

const RunSetting& run_setting(const std::string& key) {
    const RunSetting* s = find_run_setting(key);
    if (!s) throw std::logic_error("no run setting '" + key + "'");
    return *s;
}

std::string setting_flag(const RunSetting& s) {
    std::string flag = s.key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    return "--" + flag;
}

long check_run_value(const std::string& key, const std::string& text, const std::string& name) {
    return std::stol(run_setting(key).range.check(name, text));
}

double check_run_number(const std::string& key, const std::string& text, const std::string& name) {
    return std::stod(run_setting(key).range.check(name, text));
}

const char* build_precision() {
#ifdef SPH_DOUBLE
    return "float64";
#else
    return "float32";
#endif
}

std::string filename_safe(const std::string& text) {
    std::string out = text;
    for (char& c : out)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '-';
    return out;
}

}  // namespace sph

#include "solver_settings.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "core/error.hpp"
#include "multi/load_balancer.hpp"
#include "multi/particle_transport.hpp"

namespace sph {
namespace {

struct SettingInfo {
    const char* key;
    SettingKind kind;
    const char* fallback;
    double lo, hi;  // numbers: the allowed range (lo excluded for fixed_dt, cfl and skin)
};

const std::vector<SettingInfo>& settings() {
    static const std::vector<SettingInfo> table = {
        {"backend", SettingKind::text, "auto", 0, 0},
        {"devices", SettingKind::integer, "1", 1, 1024},
        {"gpu", SettingKind::integer, "0", 0, 1023},  // GPU of a one-subdomain run ("device" names the GPU in runs.csv)
        {"balancer", SettingKind::text, "none", 0, 0},
        {"transport", SettingKind::text, "auto", 0, 0},
        {"cells_per_support", SettingKind::integer, "1", 1, 4},
        {"merge", SettingKind::boolean, "false", 0, 0},
        {"verlet", SettingKind::boolean, "false", 0, 0},
        {"skin", SettingKind::number, "0.1", 0, 10},
        {"rebuild_every", SettingKind::integer, "0", 0, 1e9},
        {"fixed_dt", SettingKind::number, "0", 0, 1e3},
        {"cfl", SettingKind::number, "0", 0, 1},
        {"diffusion", SettingKind::boolean, "true", 0, 0},
        {"precision", SettingKind::text, build_precision(), 0, 0},  // a build property: see build_precision()
    };
    return table;
}

const SettingInfo* find_setting(const std::string& key) {
    for (const auto& s : settings())
        if (key == s.key) return &s;
    return nullptr;
}

double parse_number(const std::string& key, const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError("'" + key + "' must be a number, got '" + text + "'");
    return v;
}

}  // namespace

const std::vector<std::string>& solver_setting_keys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k;
        for (const auto& s : settings()) k.emplace_back(s.key);
        return k;
    }();
    return keys;
}

bool is_solver_setting(const std::string& key) { return find_setting(key) != nullptr; }

SettingKind solver_setting_kind(const std::string& key) {
    const SettingInfo* s = find_setting(key);
    if (!s) throw InputError("unknown solver setting '" + key + "'");
    return s->kind;
}

std::string check_solver_value(const std::string& key, const std::string& text) {
    const SettingInfo* info = find_setting(key);
    if (!info) throw InputError("unknown solver setting '" + key + "'");
    if (key == "backend") {
        if (text != "auto" && text != "cuda" && text != "host")
            throw InputError("'backend' must be \"auto\", \"cuda\" or \"host\", got '" + text + "'");
        return text;
    }
    if (key == "precision") {
        if (text != "float32" && text != "float64")
            throw InputError("'precision' must be \"float32\" or \"float64\", got '" + text + "'");
        return text;
    }
    if (key == "balancer") {
        make_balancer(text);  // throws InputError naming the allowed forms
        return text;
    }
    if (key == "transport") {
        parse_transport(text);  // throws InputError naming the allowed values
        return text;
    }
    if (info->kind == SettingKind::boolean) {
        std::string t = text;
        std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (t == "true" || t == "1" || t == "yes" || t == "on") return "true";
        if (t == "false" || t == "0" || t == "no" || t == "off") return "false";
        throw InputError("'" + key + "' must be true or false, got '" + text + "'");
    }
    if (info->kind == SettingKind::integer) {
        long long v = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || end != text.data() + text.size())
            throw InputError("'" + key + "' must be an integer, got '" + text + "'");
        if (double(v) < info->lo || double(v) > info->hi)
            throw InputError("'" + key + "' = " + text + " is outside its range " + format_number(info->lo) + " to " +
                             format_number(info->hi));
        return std::to_string(v);
    }
    const double v = parse_number(key, text);
    if (!(v > info->lo && v <= info->hi))
        throw InputError("'" + key + "' = " + text + " is outside its range (" + format_number(info->lo) + ", " +
                         format_number(info->hi) + "]");
    return format_number(v);
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
    o.balancer = c.at("balancer");
    o.transport = parse_transport(c.at("transport"));
    o.search.cells_per_support = std::stoi(c.at("cells_per_support"));
    o.search.merge = c.at("merge") == "true";
    o.search.verlet = c.at("verlet") == "true";
    o.search.skin = std::stod(c.at("skin"));
    o.search.rebuild_every = std::stoi(c.at("rebuild_every"));
    o.fixed_dt = std::stod(c.at("fixed_dt"));
    o.cfl = std::stod(c.at("cfl"));
    o.diffusion = c.at("diffusion") == "true";
    return o;
}

const char* build_precision() {
#ifdef SPH_DOUBLE
    return "float64";
#else
    return "float32";
#endif
}

std::string format_number(double value) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    if (ec != std::errc()) return "nan";
    return std::string(buf, end);
}

std::string filename_safe(const std::string& text) {
    std::string out = text;
    for (char& c : out)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '-';
    return out;
}

}  // namespace sph

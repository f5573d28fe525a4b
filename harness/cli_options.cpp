#include "cli_options.hpp"

#include <filesystem>

#include "core/error.hpp"

namespace sph {

namespace fs = std::filesystem;

CLI::Validator in_range(const ValueRange& range) {
    // CLI11 puts the flag's name in front of what a check returns.
    return CLI::Validator(
        [range](std::string& text) -> std::string {
            try {
                text = range.check("", text);
                return "";
            } catch (const InputError& e) {
                const std::string m = e.what();
                return m.rfind(": ", 0) == 0 ? m.substr(2) : m;
            }
        },
        range.describe());
}

CLI::Validator setting_validator(const std::string& key) {
    const SolverSetting* s = find_solver_setting(key);
    if (!s) throw std::logic_error("no solver setting '" + key + "'");
    // The table's own check, so that the message is the spec's; CLI11 puts the flag in front.
    return CLI::Validator(
        [key](std::string& text) -> std::string {
            try {
                text = check_solver_value(key, text, key);
                return "";
            } catch (const InputError& e) {
                const std::string m = e.what();
                return m.rfind(key + ": ", 0) == 0 ? m.substr(key.size() + 2) : m;
            }
        },
        describe_allowed(*s));
}

void add_solver_options(CLI::App& cmd, SettingMap& given) {
    for (const SolverSetting& s : solver_settings_table()) {
        if (!s.on_command_line) continue;
        const std::string key = s.key, flag = setting_flag(s);
        if (s.kind == SettingKind::boolean) {
            const bool off_switch = std::string(s.fallback) == "true";
            const std::string value = off_switch ? "false" : "true";
            cmd.add_flag_callback(flag, [&given, key, value] { given[key] = value; },
                                  off_switch ? "without " + std::string(s.help) : std::string(s.help));
            continue;
        }
        // A default outside the range (fixed_dt's and cfl's 0) means "absent"; the help says what then.
        bool default_shown = *s.fallback != '\0';
        try {
            check_solver_value(key, s.fallback);
        } catch (const InputError&) {
            default_shown = false;
        }
        const std::string help = std::string(s.help) + (default_shown ? " (default: " + std::string(s.fallback) + ")" : "");
        const char* type = s.kind == SettingKind::integer || s.kind == SettingKind::integer_list ? "INT"
                           : s.kind == SettingKind::number                                         ? "FLOAT"
                                                                                                   : "TEXT";
        const CLI::Validator check = setting_validator(key);
        if (s.kind == SettingKind::integer_list) {
            cmd.add_option_function<std::vector<std::string>>(
                   flag,
                   [&given, key](const std::vector<std::string>& items) {
                       std::string joined;
                       for (const auto& i : items) joined += (joined.empty() ? "" : ",") + i;
                       given[key] = joined;
                   },
                   help)
                ->check(check)
                ->type_name(type);
        } else {
            cmd.add_option_function<std::string>(
                   flag, [&given, key](const std::string& v) { given[key] = v; }, help)
                ->check(check)
                ->type_name(type);
        }
    }
}

std::string backend_name(BackendKind b) { return b == BackendKind::cuda ? "cuda" : "host"; }

SolverOptions solver_options(const SettingMap& given) {
    const SettingMap complete = complete_solver_settings(given);
    const bool cuda_wanted = complete.at("backend") != "host";
    // The device map's GPUs are checked by the simulation, rank by rank (each sees its node's).
    return to_solver_options(complete, cuda_wanted && cuda_backend_available());
}

void check_output_folder(const std::string& flag, const std::string& path) {
    std::error_code ec;
    fs::path p = fs::path(path).lexically_normal();
    if (p.empty()) p = ".";
    for (fs::path at = p; !at.empty(); at = at.parent_path()) {
        if (fs::exists(at, ec)) {
            if (fs::is_directory(at, ec)) return;
            if (at == p) throw InputError(flag + ": '" + path + "' is a file, not a folder for results");
            throw InputError(flag + ": '" + path + "' cannot be a folder for results, because '" + at.string() +
                             "' is a file");
        }
        if (at == at.parent_path()) break;
    }
}

std::map<std::string, std::string> parse_settings(const std::vector<std::string>& pairs) {
    std::map<std::string, std::string> out;
    for (const auto& p : pairs) {
        const auto eq = p.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("--set: '" + p + "' is not of the form key=value");
        out[p.substr(0, eq)] = p.substr(eq + 1);
    }
    return out;
}

}  // namespace sph

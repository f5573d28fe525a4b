// Strict parsing of experiment specs (TOML). Every message starts with "file:line:" so that a
// mistake in a long spec is found at once.
#include "experiment_spec.hpp"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

// Header-only: the binary then needs no libtomlplusplus.so where it runs.
#undef TOML_HEADER_ONLY
#define TOML_HEADER_ONLY 1
#include <toml++/toml.h>

#include "case_file.hpp"
#include "toml_type_name.hpp"
#include "core/error.hpp"
#include "gauge_tables.hpp"
#include "scenes/scene.hpp"

namespace sph {
namespace {

const std::vector<std::string> record_items = {"summary", "steps", "snapshots", "counters-every-step"};

class SpecReader {
public:
    explicit SpecReader(std::string path) : path_(std::move(path)) {}

    // A case file named in the spec, relative to the spec's folder (as a path inside a file
    // means), so that the spec runs from any working directory; absolute paths stay as given.
    std::string case_scene_in_spec(const std::string& scene) const {
        const std::filesystem::path file = case_file_of(scene);
        if (file.is_absolute()) return scene;
        const std::filesystem::path folder = std::filesystem::path(path_).parent_path();
        return case_scene_prefix + (folder / file).lexically_normal().string();
    }

    [[noreturn]] void fail(const toml::source_region& where, const std::string& message) const {
        fail_at(long(where.begin.line), message);
    }
    [[noreturn]] void fail_at(long line, const std::string& message) const {
        throw InputError(path_ + (line > 0 ? ":" + std::to_string(line) : "") + ": " + message);
    }

    // Refuses any key of `table` that is not in `known`.
    void check_keys(const toml::table& table, const std::vector<std::string>& known, const std::string& where) const {
        for (const auto& [key, node] : table) {
            if (std::find(known.begin(), known.end(), std::string(key.str())) != known.end()) continue;
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            fail(key.source(), "unknown key '" + std::string(key.str()) + "' in " + where + " (known: " + list + ")");
        }
    }

    std::string text(const toml::table& t, const std::string& key, bool required, const std::string& fallback,
                     const std::string& where) const {
        const toml::node* n = t.get(key);
        if (!n) {
            if (required) fail(t.source(), "missing required key '" + key + "' in " + where);
            return fallback;
        }
        if (!n->is_string()) fail(n->source(), "'" + key + "' must be a string, not " + toml_type_name(*n));
        return n->value<std::string>().value();
    }

    long long integer(const toml::table& t, const std::string& key, bool required, long long fallback,
                      long long lo, const std::string& where) const {
        const ValueRange range = whole_from(double(lo));
        return integer(t, key, required, fallback, lo > LLONG_MIN ? &range : nullptr, where);
    }
    // range nullptr: any integer.
    long long integer(const toml::table& t, const std::string& key, bool required, long long fallback,
                      const ValueRange* range, const std::string& where) const {
        const toml::node* n = t.get(key);
        if (!n) {
            if (required) fail(t.source(), "missing required key '" + key + "' in " + where);
            return fallback;
        }
        if (!n->is_integer()) fail(n->source(), "'" + key + "' must be an integer, not " + toml_type_name(*n));
        const long long v = n->value<long long>().value();
        if (range) check_value(*n, key, *range, std::to_string(v));
        return v;
    }
    // A run setting (solver_settings.hpp) at the top level: its range and default from the table.
    long run_count(const toml::table& t, const std::string& key, const std::string& where) const {
        const RunSetting& s = run_setting(key);
        return long(integer(t, key, s.fallback == nullptr, s.fallback ? std::stoll(s.fallback) : 0, &s.range, where));
    }

    // A run setting that takes any number (end_time): its range from the table; absent: 0.
    double run_number(const toml::table& t, const std::string& key) const {
        const toml::node* n = t.get(key);
        if (!n) return 0;
        if (!n->is_number()) fail(n->source(), "'" + key + "' must be a number, not " + toml_type_name(*n));
        const double v = n->value<double>().value();
        check_value(*n, key, run_setting(key).range, format_number(v));
        return v;
    }

    double number(const toml::table& t, const std::string& key, double fallback, double lo_exclusive) const {
        const toml::node* n = t.get(key);
        if (!n) return fallback;
        if (!n->is_number()) fail(n->source(), "'" + key + "' must be a number, not " + toml_type_name(*n));
        const double v = n->value<double>().value();
        check_value(*n, key, number_above(lo_exclusive), format_number(v));
        return v;
    }

    // The refusal of a value out of its range, worded as the command line words it.
    void check_value(const toml::node& n, const std::string& key, const ValueRange& range, const std::string& text) const {
        try {
            range.check(key, text);
        } catch (const InputError& e) {
            fail(n.source(), e.what());
        }
    }

    // A solver setting as validated text.
    std::string solver_value(const std::string& key, const toml::node& n) const {
        std::string text;
        switch (solver_setting_kind(key)) {
        case SettingKind::text:
            if (!n.is_string()) fail(n.source(), "'" + key + "' must be a string, not " + toml_type_name(n));
            text = n.value<std::string>().value();
            break;
        case SettingKind::integer:
            if (!n.is_integer()) fail(n.source(), "'" + key + "' must be an integer, not " + toml_type_name(n));
            text = std::to_string(n.value<long long>().value());
            break;
        case SettingKind::number:
            if (!n.is_number()) fail(n.source(), "'" + key + "' must be a number, not " + toml_type_name(n));
            text = format_number(n.value<double>().value());
            break;
        case SettingKind::boolean:
            if (!n.is_boolean()) fail(n.source(), "'" + key + "' must be true or false, not " + toml_type_name(n));
            text = n.value<bool>().value() ? "true" : "false";
            break;
        case SettingKind::integer_list: {
            const toml::array* items = n.as_array();
            if (!items) fail(n.source(), "'" + key + "' must be an array of integers, not " + toml_type_name(n));
            for (const auto& item : *items) {
                if (!item.is_integer()) fail(item.source(), "'" + key + "' must be an array of integers, and " + toml_type_name(item) + " is not one");
                text += (text.empty() ? "" : ",") + std::to_string(item.value<long long>().value());
            }
            break;
        }
        }
        try {
            return check_solver_value(key, text);
        } catch (const InputError& e) {
            fail(n.source(), e.what());
        }
    }

    SettingMap solver_table(const toml::node& n, const std::string& where) const {
        const toml::table* t = n.as_table();
        if (!t) fail(n.source(), "'" + where + "' must be a table, not " + toml_type_name(n));
        check_keys(*t, solver_setting_keys(), where);
        SettingMap out;
        for (const auto& [key, value] : *t) out[std::string(key.str())] = solver_value(std::string(key.str()), value);
        return out;
    }

    std::string scene_value(const std::string& key, const toml::node& n) const {
        if (n.is_integer()) return std::to_string(n.value<long long>().value());
        if (n.is_floating_point()) return format_number(n.value<double>().value());
        if (n.is_string()) return n.value<std::string>().value();
        fail(n.source(), "scene option '" + key + "' must be an integer, a float or a string, not " + toml_type_name(n));
    }


private:
    std::string path_;
};

// [validation] or a run's validation = { ... }: the scene must have a metric.
ValidationRequest read_validation(const SpecReader& r, const toml::node& node, const std::string& where) {
    const toml::table* t = node.as_table();
    if (!t) r.fail(node.source(), "'" + where + "' must be a table, not " + toml_type_name(node));
    r.check_keys(*t, {"every", "end_time"}, where);
    if (!t->get("every")) r.fail(t->source(), "missing required key 'every' in " + where);
    ValidationRequest v;
    v.every = r.number(*t, "every", 0.0, 0.0);
    v.end_time = r.number(*t, "end_time", 0.0, 0.0);
    return v;
}

RunSpec read_run(const SpecReader& r, const toml::node& node, std::size_t index) {
    const toml::table* t = node.as_table();
    if (!t) r.fail(node.source(), "each [[runs]] entry must be a table");
    r.check_keys(*t, {"scene", "label", "steps", "end_time", "set", "solver", "validation"}, "[[runs]]");
    RunSpec run;
    run.line = long(t->source().begin.line);
    if (t->get("steps")) run.steps = long(r.integer(*t, "steps", true, 0, &run_setting("steps").range, "[[runs]]"));
    if (t->get("end_time")) run.end_time = r.run_number(*t, "end_time");
    run.scene = r.text(*t, "scene", true, "", "[[runs]]");
    const auto& scenes = scene_catalogue();
    if (is_case_scene(run.scene)) {
        run.scene = r.case_scene_in_spec(run.scene);
        try {
            load_case_file(case_file_of(run.scene));  // refused here, before any run
        } catch (const InputError& e) {
            r.fail(t->get("scene")->source(), "scene '" + run.scene + "': " + e.what());
        }
    } else if (std::none_of(scenes.begin(), scenes.end(), [&](const SceneInfo& s) { return s.name == run.scene; })) {
        std::string known;
        for (const auto& s : scenes) known += (known.empty() ? "" : ", ") + s.name;
        r.fail(t->get("scene")->source(), "unknown scene '" + run.scene + "' (known: " + known + ", or case:FILE)");
    }
    run.label = filename_safe(r.text(*t, "label", false, scene_stem(run.scene) + "-" + std::to_string(index + 1), "[[runs]]"));
    if (const toml::node* set = t->get("set")) {
        const toml::table* st = set->as_table();
        if (!st) r.fail(set->source(), "'set' must be a table of scene options, not " + toml_type_name(*set));
        for (const auto& [key, value] : *st) run.scene_options[std::string(key.str())] = r.scene_value(std::string(key.str()), value);
    }
    if (const toml::node* solver = t->get("solver")) run.solver = r.solver_table(*solver, "solver of [[runs]]");
    if (const toml::node* v = t->get("validation")) run.validation = read_validation(r, *v, "validation of [[runs]]");
    return run;
}

void read_sweep_axis(const SpecReader& r, const std::string& key, const toml::node& node, ExperimentSpec& spec) {
    const bool scene_key = key.rfind("set.", 0) == 0 && key.size() > 4;
    if (!scene_key && !is_solver_setting(key)) {
        std::string known;
        for (const auto& k : solver_setting_keys()) known += k + ", ";
        r.fail(node.source(), "unknown key '" + key + "' in [sweep] (known: " + known + "set.<scene option>)");
    }
    const toml::array* values = node.as_array();
    if (!values) r.fail(node.source(), "'" + key + "' in [sweep] must be an array, not " + toml_type_name(node));
    if (values->empty()) r.fail(node.source(), "'" + key + "' in [sweep] is an empty array");
    SweepAxis axis{key, {}};
    for (const auto& v : *values)
        axis.values.push_back(scene_key ? r.scene_value(key.substr(4), v) : r.solver_value(key, v));
    spec.sweep.push_back(std::move(axis));
}

}  // namespace

bool ExperimentSpec::records(const std::string& item) const {
    return std::find(record.begin(), record.end(), item) != record.end();
}

ExperimentSpec load_spec(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw InputError("experiment spec '" + path + "' does not exist");
    const SpecReader r(path);
    toml::table doc;
    try {
        doc = toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        r.fail(e.source(), "TOML syntax error: " + std::string(e.description()));
    }
    r.check_keys(doc,
                 {"name", "reproduces", "description", "steps", "end_time", "warmup", "repetitions", "max_repetitions", "seed", "record",
                  "snapshot_every", "solver", "runs", "sweep", "host", "stability", "validation", "blow_up", "gauges"},
                 "the top level");
    ExperimentSpec spec;
    spec.path = path;
    const std::string top = "the top level";
    spec.name = r.text(doc, "name", true, "", top);
    if (spec.name.empty() || filename_safe(spec.name) != spec.name)
        r.fail(doc.get("name")->source(), "'name' must be a non-empty file name of letters, digits, '.', '_' or '-'");
    spec.reproduces = r.text(doc, "reproduces", true, "", top);
    spec.description = r.text(doc, "description", false, "", top);
    spec.end_time = r.run_number(doc, "end_time");
    // With an end time, steps is a cap, and no cap is given by leaving it out; so is it where
    // every run gives its own steps or end time (checked with the runs below).
    if (doc.get("steps")) spec.steps = r.run_count(doc, "steps", top);
    spec.warmup = r.run_count(doc, "warmup", top);
    spec.repetitions = r.run_count(doc, "repetitions", top);
    spec.max_repetitions = r.run_count(doc, "max_repetitions", top);
    spec.seed = r.integer(doc, "seed", false, 1, LLONG_MIN, top);
    spec.snapshot_every = r.run_count(doc, "snapshot_every", top);

    if (const toml::node* rec = doc.get("record")) {
        const toml::array* items = rec->as_array();
        if (!items) r.fail(rec->source(), "'record' must be an array of strings, not " + toml_type_name(*rec));
        spec.record.clear();
        for (const auto& item : *items) {
            const auto s = item.value<std::string>();
            if (!item.is_string() || std::find(record_items.begin(), record_items.end(), *s) == record_items.end())
                r.fail(item.source(), "unknown item in 'record' (allowed: summary, steps, snapshots, counters-every-step)");
            spec.record.push_back(*s);
        }
    }
    if (spec.snapshot_every > 0 && !spec.records("snapshots"))
        r.fail(doc.get("snapshot_every")->source(), "'snapshot_every' needs \"snapshots\" in 'record'");
    if (spec.records("snapshots") && spec.snapshot_every == 0)
        r.fail(doc.get("record")->source(), "\"snapshots\" in 'record' needs 'snapshot_every' > 0");

    if (const toml::node* solver = doc.get("solver")) spec.solver = r.solver_table(*solver, "[solver]");

    const std::string blow_up = r.text(doc, "blow_up", false, "fail", top);
    if (blow_up != "fail" && blow_up != "record")
        r.fail(doc.get("blow_up")->source(), "'blow_up' must be \"fail\" or \"record\", got '" + blow_up + "'");
    spec.record_blow_ups = blow_up == "record";
    if (const toml::node* v = doc.get("validation")) spec.validation = read_validation(r, *v, "[validation]");

    if (const toml::node* gauges = doc.get("gauges")) spec.gauges = read_gauge_tables(*gauges, path, "[[gauges]]");

    const toml::node* runs = doc.get("runs");
    if (!runs) r.fail_at(0, "missing required key 'runs' (one or more [[runs]] tables)");
    const toml::array* run_list = runs->as_array();
    if (!run_list || run_list->empty()) r.fail(runs->source(), "'runs' must be one or more [[runs]] tables");
    for (std::size_t i = 0; i < run_list->size(); ++i) {
        RunSpec run = read_run(r, *run_list->get(i), i);
        for (const auto& other : spec.runs)
            if (other.label == run.label)
                r.fail_at(run.line, "label '" + run.label + "' is used twice (also at line " +
                                        std::to_string(other.line) + ")");
        if ((run.validation || spec.validation) && !find_validation_metric(run.scene))
            r.fail_at(run.line, "validation asked for, but scene '" + run.scene + "' has no validation metric (scenes with one: " +
                                    scenes_with_validation() + ")");
        if (spec.steps == 0 && spec.end_time <= 0 && !run.steps && !run.end_time)
            r.fail_at(0, "missing required key 'steps' (or 'end_time') at the top level: the run at line " +
                             std::to_string(run.line) + " gives neither of its own");
        spec.runs.push_back(std::move(run));
    }

    if (const toml::node* sweep = doc.get("sweep")) {
        const toml::table* t = sweep->as_table();
        if (!t) r.fail(sweep->source(), "'sweep' must be a table, not " + toml_type_name(*sweep));
        for (const auto& [key, node] : *t) {
            const std::string k(key.str());
            if (k == "set" && node.is_table()) {  // set.particles = [...] written as a dotted key
                for (const auto& [option, values] : *node.as_table())
                    read_sweep_axis(r, "set." + std::string(option.str()), values, spec);
            } else {
                read_sweep_axis(r, k, node, spec);
            }
        }
        std::sort(spec.sweep.begin(), spec.sweep.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
    }

    if (const toml::node* host = doc.get("host")) {
        const toml::table* t = host->as_table();
        if (!t) r.fail(host->source(), "'host' must be a table, not " + toml_type_name(*host));
        r.check_keys(*t, {"scale", "steps", "end_time"}, "[host]");
        HostReduction h;
        h.scale = r.number(*t, "scale", 1.0, 0.0);
        h.steps = long(r.integer(*t, "steps", false, 0, 1, "[host]"));
        h.end_time = r.run_number(*t, "end_time");
        spec.host = h;
    }

    if (const toml::node* st = doc.get("stability")) {
        const toml::table* t = st->as_table();
        if (!t) r.fail(st->source(), "'stability' must be a table, not " + toml_type_name(*st));
        const std::string where = "[stability]";
        r.check_keys(*t, {"probe", "time", "cfl_low", "cfl_high", "bisections", "sample_every"}, where);
        StabilityStudy s;
        s.probe = r.text(*t, "probe", true, "", where);
        if (s.probe != "cfl-limit" && s.probe != "energy")
            r.fail(t->get("probe")->source(), "'probe' must be \"cfl-limit\" or \"energy\", not '" + s.probe + "'");
        s.time = t->get("time") ? r.number(*t, "time", 0, 0.0) : 0.0;
        if (s.time > 0 && spec.end_time > 0)
            r.fail(t->get("time")->source(), "'time' in [stability] and 'end_time' at the top level both set the "
                                             "simulated time to reach; give one");
        s.cfl_low = r.number(*t, "cfl_low", s.cfl_low, 0.0);
        s.cfl_high = r.number(*t, "cfl_high", s.cfl_high, 0.0);
        if (s.cfl_high <= s.cfl_low) r.fail(t->source(), "'cfl_high' must be greater than 'cfl_low'");
        s.bisections = long(r.integer(*t, "bisections", false, s.bisections, 1, where));
        s.sample_every = long(r.integer(*t, "sample_every", false, s.sample_every, 1, where));
        spec.stability = s;
    }
    return spec;
}

std::string fnv1a_hex(const std::string& bytes) {
    std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64 offset basis
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ULL;  // FNV prime
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

std::string spec_hash(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "'");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return fnv1a_hex(bytes.str());
}

}  // namespace sph

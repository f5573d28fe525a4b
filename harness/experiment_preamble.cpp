#include "experiment_preamble.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

#include "backend/subdomain.hpp"
#include "cli_options.hpp"
#include "case_file.hpp"
#include "core/error.hpp"
#include "experiment_runner.hpp"
#include "result_freshness.hpp"

namespace sph {

void add_end_time_option(CLI::App& cmd, ExperimentArgs& args, const std::string& help) {
    const RunSetting& s = run_setting("end_time");
    cmd.add_option_function<std::string>(
           setting_flag(s), [&args](const std::string& t) { args.settings.push_back("end_time=" + t); },
           help + "; the same as --set end_time=T")
        ->check(in_range(s.range))
        ->type_name("FLOAT");
}

Experiment load_experiment(const ExperimentArgs& a, ExperimentKind kind) {
    Experiment e;
    e.spec = load_spec(a.spec);
    e.dir = experiment_dir(a.out, e.spec);
    check_output_folder("--out", e.dir);
    const ExperimentSpec& spec = e.spec;
    if (kind == ExperimentKind::runs && spec.stability)
        throw InputError("experiment spec '" + spec.path + "' is a stability study ([stability]); run it with `sphbench stability " +
                         spec.path + "`");
    if (kind == ExperimentKind::stability && !spec.stability)
        throw InputError("experiment spec '" + spec.path + "' has no [stability] table; run it with `sphbench run`");
    ExpandOptions ex;
    for (const auto& [k, v] : parse_settings(a.settings)) ex.overrides.emplace_back(k, v);
    ex.scale = a.scale;
    ex.backend = a.backend;
    ex.gpu_available = cuda_backend_available();
    e.runs = expand(spec, ex);
    if (!a.only.empty()) {
        for (const auto& id : a.only)
            if (std::none_of(e.runs.begin(), e.runs.end(), [&](const PlannedRun& r) { return r.run_id == id; }))
                throw InputError("--only names run '" + id + "', which " + spec.path + " does not have");
        std::erase_if(e.runs, [&](const PlannedRun& r) {
            return std::find(a.only.begin(), a.only.end(), r.run_id) == a.only.end();
        });
    }
    e.reduced = std::any_of(e.runs.begin(), e.runs.end(), [](const PlannedRun& r) { return r.reduced_scale; });
    std::set<std::string> backends;
    for (const auto& r : e.runs) backends.insert(r.solver.backend == BackendKind::cuda ? "cuda" : "host");
    e.backend = backends.size() == 1 ? *backends.begin() : "mixed";
    return e;
}

std::vector<std::string> override_arguments(const ExperimentArgs& a) {
    std::vector<std::string> args;
    for (const auto& kv : a.settings) args.insert(args.end(), {"--set", kv});
    if (a.scale != 1.0) args.insert(args.end(), {"--scale", format_number(a.scale)});
    if (!a.backend.empty()) args.insert(args.end(), {"--backend", a.backend});
    return args;
}

std::string overrides_text(const ExperimentArgs& a) {
    std::vector<std::string> args = override_arguments(a);
    for (const auto& id : a.only) args.insert(args.end(), {"--only", id});
    std::string s;
    for (const auto& w : args) s += (s.empty() ? "" : " ") + w;
    return s.empty() ? "none" : s;
}

// The case files the runs build their scenes from, each once as "FILE=HASH" in run order, or
// "none": a case file edited (its geometry, its gauges) makes the results out of date as an
// edited spec does (result_freshness.hpp).
std::string case_hashes_text(const Experiment& e) {
    std::string s;
    std::vector<std::string> seen;
    for (const PlannedRun& r : e.runs) {
        if (!is_case_scene(r.scene)) continue;
        const std::string file = case_file_of(r.scene);
        if (std::find(seen.begin(), seen.end(), file) != seen.end()) continue;
        seen.push_back(file);
        s += (s.empty() ? "" : " ") + file + "=" + spec_hash(file);
    }
    return s.empty() ? "none" : s;
}

Metadata experiment_metadata(const Experiment& e, const ExperimentArgs& a, const CommandContext& ctx) {
    const ExperimentSpec& spec = e.spec;
    std::vector<ImplementationVariants> variants;
    for (const PlannedRun& r : e.runs) variants.push_back(r.solver.variants);
    Metadata meta = provenance(e.backend, e.backend == "host" ? "host" : cuda_device_summary(),
                               describe_implementation_variants(variants), command_line_of(ctx.argc, ctx.argv));
    for (auto& kv : Metadata{{"experiment", spec.name},
                             {"reproduces", spec.reproduces},
                             {"spec", spec.path},
                             {"spec_hash", spec_hash(spec.path)},
                             {"case_hashes", case_hashes_text(e)},
                             {"binary_hash", binary_hash()},
                             {"overrides", overrides_text(a)},
                             {"seed", std::to_string(spec.seed)},
                             {"scale", format_number(e.runs.front().scale)},
                             {"reduced_scale", e.reduced ? "yes" : "no"}})
        meta.push_back(std::move(kv));
    return meta;
}

bool skip_up_to_date(const Experiment& e, const ExperimentArgs& a, const std::string& table, const Metadata& metadata) {
    if (a.force || !results_up_to_date(table, metadata)) return false;
    std::printf("%s: up to date (use --force to run again)\n", e.spec.name.c_str());
    return true;
}

}  // namespace sph

#include "precision_delegate.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "core/error.hpp"
#include "csv_table.hpp"

namespace sph {

DelegatedRuns plan_delegation(const std::vector<PlannedRun>& runs, const std::string& float64_binary) {
    DelegatedRuns d;
    d.binary = float64_binary;
    for (const auto& r : runs) {
        const std::string& wanted = r.solver_settings.at("precision");
        if (wanted == build_precision()) continue;
        if (wanted == "float32")
            throw InputError("run '" + r.run_id + "' asks for precision float32, but this sphbench is a float64 build; "
                             "run the spec with the float32 build");
        if (float64_binary.empty())
            throw InputError("run '" + r.run_id + "' asks for precision float64, but this sphbench is a float32 build; "
                             "give --float64-binary PATH (`make accuracy` builds build-f64/harness/sphbench)");
        d.run_ids.push_back(r.run_id);
    }
    if (!d.run_ids.empty() && !std::filesystem::is_regular_file(float64_binary))
        throw InputError("--float64-binary '" + float64_binary + "' does not exist");
    return d;
}

std::map<std::string, std::vector<std::string>> run_delegated(const DelegatedRuns& d, const ExperimentSpec& spec,
                                                              const std::string& experiment_dir,
                                                              const std::vector<std::string>& columns, bool quiet) {
    namespace fs = std::filesystem;
    const std::string out = (fs::path(experiment_dir) / "float64").string();
    std::vector<std::string> args = {d.binary, "run", spec.path, "--out", out, "--force"};
    if (quiet) args.emplace_back("--quiet");
    for (const auto& id : d.run_ids) args.insert(args.end(), {"--only", id});
    args.insert(args.end(), d.arguments.begin(), d.arguments.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid < 0) throw RunError("cannot start the float64 sphbench '" + d.binary + "'");
    if (pid == 0) {
        execv(d.binary.c_str(), argv.data());
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw RunError("the float64 runs failed (" + d.binary + " exited with status " +
                       std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");

    const CsvTable child = read_csv((fs::path(out) / spec.name / "runs.csv").string());
    const std::string prefix = "float64/" + spec.name + "/";
    std::map<std::string, std::vector<std::string>> rows;
    for (std::size_t i = 0; i < child.rows.size(); ++i) {
        std::vector<std::string> row;
        for (const auto& c : columns) {
            std::string v = child.cell(i, c);
            if (!v.empty() && (c == "steps_file" || c == "validation_file")) v = prefix + v;
            row.push_back(v);
        }
        rows[child.cell(i, "run_id")] = row;
    }
    for (const auto& id : d.run_ids)
        if (!rows.count(id)) throw RunError("the float64 sphbench wrote no row for run '" + id + "'");
    return rows;
}

}  // namespace sph

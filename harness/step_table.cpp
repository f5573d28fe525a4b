#include "step_table.hpp"

#include <algorithm>
#include <cmath>

#include "io/csv_writer.hpp"

namespace sph {
namespace {

std::string f(double v) { return CsvWriter::fmt(v); }

template <class T>
std::string whole(T v) {
    return std::to_string(v);
}

// "a;b;c": one value per subdomain.
template <class Value>
std::string per_subdomain(const std::vector<Value>& values, std::string (*text)(const Value&)) {
    std::string out;
    for (std::size_t d = 0; d < values.size(); ++d) out += (d ? ";" : "") + text(values[d]);
    return out;
}

ColumnTable<StepRow> make_step_table() {
    using R = const StepRow&;
    ColumnTable<StepRow> t;
    t.add("step", [](R r) { return whole(r.record.step); })
        .add("time", [](R r) { return f(r.record.time); })
        .add("dt", [](R r) { return f(r.record.dt); })
        .add("fluid", [](R r) { return whole(r.record.stats.fluid_count); })
        .add("boundary", [](R r) { return whole(r.boundary); })
        .add("out_of_domain", [](R r) { return whole(r.record.out_of_domain); })
        .add("kinetic_energy", [](R r) { return f(r.record.stats.kinetic_energy); })
        .add("max_speed", [](R r) { return f(std::sqrt(double(r.record.stats.max_speed2))); })
        .add("min_density", [](R r) { return f(r.record.stats.min_density); })
        .add("max_density", [](R r) { return f(r.record.stats.max_density); });
    for (std::size_t p = 0; p < phase_count; ++p)
        t.add(std::string(phase_names[p]) + "_ms", [p](R r) { return f(r.record.phase_ms[p]); });
    // update_ms is the paper's real wall time: the slowest subdomain's forces plus integration;
    // update_ideal_ms is the mean over subdomains (paper Fig. 5 and 8).
    t.add("update_ms", [](R r) { return f(r.record.update_ms()); })
        .add("update_ideal_ms", [](R r) { return f(r.record.update_ideal_ms()); })
        .add("step_ms", [](R r) { return f(r.record.step_ms()); })
        .add("wall_ms", [](R r) { return f(r.record.wall_ms); })
        .add("subdomains", [](R r) { return whole(std::max<std::size_t>(1, r.record.subdomain_ms.size())); })
        .add("slices_moved", [](R r) { return whole(r.record.slices_moved); })
        .add("particles_migrated", [](R r) { return whole(r.record.exchange.particles_migrated); })
        .add("ghosts_sent", [](R r) { return whole(r.record.exchange.ghosts_sent); })
        .add("bytes_exchanged", [](R r) { return whole(r.record.exchange.bytes); })
        .add("subdomain_update_ms",
             [](R r) {
                 return per_subdomain<PhaseTimes>(r.record.subdomain_ms,
                                                  [](const PhaseTimes& t) { return f(update_time(t)); });
             })
        .add("subdomain_particles",
             [](R r) {
                 return per_subdomain<std::size_t>(r.record.subdomain_particles,
                                                   [](const std::size_t& n) { return std::to_string(n); });
             })
        // The exchange's copies as CUDA events time them; they run under the inner update
        // (paper 5.3), so they are not part of step_ms.
        .add("transfer_ms", [](R r) { return f(r.record.transfer_ms); });
    return t;
}

}  // namespace

const ColumnTable<StepRow>& step_table() {
    static const ColumnTable<StepRow> table = make_step_table();
    return table;
}

std::vector<std::string> step_csv_columns() { return step_table().names(); }

std::vector<std::string> step_csv_row(const StepRecord& r, std::size_t boundary) {
    return step_table().cells(StepRow{r, boundary});
}

}  // namespace sph

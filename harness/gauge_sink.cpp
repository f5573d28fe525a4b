#include "gauge_sink.hpp"

#include "io/csv_writer.hpp"

namespace sph {

std::vector<std::string> GaugeSink::columns() const {
    std::vector<std::string> cols = {"time"};
    for (const Gauge& g : gauges_)
        for (const std::string& c : gauge_columns(g)) cols.push_back(c);
    return cols;
}

void GaugeSink::begin(Simulation& sim) {
    next_.assign(gauges_.size(), sim.time());
    sample(sim);
}

void GaugeSink::sample(Simulation& sim) {
    // Due: the sample time was reached (to a millionth of the interval: sums of dt round).
    std::vector<Gauge> due;
    std::vector<bool> is_due(gauges_.size(), false);
    const double t = sim.time();
    for (std::size_t g = 0; g < gauges_.size(); ++g) {
        if (t < next_[g] - 1e-6 * gauges_[g].every) continue;
        is_due[g] = true;
        due.push_back(gauges_[g]);
        while (next_[g] <= t + 1e-6 * gauges_[g].every) next_[g] += gauges_[g].every;
    }
    if (due.empty()) return;
    const std::vector<double> values = sim.measure_gauges(due);
    std::vector<std::string> row = {CsvWriter::fmt(t)};
    std::size_t k = 0;
    for (std::size_t g = 0; g < gauges_.size(); ++g) {
        const std::size_t n = gauge_columns(gauges_[g]).size();
        for (std::size_t c = 0; c < n; ++c) row.push_back(is_due[g] ? CsvWriter::fmt(values[k + c]) : "");
        if (is_due[g]) k += n;
    }
    rows_.push_back(std::move(row));
}

void GaugeSink::end(Simulation&) {
    if (path_.empty()) return;
    Metadata meta = metadata_;
    for (const Gauge& g : gauges_) {
        std::string where;
        switch (g.kind) {
        case GaugeKind::pressure:
        case GaugeKind::velocity:
            where = "x=" + CsvWriter::fmt(g.x) + " y=" + CsvWriter::fmt(g.y) + " z=" + CsvWriter::fmt(g.z);
            break;
        case GaugeKind::water_level: where = "x=" + CsvWriter::fmt(g.x) + " y=" + CsvWriter::fmt(g.y); break;
        case GaugeKind::max_height:
            where = "x=" + CsvWriter::fmt(g.x) + " y=" + CsvWriter::fmt(g.y) + " radius=" + CsvWriter::fmt(g.radius);
            break;
        case GaugeKind::force: where = "body=" + g.body; break;
        }
        meta.emplace_back("gauge." + g.name, std::string(gauge_kind_name(g.kind)) + " " + where + " every=" +
                                                 CsvWriter::fmt(g.every));
    }
    CsvWriter csv(path_, columns(), meta);
    for (const auto& r : rows_) csv.row(r);
    csv.commit();
}

}  // namespace sph

#include "step_csv_sink.hpp"

#include "io/csv_writer.hpp"
#include "step_table.hpp"

namespace sph {

void StepCsvSink::end(Simulation&) {
    CsvWriter csv(path_, step_csv_columns(), metadata_);
    for (const StepRecord& r : steps_.records()) csv.row(step_csv_row(r, boundary_));
    csv.commit();
}

}  // namespace sph

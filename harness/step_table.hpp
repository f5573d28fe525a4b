#pragma once
// The per-step table (<run>_steps.csv): one row per recorded step, its columns declared once
// in step_table.cpp beside the values that fill them.
#include <cstddef>
#include <string>
#include <vector>

#include "column_table.hpp"
#include "simulation.hpp"

namespace sph {

struct StepRow {
    const StepRecord& record;
    std::size_t boundary;  // the scene's boundary particles (a column of every row)
};

const ColumnTable<StepRow>& step_table();

// The table's column names and one row's cells, for the CSV writer and its readers.
std::vector<std::string> step_csv_columns();
std::vector<std::string> step_csv_row(const StepRecord& r, std::size_t boundary);

}  // namespace sph

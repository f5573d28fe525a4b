#pragma once
// Reads back what CsvWriter writes: the "# key: value" metadata block, the header and the rows
// (RFC 4180 quoting). Used to skip experiments that are up to date and to compare results.
#include <optional>
#include <string>
#include <vector>

#include "provenance.hpp"

namespace sph {

struct CsvTable {
    std::string path;
    Metadata metadata;
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;

    std::optional<std::string> meta(const std::string& key) const;
    // Index of a column, or -1.
    int column(const std::string& name) const;
    // The cell of `row` in column `name`, or "" when the table has no such column.
    const std::string& cell(std::size_t row, const std::string& name) const;
};

// Throws InputError naming the file when it cannot be read or a row has the wrong width.
CsvTable read_csv(const std::string& path);
// Only the metadata block: cheap on large files.
Metadata read_csv_metadata(const std::string& path);

}  // namespace sph

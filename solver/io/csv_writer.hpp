#pragma once
// CSV output with provenance. Layout:
//   # key: value          (one line per metadata pair, in the order given)
//   col_a,col_b,...       (header)
//   1.5,2,...             (rows)
// Readers skip the comment block with e.g. pandas.read_csv(path, comment='#').
// Cells are quoted per RFC 4180; the file appears under its final name only on commit().
#include <string>
#include <utility>
#include <vector>

#include "io/atomic_file.hpp"

namespace sph {

class CsvWriter {
public:
    // Writes the metadata block and header at once (into the temporary file).
    // Throws RunError if `columns` is empty or the file cannot be created.
    CsvWriter(std::string path, std::vector<std::string> columns,
              std::vector<std::pair<std::string, std::string>> metadata = {});

    // Appends one row. Throws RunError, naming the file, if cells.size() differs
    // from the number of columns or the writer was already committed.
    void row(const std::vector<std::string>& cells);

    // Shortest text that parses back to exactly `value` ("0.1", "1e-300", "nan", "inf").
    static std::string fmt(double value);

    // Moves the finished file into place. Without it, nothing appears at `path`.
    void commit();

    const std::string& path() const { return file_.path(); }

private:
    void write_line(const std::vector<std::string>& cells);

    AtomicFile file_;
    std::size_t ncolumns_;
};

}  // namespace sph

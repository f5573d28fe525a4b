#include "io/csv_writer.hpp"

#include <charconv>
#include <ostream>
#include <system_error>

#include "core/error.hpp"

namespace sph {

namespace {

// RFC 4180: quote a field that holds a comma, quote or line break, doubling inner quotes.
// '#' is quoted too, so a cell can never be mistaken for the start of a comment line.
void write_cell(std::ostream& out, const std::string& cell) {
    if (cell.find_first_of(",\"\r\n#") == std::string::npos) {
        out << cell;
        return;
    }
    out << '"';
    for (char c : cell) {
        if (c == '"') out << '"';
        out << c;
    }
    out << '"';
}

// A comment must stay on one line, or the rest would be parsed as data.
std::string one_line(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        if (c == '\n')
            out += "\\n";
        else if (c == '\r')
            out += "\\r";
        else
            out += c;
    }
    return out;
}

}  // namespace

CsvWriter::CsvWriter(std::string path, std::vector<std::string> columns,
                     std::vector<std::pair<std::string, std::string>> metadata)
    : file_(std::move(path)), ncolumns_(columns.size()) {
    if (columns.empty()) throw RunError("CSV file '" + file_.path() + "' has no columns");
    std::ostream& out = file_.stream();
    for (const auto& [key, value] : metadata) out << "# " << one_line(key) << ": " << one_line(value) << '\n';
    write_line(columns);
}

void CsvWriter::row(const std::vector<std::string>& cells) {
    if (file_.committed()) throw RunError("CSV file '" + file_.path() + "' was already committed");
    if (cells.size() != ncolumns_)
        throw RunError("CSV file '" + file_.path() + "': row has " + std::to_string(cells.size()) +
                       " cells but the header has " + std::to_string(ncolumns_) + " columns");
    write_line(cells);
}

void CsvWriter::write_line(const std::vector<std::string>& cells) {
    std::ostream& out = file_.stream();
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (i) out << ',';
        write_cell(out, cells[i]);
    }
    out << '\n';
}

std::string CsvWriter::fmt(double value) {
    // std::to_chars without a precision gives the shortest round-trip form, independent
    // of the C locale (printf would write "0,1" under a German locale).
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    if (ec != std::errc()) throw RunError("cannot format a number for CSV output");
    return std::string(buf, end);
}

void CsvWriter::commit() { file_.commit(); }

}  // namespace sph

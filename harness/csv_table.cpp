#include "csv_table.hpp"

#include <fstream>

#include "core/error.hpp"

namespace sph {
namespace {

// Splits one record; a quoted cell may hold commas, doubled quotes and line breaks, so more
// lines are pulled from `in` while a quote is open.
bool read_record(std::istream& in, std::string line, std::vector<std::string>& cells) {
    cells.assign(1, "");
    bool quoted = false;
    for (;;) {
        for (std::size_t i = 0; i < line.size(); ++i) {
            const char c = line[i];
            if (quoted) {
                if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
                else if (c == '"') quoted = false;
                else cells.back() += c;
            } else if (c == '"') {
                quoted = true;
            } else if (c == ',') {
                cells.emplace_back();
            } else if (c != '\r') {
                cells.back() += c;
            }
        }
        if (!quoted) return true;
        if (!std::getline(in, line)) return false;
        cells.back() += '\n';
    }
}

bool metadata_line(const std::string& line, Metadata& meta) {
    if (line.rfind("# ", 0) != 0) return false;
    const auto colon = line.find(": ", 2);
    if (colon == std::string::npos) meta.emplace_back(line.substr(2), "");
    else meta.emplace_back(line.substr(2, colon - 2), line.substr(colon + 2));
    return true;
}

}  // namespace

std::optional<std::string> CsvTable::meta(const std::string& key) const {
    for (const auto& [k, v] : metadata)
        if (k == key) return v;
    return std::nullopt;
}

int CsvTable::column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == name) return int(i);
    return -1;
}

const std::string& CsvTable::cell(std::size_t row, const std::string& name) const {
    static const std::string empty;
    const int c = column(name);
    return c < 0 ? empty : rows.at(row).at(std::size_t(c));
}

CsvTable read_csv(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read CSV file '" + path + "'");
    CsvTable t;
    t.path = path;
    std::string line;
    std::vector<std::string> cells;
    long line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        if (t.columns.empty() && metadata_line(line, t.metadata)) continue;
        if (line.empty() || line == "\r") continue;
        if (!read_record(in, line, cells))
            throw InputError("CSV file '" + path + "' ends inside a quoted cell begun at line " + std::to_string(line_no));
        if (t.columns.empty()) {
            t.columns = cells;
            continue;
        }
        if (cells.size() != t.columns.size())
            throw InputError("CSV file '" + path + "' line " + std::to_string(line_no) + " has " +
                             std::to_string(cells.size()) + " cells but the header has " +
                             std::to_string(t.columns.size()));
        t.rows.push_back(cells);
    }
    if (t.columns.empty()) throw InputError("CSV file '" + path + "' has no header line");
    return t;
}

Metadata read_csv_metadata(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read CSV file '" + path + "'");
    Metadata meta;
    std::string line;
    while (std::getline(in, line) && metadata_line(line, meta)) {
    }
    return meta;
}

}  // namespace sph

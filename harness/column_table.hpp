#pragma once
// A CSV layout declared once: each column's name beside the function that fills its cell
// (nvbench's printers are the model), so that the header and the rows come from one list and
// cannot drift apart.
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace sph {

template <class Row>
class ColumnTable {
public:
    using Cell = std::function<std::string(const Row&)>;

    ColumnTable& add(std::string name, Cell cell) {
        columns_.emplace_back(std::move(name), std::move(cell));
        return *this;
    }
    // Another table's columns after these (a shared prefix, then each layout's own).
    template <class Other, class Project>
    ColumnTable& append(const ColumnTable<Other>& other, Project project) {
        for (const auto& [name, cell] : other.columns())
            add(name, [cell, project](const Row& r) { return cell(project(r)); });
        return *this;
    }

    std::vector<std::string> names() const {
        std::vector<std::string> out;
        out.reserve(columns_.size());
        for (const auto& c : columns_) out.push_back(c.first);
        return out;
    }
    std::vector<std::string> cells(const Row& row) const {
        std::vector<std::string> out;
        out.reserve(columns_.size());
        for (const auto& c : columns_) out.push_back(c.second(row));
        return out;
    }
    std::size_t size() const { return columns_.size(); }
    const std::vector<std::pair<std::string, Cell>>& columns() const { return columns_; }

private:
    std::vector<std::pair<std::string, Cell>> columns_;
};

}  // namespace sph

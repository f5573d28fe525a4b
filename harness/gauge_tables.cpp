// Header-only toml++, as in the spec and case readers: the binary then needs no libtomlplusplus.so.
#undef TOML_HEADER_ONLY
#define TOML_HEADER_ONLY 1
#include "gauge_tables.hpp"

#include <map>
#include <utility>

#include "core/error.hpp"
#include "gauge_options.hpp"
#include "io/csv_writer.hpp"
#include "toml_type_name.hpp"

namespace sph {

namespace {

// "FILE:LINE", or "FILE" where toml++ knows no line.
std::string at(const std::string& file, const toml::source_region& where) {
    return file + (where.begin.line > 0 ? ":" + std::to_string(where.begin.line) : "");
}

[[noreturn]] void fail(const std::string& file, const toml::source_region& where, const std::string& message) {
    throw InputError(at(file, where) + ": " + message);
}

// One table: its kind and its other keys as text, as --gauge gives them, to make_gauge.
Gauge gauge_from_table(const toml::table& t, const std::string& file, const std::string& where) {
    const toml::node* kind = t.get("kind");
    if (!kind) fail(file, t.source(), "missing required key 'kind' in " + where);
    if (!kind->is_string()) fail(file, kind->source(), "'kind' must be a string, not " + toml_type_name(*kind));
    std::map<std::string, std::string> keys;
    for (const auto& [key, value] : t) {
        const std::string k(key.str());
        if (k == "kind") continue;
        if (value.is_string()) keys[k] = *value.value<std::string>();
        else if (value.is_integer()) keys[k] = std::to_string(*value.value<long long>());
        else if (value.is_floating_point()) keys[k] = CsvWriter::fmt(*value.value<double>());
        else fail(file, value.source(), where + ": '" + k + "' must be a number or a string, not " + toml_type_name(value));
    }
    try {
        return make_gauge(*kind->value<std::string>(), keys, where);
    } catch (const InputError& e) {
        fail(file, t.source(), e.what());
    }
}

}  // namespace

std::vector<Gauge> read_gauge_tables(const toml::node& node, const std::string& file, const std::string& table) {
    const toml::array* list = node.as_array();
    if (!list) fail(file, node.source(), "'gauges' must be " + table + " tables, not " + toml_type_name(node));
    std::vector<Gauge> gauges;
    std::map<std::string, toml::source_region> named;  // each given name and where it was given
    for (std::size_t i = 0; i < list->size(); ++i) {
        const toml::node& item = *list->get(i);
        const toml::table* t = item.as_table();
        if (!t) fail(file, item.source(), "each " + table + " entry must be a table");
        Gauge g = gauge_from_table(*t, file, table + " " + std::to_string(i + 1));
        if (!g.name.empty()) {
            const toml::source_region& here = t->get("name")->source();
            const auto [earlier, first] = named.emplace(g.name, here);
            if (!first)
                fail(file, here, "gauge name '" + g.name + "' is used twice (also at " + at(file, earlier->second) + ")");
        }
        gauges.push_back(std::move(g));
    }
    // A given name that an unnamed gauge would also be given (a "pressure1" beside an unnamed
    // pressure gauge) is refused here too, before any run.
    std::vector<Gauge> as_named = gauges;
    try {
        name_gauges(as_named);
    } catch (const InputError& e) {
        fail(file, node.source(), e.what());
    }
    return gauges;
}

}  // namespace sph

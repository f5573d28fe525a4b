#include "result_freshness.hpp"

#include <filesystem>

#include "core/error.hpp"
#include "csv_table.hpp"

namespace sph {

bool results_up_to_date(const std::string& csv, const Metadata& now) {
    if (!std::filesystem::exists(csv)) return false;
    Metadata old;
    try {
        old = read_csv_metadata(csv);
    } catch (const InputError&) {
        return false;  // unreadable: run again rather than refuse
    }
    auto value = [](const Metadata& m, const std::string& key) {
        for (const auto& [k, v] : m)
            if (k == key) return v;
        return std::string("\x01missing");
    };
    for (const char* key : {"spec_hash", "case_hashes", "binary_hash", "overrides", "backend", "float64_binary_hash"})
        if (value(old, key) != value(now, key)) return false;
    return true;
}

}  // namespace sph

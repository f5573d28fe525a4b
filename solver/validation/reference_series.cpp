#include "validation/reference_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace sph {

double ReferenceSeries::at(double v) const {
    if (x.empty() || !(v >= x.front() && v <= x.back())) return std::numeric_limits<double>::quiet_NaN();
    std::size_t i = 1;
    while (i < x.size() - 1 && x[i] < v) ++i;
    if (x.size() == 1) return y[0];
    const double w = (v - x[i - 1]) / (x[i] - x[i - 1]);
    return y[i - 1] + w * (y[i] - y[i - 1]);
}

ReferenceSeries read_reference_series(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read the reference data '" + path + "'");
    ReferenceSeries s;
    s.path = path;
    std::string line;
    bool header = false;
    long number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty() || line[0] == '#') continue;
        if (!header) {  // the column names
            header = true;
            continue;
        }
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream cells(line);
        double a = 0, b = 0;
        if (!(cells >> a >> b) || !std::isfinite(a) || !std::isfinite(b))
            throw InputError(path + ":" + std::to_string(number) + ": expected two numbers");
        if (!s.x.empty() && !(a > s.x.back()))
            throw InputError(path + ":" + std::to_string(number) + ": the first column must increase");
        s.x.push_back(a);
        s.y.push_back(b);
    }
    if (s.x.size() < 2) throw InputError("the reference data '" + path + "' has fewer than two points");
    return s;
}

std::string find_validation_data(const std::string& file_name) {
    namespace fs = std::filesystem;
    std::vector<fs::path> places;
    if (const char* dir = std::getenv("SPH_VALIDATION_DATA")) places.emplace_back(dir);
#ifdef SPH_SOURCE_DIR
    places.emplace_back(fs::path(SPH_SOURCE_DIR) / "validation" / "data");
#endif
    places.emplace_back(fs::path("validation") / "data");
    std::string tried;
    for (const auto& p : places) {
        const fs::path f = p / file_name;
        if (fs::is_regular_file(f)) return f.string();
        tried += (tried.empty() ? "" : ", ") + p.string();
    }
    throw InputError("reference data '" + file_name + "' not found (looked in " + tried +
                     "; set SPH_VALIDATION_DATA to its folder)");
}

}  // namespace sph

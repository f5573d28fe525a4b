#pragma once
// Published reference data as (x, y) series read from validation/data/*.csv ("# " comment
// lines naming the source, a header, then two numeric columns), with linear interpolation.
#include <string>
#include <vector>

namespace sph {

struct ReferenceSeries {
    std::string path;
    std::vector<double> x, y;  // x increasing

    // Linear interpolation; NaN outside [x.front(), x.back()] (no extrapolation of a measurement).
    double at(double x_value) const;
};

// Reads a reference file. Throws InputError naming the file when it is missing or malformed.
ReferenceSeries read_reference_series(const std::string& path);

// Where reference data lives: $SPH_VALIDATION_DATA, else validation/data in the source tree,
// else validation/data under the working directory (a checkout copied to another machine).
// Throws InputError listing the places tried when `file_name` is in none of them.
std::string find_validation_data(const std::string& file_name);

}  // namespace sph

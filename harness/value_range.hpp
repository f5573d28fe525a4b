#pragma once
// The allowed values of a numeric setting and the one way their text is checked. The spec
// keys, the command-line flags and `--set` all check through here, so a refusal reads the same
// wherever the value came from: "NAME: 'abc' is not a number (allowed: ...)".
#include <limits>
#include <string>

namespace sph {

struct ValueRange {
    bool whole = false;  // integers only
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();  // always included when finite
    bool lo_open = false;                                 // lo itself excluded

    // As a user would write it: "a whole number from 1 to 4", "a number greater than 0".
    std::string describe() const;
    // The value's normal form ("2.50" -> "2.5", "+3" -> "3"); throws InputError
    // "NAME: TEXT is out of range (allowed: ...)" or "NAME: 'TEXT' is not a number (allowed: ...)".
    std::string check(const std::string& name, const std::string& text) const;
};

ValueRange whole_from(double lo, double hi = std::numeric_limits<double>::infinity());
ValueRange number_above(double lo, double hi = std::numeric_limits<double>::infinity());

// Shortest text that reads back as the same double.
std::string format_number(double value);

}  // namespace sph

#include "value_range.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "core/error.hpp"

namespace sph {

ValueRange whole_from(double lo, double hi) { return ValueRange{true, lo, hi, false}; }
ValueRange number_above(double lo, double hi) { return ValueRange{false, lo, hi, true}; }

namespace {

// Whole numbers in full ("1000000000", not "1e+09"): a range is read by people.
std::string plain(double v) {
    if (std::fabs(v) < 1e15 && v == std::floor(v)) return std::to_string((long long)v);
    return format_number(v);
}

}  // namespace

std::string ValueRange::describe() const {
    const std::string what = whole ? "a whole number" : "a number";
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (has_lo && has_hi && !lo_open) return what + " from " + plain(lo) + " to " + plain(hi);
    if (has_lo && has_hi) return what + " greater than " + plain(lo) + " and at most " + plain(hi);
    if (has_lo) return what + (lo_open ? " greater than " : " of at least ") + plain(lo);
    if (has_hi) return what + " of at most " + plain(hi);
    return what;
}

std::string ValueRange::check(const std::string& name, const std::string& text) const {
    const std::string allowed = " (allowed: " + describe() + ")";
    double v = 0;
    std::string normal;
    long long whole_value = 0;
    const char* first = text.data() + (text.size() > 1 && text[0] == '+' ? 1 : 0);  // from_chars refuses '+'
    const auto [end, ec] = std::from_chars(first, text.data() + text.size(), whole_value);
    if (ec == std::errc() && end == text.data() + text.size() && end != first) {
        v = double(whole_value);
        normal = std::to_string(whole_value);
    } else {
        char* stop = nullptr;
        v = std::strtod(text.c_str(), &stop);
        if (text.empty() || *stop != '\0' || !std::isfinite(v))
            throw InputError(name + ": '" + text + "' is not a number" + allowed);
        const bool integral = v == std::floor(v) && std::fabs(v) < 9e15;  // "1e6" is whole too
        if (whole && !integral) throw InputError(name + ": " + text + " is not a whole number" + allowed);
        normal = whole ? std::to_string((long long)v) : format_number(v);
    }
    const bool below = lo_open ? !(v > lo) : v < lo;
    if (below || v > hi) throw InputError(name + ": " + text + " is out of range" + allowed);
    return normal;
}

std::string format_number(double value) {
    char buf[64];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    if (ec != std::errc()) return "nan";
    return std::string(buf, end);
}

}  // namespace sph

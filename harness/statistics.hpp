#pragma once
// Robust summaries of repeated timings: median, quartiles and minimum.
#include <vector>

namespace sph {

struct Summary {
    double median = 0, q1 = 0, q3 = 0, min = 0, max = 0, mean = 0;
    std::size_t n = 0;
};

Summary summarize(std::vector<double> values);
double quantile_sorted(const std::vector<double>& sorted, double q);  // linear interpolation

}  // namespace sph

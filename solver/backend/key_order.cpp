#include "backend/key_order.hpp"

#include <algorithm>

namespace sph {

// After an exchange the particles form a few ascending runs of (cell, id): the kept range,
// the out-of-domain tail and one run per sender (each sent its range sorted). Merging those
// runs replaces the full sort there (issue 13 item 4). After a step's moves there are many
// short runs, and a full sort is cheaper. Keys are unique (ids are), so both give the same
// order, bit for bit.
void order_by_keys(const std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& order) {
    constexpr std::size_t most_runs_merged = 32;
    const std::size_t n = keys.size();
    auto by_key = [&](std::uint32_t x, std::uint32_t y) { return keys[x] < keys[y]; };
    std::vector<std::size_t> bounds{0};  // run r is [bounds[r], bounds[r + 1])
    for (std::size_t i = 1; i < n && bounds.size() <= most_runs_merged; ++i)
        if (keys[i] < keys[i - 1]) bounds.push_back(i);
    if (bounds.size() > most_runs_merged) {
        std::sort(order.begin(), order.end(), by_key);
        return;
    }
    bounds.push_back(n);
    while (bounds.size() > 2) {  // merge neighbouring runs pairwise until one is left
        std::vector<std::size_t> merged;
        const std::size_t runs = bounds.size() - 1;
        for (std::size_t r = 0; r < runs; r += 2) {
            merged.push_back(bounds[r]);
            if (r + 1 < runs)
                std::inplace_merge(order.begin() + bounds[r], order.begin() + bounds[r + 1], order.begin() + bounds[r + 2],
                                   by_key);
        }
        merged.push_back(n);
        bounds.swap(merged);
    }
}

}  // namespace sph

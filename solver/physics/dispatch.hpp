#pragma once
// Picks the compile-time specialisation of the force loop once per run, from the scene's
// features: kernel, density diffusion on or off, and search strategy. Terms a scene does
// not use are compiled out rather than branched over in the inner loop.
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/smoothing_kernels.hpp"
#include "neighbours/cell_search.hpp"

namespace sph {

template <class T>
struct type_tag {
    using type = T;
};

template <class F>
void dispatch_search(const SearchOptions& s, F&& f) {
    switch (s.cells_per_support * 2 + (s.merge ? 1 : 0)) {
        case 2: return f(type_tag<CellSearch<1, false>>{});
        case 3: return f(type_tag<CellSearch<1, true>>{});
        case 4: return f(type_tag<CellSearch<2, false>>{});
        case 5: return f(type_tag<CellSearch<2, true>>{});
        case 6: return f(type_tag<CellSearch<3, false>>{});
        case 7: return f(type_tag<CellSearch<3, true>>{});
        case 8: return f(type_tag<CellSearch<4, false>>{});
        case 9: return f(type_tag<CellSearch<4, true>>{});
    }
    throw std::invalid_argument("cells per support must be 1 to 4, got " + std::to_string(s.cells_per_support));
}

// f(kernel_tag, diffusion) with diffusion a std::bool_constant.
template <class F>
void dispatch_kernel(KernelType kernel, bool diffusion, F&& f) {
    auto with_kernel = [&](auto k) {
        if (diffusion) f(k, std::true_type{});
        else f(k, std::false_type{});
    };
    if (kernel == KernelType::wendland) with_kernel(type_tag<WendlandC2>{});
    else with_kernel(type_tag<CubicSpline>{});
}

// f(kernel_tag, search_tag, diffusion).
template <class F>
void dispatch_physics(KernelType kernel, bool diffusion, const SearchOptions& s, F&& f) {
    dispatch_search(s, [&](auto search) { dispatch_kernel(kernel, diffusion, [&](auto k, auto d) { f(k, search, d); }); });
}

}  // namespace sph

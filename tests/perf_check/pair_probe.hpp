#pragma once
// The real pair body (physics/interaction.hpp) behind stand-ins for the smoothing kernel and the
// search, so that the perf-check tests can inject a known cost into it without touching the
// solver: these stand-ins are compiled only into the probe programs of tests/perf_check.
//   SPH_PROBE_INJECT_DIVISION    one more IEEE division per pair (in grad_factor)
//   SPH_PROBE_INJECT_EXTRA_PAIRS every 10th candidate is summed a second time: 10% more pair work
//   SPH_PROBE_MIN_BLOCKS         __launch_bounds__ minimum blocks per SM of the probe kernels;
//                                16 blocks of 128 threads leave 32 registers a thread: a spill
#include "core/smoothing_kernels.hpp"
#include "neighbours/cell_search.hpp"
#include "physics/interaction.hpp"

namespace sph::probe {

template <class Base>
struct KernelWithExtraDivision : Base {
    SPH_HD explicit KernelWithExtraDivision(real h) : Base(h) {}
    // The value is meaningless; what matters is that the compiler cannot fold the division
    // into a multiplication (the divisor depends on r).
    SPH_HD real grad_factor(real r) const { return Base::grad_factor(r) / (r + this->inv_h); }
};

template <class Base>
struct SearchWithRepeatedPairs : Base {
    template <class Visit>
    SPH_HD static void visit(const GridView& g, const std::uint32_t* cell_start, const std::uint32_t* cell, int3v c,
                             Visit&& visit) {
        unsigned visited = 0;
        Base::visit(g, cell_start, cell, c, [&](std::uint32_t j, int dx, int dy, int dz) {
            visit(j, dx, dy, dz);
            if (++visited == 10) {
                visited = 0;
                // j through a volatile: with the pair loop inlined (SPH_HD_INLINE), g++ would
                // otherwise reuse the first visit's loads and arithmetic for the second.
                volatile std::uint32_t again = j;
                visit(again, dx, dy, dz);
            }
        });
    }
};

#ifdef SPH_PROBE_INJECT_DIVISION
using ProbeKernel = KernelWithExtraDivision<WendlandC2>;
#else
using ProbeKernel = WendlandC2;
#endif
#ifdef SPH_PROBE_INJECT_EXTRA_PAIRS
using ProbeSearch = SearchWithRepeatedPairs<CellSearch<2, false>>;
#else
using ProbeSearch = CellSearch<2, false>;
#endif
#ifndef SPH_PROBE_MIN_BLOCKS
#define SPH_PROBE_MIN_BLOCKS 1
#endif

}  // namespace sph::probe

#include "neighbours/grid.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace sph {

Grid make_grid(const double lo[3], const double hi[3], double support, int cells_per_support, const bool periodic[3]) {
    Grid g;
    g.cells_per_support = cells_per_support;
    const double cs = support / cells_per_support;
    int* dims[3] = {&g.view.nx, &g.view.ny, &g.view.nz};
    real* sizes[3] = {&g.view.cell_size.x, &g.view.cell_size.y, &g.view.cell_size.z};
    bool* flags[3] = {&g.view.periodic_x, &g.view.periodic_y, &g.view.periodic_z};
    for (int a = 0; a < 3; ++a) {
        g.origin[a] = lo[a];
        const double length = hi[a] - lo[a];
        const bool wraps = periodic != nullptr && periodic[a];
        *flags[a] = wraps;
        if (wraps && length < cs * (1 - 1e-9)) {
            // One cell would be shorter than support / n, and the stencil would miss images.
            static const char* axis[] = {"x", "y", "z"};
            std::ostringstream m;
            m << "the periodic " << axis[a] << " axis is " << length << " m long, shorter than one cell (support / "
              << cells_per_support << " = " << cs << " m); make the periodic box longer along " << axis[a]
              << " or use more cells per support";
            throw InputError(m.str());
        }
        if (wraps) {
            // A whole number of cells spans the period; rounding down keeps them >= support / n.
            // (The 1e-9 keeps a period of exactly k cells from losing one to rounding.)
            *dims[a] = std::max(1, int(std::floor(length / cs + 1e-9)));
            *sizes[a] = real(length / *dims[a]);
        } else {
            *dims[a] = std::max(1, int(std::ceil(length / cs)));
            *sizes[a] = real(cs);
        }
    }
    return g;
}

}  // namespace sph

#include "neighbours/grid.hpp"

#include <algorithm>
#include <cmath>

namespace sph {

Grid make_grid(const double lo[3], const double hi[3], double support, int cells_per_support) {
    Grid g;
    g.cells_per_support = cells_per_support;
    const double cs = support / cells_per_support;
    g.view.cell_size = real(cs);
    int* dims[3] = {&g.view.nx, &g.view.ny, &g.view.nz};
    for (int a = 0; a < 3; ++a) {
        g.origin[a] = lo[a];
        *dims[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / cs)));
    }
    return g;
}

}  // namespace sph

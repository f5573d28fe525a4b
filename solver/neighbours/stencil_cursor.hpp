#pragma once
// The stencil of CellSearch<N, Merge> as a cursor: the same candidates in the same order as
// CellSearch::visit, but one at a time, so that a loop can stop between two candidates and go
// on later. The GPU force loop needs that: it gathers each thread's neighbours into a small
// buffer until the buffer is full, then evaluates the pair body with every lane of the warp
// busy, then resumes the search where it stopped (backend/cuda_force_loop.cuh).
//
// A cursor opened with fluid_only (for a boundary particle, which interacts with fluid only)
// walks the stencil cell by cell and starts each cell at its first fluid particle:
// fluid_begin[c] in [cell_start[c], cell_start[c + 1]]. That relies on the sort order:
// particles sorted by (cell, id), and boundary particles have the lowest ids (scene.hpp), so
// each cell holds its boundary particles first. A wall with no water within reach then reads
// two indices per stencil cell and no particle at all.
//
// Open and x/y-periodic grids only: a periodic z axis splits merged runs into pieces
// (CellSearch::visit_periodic_column), and the callers use the plain visit there.
#include "neighbours/cell_search.hpp"

namespace sph {

template <class Search>
struct StencilCursor {
    static constexpr int N = Search::n;
    static constexpr int W = 2 * N + 1;

    // The candidate the cursor stands on, and its cell offset from the particle's cell.
    std::uint32_t j = 0;
    int dx = 0, dy = 0, dz = 0;

    SPH_HD StencilCursor(const GridView& g, const std::uint32_t* cell_start, const std::uint32_t* fluid_begin,
                         const std::uint32_t* cell, int3v c, bool fluid_only)
        : g_(g), cell_start_(cell_start), fluid_begin_(fluid_begin), cell_(cell), c_(c),
          per_cell_(fluid_only || !Search::merge), fluid_only_(fluid_only),
          z0_(c.z - N < 0 ? 0 : c.z - N), z1_(c.z + N >= g.nz ? g.nz - 1 : c.z + N) {}

    // Moves onto the first candidate; false when the stencil holds none.
    SPH_HD bool start() { return open_next_range(); }

    // Moves onto the next candidate; false when the stencil is exhausted.
    SPH_HD bool advance() {
        if (++j < end_) {
            if (!per_cell_) dz = int(cell_[j]) - ref_;
            return true;
        }
        return open_next_range();
    }

private:
    // Ranges are numbered column by column ((dx, dy) as in CellSearch::visit), and within a
    // column cell by cell (per_cell_) or as the one merged z-run. Empty ranges are skipped.
    SPH_HD bool open_next_range() {
        const int count = per_cell_ ? W * W * W : W * W;
        while (q_ < count) {
            const int t = q_++;
            const int column_index = per_cell_ ? t / W : t;
            const int zi = per_cell_ ? t % W : 0;
            dx = column_index / W - N;
            dy = column_index % W - N;
            int x = c_.x + dx, y = c_.y + dy;
            if (x < 0 || x >= g_.nx) {
                if (!g_.periodic_x) continue;
                x = wrap_index(x, g_.nx);
            }
            if (y < 0 || y >= g_.ny) {
                if (!g_.periodic_y) continue;
                y = wrap_index(y, g_.ny);
            }
            const std::uint32_t column = g_.encode(x, y, 0);
            std::uint32_t begin, end;
            if (per_cell_) {
                const int z = c_.z + zi - N;
                if (z < 0 || z >= g_.nz) continue;
                begin = (fluid_only_ ? fluid_begin_ : cell_start_)[column + z];
                end = cell_start_[column + z + 1];
                dz = zi - N;
            } else {
                begin = cell_start_[column + z0_];
                end = cell_start_[column + z1_ + 1];
                ref_ = int(column) + c_.z;
            }
            if (begin < end) {
                j = begin;
                end_ = end;
                if (!per_cell_) dz = int(cell_[j]) - ref_;
                return true;
            }
        }
        return false;
    }

    GridView g_;  // a copy: a reference to a kernel parameter can cost a local-memory copy
    const std::uint32_t* cell_start_;
    const std::uint32_t* fluid_begin_;
    const std::uint32_t* cell_;
    int3v c_;
    bool per_cell_, fluid_only_;
    int z0_, z1_;
    int q_ = 0;
    int ref_ = 0;
    std::uint32_t end_ = 0;
};

}  // namespace sph

#pragma once
// Page-locked staging memory for particle transfers through the host.
#include <cstdint>

#include "backend/cuda_check.cuh"
#include "core/types.hpp"

namespace sph {

// Page-locked host memory for transfers between subdomains, grown as needed.
class PinnedStaging {
public:
    ~PinnedStaging() {
        if (ptr_) cudaFreeHost(ptr_);
    }
    // The transfer layout of m particles: positions, velocities (now and the previous step), cells, ids, back to back.
    struct Layout {
        real4 *pos, *velrho, *velrho_prev;
        std::uint32_t *cell, *id;
    };
    Layout particles(std::size_t m) {
        const std::size_t need = m * (3 * sizeof(real4) + 2 * sizeof(std::uint32_t));
        if (need > bytes_) {
            if (ptr_) SPH_CUDA_CHECK(cudaFreeHost(ptr_));
            ptr_ = nullptr;
            bytes_ = need + need / 2;
            SPH_CUDA_CHECK(cudaMallocHost(&ptr_, bytes_));
        }
        auto* pos = static_cast<real4*>(ptr_);
        auto* cell = reinterpret_cast<std::uint32_t*>(pos + 3 * m);
        return {pos, pos + m, pos + 2 * m, cell, cell + m};
    }

private:
    void* ptr_ = nullptr;
    std::size_t bytes_ = 0;
};

}  // namespace sph

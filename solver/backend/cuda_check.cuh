#pragma once
// Every CUDA call is checked; a failure becomes a RunError naming the call and the error.
#include <cuda_runtime.h>

#include <string>

#include "core/error.hpp"

namespace sph {

inline void cuda_check(cudaError_t e, const char* what, const char* file, int line) {
    if (e != cudaSuccess)
        throw RunError(std::string("CUDA error '") + cudaGetErrorString(e) + "' from " + what + " at " + file + ":" +
                       std::to_string(line));
}

}  // namespace sph

#define SPH_CUDA_CHECK(call) ::sph::cuda_check((call), #call, __FILE__, __LINE__)
#define SPH_CUDA_CHECK_LAUNCH() ::sph::cuda_check(cudaGetLastError(), "kernel launch", __FILE__, __LINE__)

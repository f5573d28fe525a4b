#pragma once
// Scalar and vector types shared by host and device code. One source for the physics:
// everything here compiles under both g++ (host backend) and nvcc (CUDA backend).
#include <cstdint>
#include <cmath>

#if defined(__CUDACC__)
#define SPH_HD __host__ __device__ __forceinline__
#else
#define SPH_HD inline
#endif
// SPH_HD for the pair loop's pieces, inlined on the host too: left to g++'s heuristics, the
// pair body called through PairSums::add stayed a call, which cost the host's force loop 17%
// more instructions (make perf-check).
#if defined(__CUDACC__)
#define SPH_HD_INLINE SPH_HD
#else
#define SPH_HD_INLINE inline __attribute__((always_inline))
#endif
// The same for a lambda holding such a piece (after its parameter list): the listed loop's
// entry body as a lambda stayed a call on the host, 32% more instructions (change 19).
#if defined(__CUDACC__)
#define SPH_LAMBDA_INLINE
#else
#define SPH_LAMBDA_INLINE __attribute__((always_inline))
#endif

namespace sph {

// SPH_DOUBLE builds the whole solver in float64 for reference runs (CMake option SPH_DOUBLE).
#ifdef SPH_DOUBLE
using real = double;
#else
using real = float;
#endif

// Aligned so that a particle's position or velocity is one vector load on the GPU.
struct alignas(4 * sizeof(real)) real4 {
    real x, y, z, w;
};
struct real3 {
    real x, y, z;
};
struct int3v {
    int x, y, z;
};

SPH_HD real3 make3(real x, real y, real z) { return {x, y, z}; }
SPH_HD real3 xyz(const real4& a) { return {a.x, a.y, a.z}; }
SPH_HD real4 make4(real3 a, real w) { return {a.x, a.y, a.z, w}; }
SPH_HD real3 operator+(real3 a, real3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
SPH_HD real3 operator-(real3 a, real3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
SPH_HD real3 operator*(real s, real3 a) { return {s * a.x, s * a.y, s * a.z}; }
SPH_HD real3& operator+=(real3& a, real3 b) { a.x += b.x; a.y += b.y; a.z += b.z; return a; }
SPH_HD real3& operator-=(real3& a, real3 b) { a.x -= b.x; a.y -= b.y; a.z -= b.z; return a; }
SPH_HD real dot(real3 a, real3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

SPH_HD real sqrt_r(real x) { return std::sqrt(x); }
SPH_HD real floor_r(real x) { return std::floor(x); }

// a / b where b is a positive, moderate quantity (a distance, a density, r^2 + eta^2): in
// float32 on the GPU the approximate quotient without the operand scaling that the
// compiler's fast division adds for |b| > 2^126 (four instructions per division in the force
// loop, ~16 per pair); exact division on the host and in float64 builds.
SPH_HD real fast_divide(real a, real b) {
#if defined(__CUDA_ARCH__) && !defined(SPH_DOUBLE)
    return __fdividef(a, b);
#else
    return a / b;
#endif
}

// a + b as one rounded addition that the compiler may not fuse with a multiplication before
// it: a pair's terms are summed into a particle's totals this way wherever they were computed
// (in the same thread, or in another lane of a GPU warp and passed through shared memory), so
// that a particle's sums have the same bits whichever force loop ran them.
SPH_HD real add_uncontracted(real a, real b) {
#if defined(__CUDA_ARCH__) && defined(SPH_DOUBLE)
    return __dadd_rn(a, b);
#elif defined(__CUDA_ARCH__)
    return __fadd_rn(a, b);
#else
    return a + b;  // the host build does not target FMA, so nothing is fused there
#endif
}
SPH_HD real3 add_uncontracted(real3 a, real3 b) {
    return {add_uncontracted(a.x, b.x), add_uncontracted(a.y, b.y), add_uncontracted(a.z, b.z)};
}

// a[k], loaded whole where the caller writes it and kept in registers. The listed loop
// (physics/interaction.hpp) reads j's position and velocity-density before the support test;
// left to itself, nvcc loaded only the density there, then the whole velocity-density and the
// pressure again behind the test: three gathers of a neighbour's data where two do, in a loop
// bound by the L1's throughput (ncu, change 10 of docs/force-loop-notes.md). One asm
// statement yields all four components at once, so the compiler cannot split the load, nor
// sink it behind a test that reads one of them; not volatile, so that it stays a read-only
// (.nc) load like the loop's others. The host reads a[k] plainly.
SPH_HD real4 load_whole(const real4* a, std::uint32_t k) {
#if defined(__CUDA_ARCH__) && !defined(SPH_DOUBLE)
    real4 v;
    asm("ld.global.nc.v4.f32 {%0, %1, %2, %3}, [%4];"
                 : "=f"(v.x), "=f"(v.y), "=f"(v.z), "=f"(v.w)
                 : "l"(a + k));
    return v;
#else
    return a[k];
#endif
}

// The index of the lowest set bit of a non-zero mask.
SPH_HD int lowest_set_bit(std::uint32_t mask) {
#if defined(__CUDA_ARCH__)
    return __ffs(int(mask)) - 1;
#else
    return __builtin_ctz(mask);
#endif
}
SPH_HD bool finite_r(real x) {
#if defined(__CUDA_ARCH__)
    return isfinite(x);
#else
    return std::isfinite(x);
#endif
}

}  // namespace sph

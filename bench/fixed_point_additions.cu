// How fast can a GPU add j's sums of a symmetric cluster-pair loop? (docs/force-loop-notes.md,
// "j's side counted".) A warp stands for one cluster I walking its list: per listed cluster it
// adds, for each of the 4 j's of a tile, 4 quantities (acceleration, d rho / dt) as 64-bit
// fixed-point integers, to accumulators in global memory (L2-resident: 32 bytes a particle) or,
// as a block gathering j first would, in shared memory. The j's of a listed cluster are
// consecutive, its clusters lie within a window of the walking cluster's index, as the sorted
// order puts spatial neighbours. Prints additions per second for each; no physics, no lists.
//   fixed_point_additions [particles (1040000)] [listed clusters a warp (40)]
#include <cuda_runtime.h>

#include <cstdio>
#include <cstdlib>

namespace {

constexpr int cluster = 8, quantities = 4, warps_per_block = 8;

__device__ unsigned hash(unsigned x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    return x ^ (x >> 16);
}

// Lane l < 16 of each tile adds quantity l % 4 of j = l / 4 of the tile (16 additions a tile,
// two tiles a listed cluster): as after the 8-lane reductions.
template <bool Shared>
__global__ void add_kernel(unsigned long long* acc, unsigned clusters, int listed, unsigned window) {
    // A block of 8 clusters lists at most 157 clusters (the counts' block8_union_max at dp 0.01):
    // 160 x 8 j's x 4 quantities, 40 KB; j's slot here is j modulo that, not the union's index.
    __shared__ unsigned long long slots[160 * cluster * quantities];
    const unsigned warp = (blockIdx.x * blockDim.x + threadIdx.x) / 32, lane = threadIdx.x % 32;
    const unsigned slot_count = sizeof(slots) / sizeof(slots[0]);
    // No early return: the shared variant's warps all meet at __syncthreads below.
    const int walk = warp < clusters ? listed : 0;
    for (int k = 0; k < walk; ++k) {
        const unsigned offset = hash(warp * 131u + unsigned(k)) % (2 * window + 1);
        unsigned j_cluster = warp + offset > window ? warp + offset - window : 0;
        if (j_cluster >= clusters) j_cluster = clusters - 1;
        for (int half = 0; half < 2; ++half) {
            if (lane >= 16) continue;
            const unsigned j = j_cluster * cluster + unsigned(half) * 4 + lane / 4;
            const unsigned long long value = (unsigned long long)(hash(j + lane) & 0xffff);
            if constexpr (Shared)
                atomicAdd(&slots[(j * quantities + lane % 4) % slot_count], value);
            else
                atomicAdd(&acc[std::size_t(j) * quantities + lane % 4], value);
        }
    }
    if constexpr (Shared) {
        __syncthreads();
        if (threadIdx.x == 0) atomicAdd(&acc[blockIdx.x], slots[warp % slot_count]);  // keep the work
    }
}

#define CHECK(x)                                                                       \
    do {                                                                               \
        cudaError_t e_ = (x);                                                          \
        if (e_ != cudaSuccess) {                                                       \
            std::fprintf(stderr, "fixed_point_additions: %s\n", cudaGetErrorString(e_)); \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

template <bool Shared>
int time_one(const char* name, unsigned long long* acc, unsigned clusters, int listed) {
    const unsigned window = 6000;  // clusters between a cluster and its farthest listed one
    const unsigned threads = 32 * warps_per_block, blocks = (clusters + warps_per_block - 1) / warps_per_block;
    cudaEvent_t a, b;
    CHECK(cudaEventCreate(&a));
    CHECK(cudaEventCreate(&b));
    add_kernel<Shared><<<blocks, threads>>>(acc, clusters, listed, window);  // warm-up
    CHECK(cudaGetLastError());
    float best = 1e30f;
    for (int r = 0; r < 5; ++r) {
        CHECK(cudaEventRecord(a));
        add_kernel<Shared><<<blocks, threads>>>(acc, clusters, listed, window);
        CHECK(cudaEventRecord(b));
        CHECK(cudaEventSynchronize(b));
        float ms = 0;
        CHECK(cudaEventElapsedTime(&ms, a, b));
        best = ms < best ? ms : best;
    }
    const double additions = double(clusters) * listed * 2 * 16;
    std::printf("%s: %.0f additions in %.3f ms (best of 5): %.3g additions a second\n", name, additions, best,
                additions / (best * 1e-3));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const long particles = argc > 1 ? std::atol(argv[1]) : 1040000;
    const int listed = argc > 2 ? std::atoi(argv[2]) : 40;
    if (particles < cluster || listed < 1) {
        std::fprintf(stderr, "fixed_point_additions: particles must be at least %d and listed clusters at least 1\n",
                     cluster);
        return 2;
    }
    const unsigned clusters = unsigned(particles / cluster);
    unsigned long long* acc = nullptr;
    CHECK(cudaMalloc(&acc, std::size_t(clusters) * cluster * quantities * sizeof(unsigned long long)));
    CHECK(cudaMemset(acc, 0, std::size_t(clusters) * cluster * quantities * sizeof(unsigned long long)));
    std::printf("%u clusters of %d, %d listed clusters a warp, accumulators %.1f MB\n", clusters, cluster, listed,
                clusters * double(cluster * quantities * 8) / 1e6);
    if (time_one<false>("global 64-bit additions", acc, clusters, listed)) return 1;
    if (time_one<true>("shared 64-bit additions", acc, clusters, listed)) return 1;
    CHECK(cudaFree(acc));
    return 0;
}

#pragma once
// Copy streams beside the subdomains' compute streams, for the exchanges that run under the
// inner update (paper section 5.3): the CUDA transports (cuda_transport.cu) and the staging of
// particles for MPI (cuda_rank_staging.cu).
#include <algorithm>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "backend/cuda_check.cuh"
#include "backend/pinned_staging.cuh"
#include "backend/subdomain.hpp"
#include "multi/particle_transport.hpp"

namespace sph {

// The arrays of `count` particles from `src` to `dst` that both carry (a null one is not
// carried: a refresh's ids), each device or page-locked host memory (unified addressing tells
// which), queued on `stream` of the current GPU.
inline void copy_particles_async(const ParticleSpan& dst, const ParticleSpan& src, std::size_t count,
                                 cudaStream_t stream) {
    for_each_array(dst, src, [&](auto* to, const auto* from) {
        SPH_CUDA_CHECK(cudaMemcpyAsync(to, from, count * sizeof(*from), cudaMemcpyDefault, stream));
    });
}

// `count` particles of page-locked staging memory from particle `at`, as a host span.
inline ParticleSpan staged_span(const PinnedStaging::Layout& host, std::size_t at, std::size_t count) {
    return {host.pos + at, host.velrho + at, host.velrho_prev + at, host.cell + at, host.id + at, count, -1, nullptr};
}

// Paper section 5.3: per subdomain, a copy stream on its GPU, an event marking its boundary
// area updated (recorded on its compute stream before the inner update is queued) and one
// marking the copies it took part in done. Copies wait for the first; the subdomains' later
// work waits for the second; the host waits for neither.
class CopyStreams {
public:
    explicit CopyStreams(const std::vector<std::unique_ptr<Subdomain>>& subs) {
        for (auto& s : subs) {
            SPH_CUDA_CHECK(cudaSetDevice(s->device()));
            Lane l{};
            l.device = s->device();
            SPH_CUDA_CHECK(cudaStreamCreateWithFlags(&l.copy, cudaStreamNonBlocking));
            SPH_CUDA_CHECK(cudaEventCreateWithFlags(&l.ready, cudaEventDisableTiming));
            SPH_CUDA_CHECK(cudaEventCreate(&l.start));  // start and done time the copies
            SPH_CUDA_CHECK(cudaEventCreate(&l.done));
            lanes_.push_back(l);
        }
    }
    ~CopyStreams() {
        for (Lane& l : lanes_) {
            cudaSetDevice(l.device);  // unchecked: destructors must not throw
            cudaEventDestroy(l.ready);
            cudaEventDestroy(l.start);
            cudaEventDestroy(l.done);
            cudaStreamDestroy(l.copy);
        }
    }
    CopyStreams(const CopyStreams&) = delete;
    CopyStreams& operator=(const CopyStreams&) = delete;

    cudaStream_t copy(int d) const { return lanes_[d].copy; }
    void mark_ready(int d, cudaStream_t compute) {
        SPH_CUDA_CHECK(cudaSetDevice(lanes_[d].device));
        SPH_CUDA_CHECK(cudaEventRecord(lanes_[d].ready, compute));
    }
    // d's copy stream waits until subdomain `other`'s boundary area is updated.
    void copy_after_ready(int d, int other) {
        SPH_CUDA_CHECK(cudaSetDevice(lanes_[d].device));
        SPH_CUDA_CHECK(cudaStreamWaitEvent(lanes_[d].copy, lanes_[other].ready, 0));
    }
    // After d's copy stream has been ordered after the ready marks: its copies start here.
    void mark_start(int d) {
        SPH_CUDA_CHECK(cudaSetDevice(lanes_[d].device));
        SPH_CUDA_CHECK(cudaEventRecord(lanes_[d].start, lanes_[d].copy));
    }
    void mark_done(int d) {
        SPH_CUDA_CHECK(cudaSetDevice(lanes_[d].device));
        SPH_CUDA_CHECK(cudaEventRecord(lanes_[d].done, lanes_[d].copy));
        timed_.insert(d);
    }
    // The longest of the copy streams marked since the last call, start to done (waits for them).
    double elapsed_ms() {
        double longest = timed_.empty() ? -1 : 0;
        for (int d : timed_) {
            SPH_CUDA_CHECK(cudaSetDevice(lanes_[d].device));
            SPH_CUDA_CHECK(cudaEventSynchronize(lanes_[d].done));
            float ms = 0;
            SPH_CUDA_CHECK(cudaEventElapsedTime(&ms, lanes_[d].start, lanes_[d].done));
            longest = std::max(longest, double(ms));
        }
        timed_.clear();
        return longest;
    }
    // For each pair (from, to) of the delivery, the compute streams of both wait for the
    // copies of from's copy stream (its sends; with NCCL a pair (d, d) stands for d's receives).
    void finish(const std::vector<std::unique_ptr<Subdomain>>& subs, const std::set<std::pair<int, int>>& pairs) {
        for (const auto& [from, to] : pairs)
            for (int waiter : {from, to}) {
                SPH_CUDA_CHECK(cudaSetDevice(lanes_[waiter].device));
                SPH_CUDA_CHECK(cudaStreamWaitEvent(static_cast<cudaStream_t>(subs[waiter]->stream()), lanes_[from].done, 0));
            }
    }

private:
    struct Lane {
        int device;
        cudaStream_t copy;
        cudaEvent_t ready, start, done;
    };
    std::vector<Lane> lanes_;
    std::set<int> timed_;
};

}  // namespace sph

#pragma once
// Phase timing with CUDA events on a subdomain's stream.
#include <vector>

#include "backend/cuda_check.cuh"
#include "backend/phase.hpp"

namespace sph {

// CUDA events on the subdomain's stream; a pool reused every step.
class CudaPhaseClock final : public PhaseClock {
public:
    // Events belong to the GPU that was current when they were made: the clock makes its
    // subdomain's GPU current before touching them.
    CudaPhaseClock(cudaStream_t s, int device) : stream_(s), device_(device) {}
    ~CudaPhaseClock() override {
        cudaSetDevice(device_);
        for (auto& m : marks_) {
            cudaEventDestroy(m.begin);
            cudaEventDestroy(m.end);
        }
    }
    void begin(Phase p) override {
        SPH_CUDA_CHECK(cudaSetDevice(device_));
        if (used_ == marks_.size()) {
            Mark m{};
            SPH_CUDA_CHECK(cudaEventCreate(&m.begin));
            SPH_CUDA_CHECK(cudaEventCreate(&m.end));
            marks_.push_back(m);
        }
        marks_[used_].phase = p;
        SPH_CUDA_CHECK(cudaEventRecord(marks_[used_].begin, stream_));
    }
    void end(Phase) override {
        SPH_CUDA_CHECK(cudaSetDevice(device_));
        SPH_CUDA_CHECK(cudaEventRecord(marks_[used_].end, stream_));
        ++used_;
    }
    PhaseTimes collect() override {
        SPH_CUDA_CHECK(cudaSetDevice(device_));
        PhaseTimes t{};
        if (used_ > 0) SPH_CUDA_CHECK(cudaEventSynchronize(marks_[used_ - 1].end));
        for (std::size_t k = 0; k < used_; ++k) {
            float ms = 0;
            SPH_CUDA_CHECK(cudaEventElapsedTime(&ms, marks_[k].begin, marks_[k].end));
            t[std::size_t(marks_[k].phase)] += ms;
        }
        used_ = 0;
        return t;
    }

private:
    struct Mark {
        cudaEvent_t begin, end;
        Phase phase;
    };
    cudaStream_t stream_;
    int device_;
    std::vector<Mark> marks_;
    std::size_t used_ = 0;
};

}  // namespace sph

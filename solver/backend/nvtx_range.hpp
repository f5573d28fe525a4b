#pragma once
// NVTX ranges in one domain ("sph"), with registered strings, so Nsight Systems shows each
// phase under the same name as its timer column. Compiles to nothing without NVTX3.
#include "backend/phase.hpp"

#if __has_include(<nvtx3/nvToolsExt.h>) && !defined(SPH_NO_NVTX)
#include <nvtx3/nvToolsExt.h>
#define SPH_HAVE_NVTX 1
#endif

namespace sph {

#ifdef SPH_HAVE_NVTX
struct sph_nvtx_domain {
    static constexpr const char* name{"sph"};
};

// Registered once per phase: cheaper than passing a string on every push.
nvtxStringHandle_t nvtx_phase_string(Phase p);
nvtxDomainHandle_t nvtx_domain();

class NvtxRange {
public:
    NvtxRange(Phase p, long long step, int device);
    ~NvtxRange();
    NvtxRange(const NvtxRange&) = delete;
    NvtxRange& operator=(const NvtxRange&) = delete;
};
// Names a CPU thread or device in the timeline ("subdomain 0 on GPU 1").
void nvtx_name_device(int subdomain, const char* label);
#else
class NvtxRange {
public:
    NvtxRange(Phase, long long, int) {}
};
inline void nvtx_name_device(int, const char*) {}
#endif

// Times and names one phase of one step on one subdomain.
class ScopedPhase {
public:
    ScopedPhase(PhaseClock& clock, Phase p, long long step, int device)
        : clock_(clock), phase_(p), range_(p, step, device) { clock_.begin(p); }
    ~ScopedPhase() { clock_.end(phase_); }
    ScopedPhase(const ScopedPhase&) = delete;
    ScopedPhase& operator=(const ScopedPhase&) = delete;

private:
    PhaseClock& clock_;
    Phase phase_;
    NvtxRange range_;
};

}  // namespace sph

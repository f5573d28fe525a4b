#include "backend/nvtx_range.hpp"

#ifdef SPH_HAVE_NVTX
#include <array>
#include <cstdint>

namespace sph {

nvtxDomainHandle_t nvtx_domain() {
    static nvtxDomainHandle_t d = nvtxDomainCreateA("sph");
    return d;
}

nvtxStringHandle_t nvtx_phase_string(Phase p) {
    static const auto handles = [] {
        std::array<nvtxStringHandle_t, phase_count> h{};
        for (std::size_t i = 0; i < phase_count; ++i) h[i] = nvtxDomainRegisterStringA(nvtx_domain(), phase_names[i]);
        return h;
    }();
    return handles[std::size_t(p)];
}

NvtxRange::NvtxRange(Phase p, long long step, int device) {
    nvtxEventAttributes_t a{};
    a.version = NVTX_VERSION;
    a.size = NVTX_EVENT_ATTRIB_STRUCT_SIZE;
    a.messageType = NVTX_MESSAGE_TYPE_REGISTERED;
    a.message.registered = nvtx_phase_string(p);
    a.payloadType = NVTX_PAYLOAD_TYPE_INT64;  // the step number
    a.payload.llValue = step;
    a.category = std::uint32_t(device);  // one category per device, named below
    nvtxDomainRangePushEx(nvtx_domain(), &a);
}

NvtxRange::~NvtxRange() { nvtxDomainRangePop(nvtx_domain()); }

void nvtx_name_device(int subdomain, const char* label) {
    nvtxDomainNameCategoryA(nvtx_domain(), std::uint32_t(subdomain), label);
}

}  // namespace sph
#endif

// Built instead of the CUDA backend when nvcc is not found: asking for it is a clear error.
#include "backend/subdomain.hpp"
#include "core/error.hpp"
#include "multi/particle_transport.hpp"

namespace sph {

std::unique_ptr<Subdomain> make_cuda_subdomain(const SubdomainConfig&, std::size_t, int) {
    throw InputError("the CUDA backend was asked for, but this build has no CUDA support (nvcc was not found)");
}
bool cuda_backend_available() { return false; }
int cuda_device_count() { return 0; }
std::string cuda_device_summary() { return ""; }
std::unique_ptr<ParticleTransport> make_cuda_transport(TransportKind, const std::vector<std::unique_ptr<Subdomain>>&,
                                                       std::string&) {
    throw InputError("GPU transports need the CUDA backend, which this build lacks (nvcc was not found)");
}

}  // namespace sph

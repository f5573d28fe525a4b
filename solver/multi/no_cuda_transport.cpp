// Built instead of cuda_transport.cu when nvcc is not found: asking for a GPU transport is a
// clear error.
#include "core/error.hpp"
#include "multi/particle_transport.hpp"

namespace sph {

std::unique_ptr<ParticleTransport> make_cuda_transport(TransportKind, const std::vector<std::unique_ptr<Subdomain>>&,
                                                       std::string&) {
    throw InputError("GPU transports need the CUDA backend, which this build lacks (nvcc was not found)");
}

}  // namespace sph

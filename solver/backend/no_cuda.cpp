// Built instead of the CUDA backend when nvcc is not found: asking for it is a clear error.
#include "backend/subdomain.hpp"
#include "core/error.hpp"

namespace sph {

std::unique_ptr<Subdomain> make_cuda_subdomain(const SubdomainConfig&, std::size_t, int) {
    throw InputError("the CUDA backend was asked for, but this build has no CUDA support (nvcc was not found)");
}
bool cuda_backend_available() { return false; }
int cuda_device_count() { return 0; }
std::string cuda_device_summary() { return ""; }

}  // namespace sph

// Built instead of cuda_rank_staging.cu when nvcc is not found.
#include "core/error.hpp"
#include "multi/rank_staging.hpp"

namespace sph {

std::unique_ptr<RankStaging> make_pinned_rank_staging(const std::vector<std::unique_ptr<Subdomain>>&) {
    throw InputError("staging GPU particles for MPI needs the CUDA backend, which this build lacks (nvcc was not found)");
}

}  // namespace sph

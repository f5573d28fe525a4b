// Built instead of mpi_rank_group.cpp when CMake finds no MPI.
#include "core/error.hpp"
#include "multi/rank_group.hpp"

namespace sph {

std::unique_ptr<RankGroup> make_mpi_rank_group(int&, char**&) {
    throw InputError("this sphbench was started by mpirun, but it was built without MPI (install libopenmpi-dev "
                     "with tools/install-deps.sh and configure again)");
}

}  // namespace sph

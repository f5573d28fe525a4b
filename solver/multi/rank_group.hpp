#pragma once
// The processes of a run: one (the default) or the ranks of an MPI job. The decomposition
// moves particles between ranks and agrees on the balancer's inputs and the step statistics
// through this interface, so the time loop has one path for one process and for many.
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace sph {

using Bytes = std::vector<std::byte>;

class RankGroup {
public:
    virtual ~RankGroup() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    // For the run's metadata: "one process" or "MPI, R ranks".
    virtual std::string description() const = 0;
    // This rank among the ranks of its node (shared memory), and how many run there: which
    // GPUs of the node a rank takes (multi/gpu_choice.hpp).
    virtual int local_rank() const { return 0; }
    virtual int local_size() const { return 1; }
    // Whether the MPI library takes GPU memory in its messages (CUDA-aware), and its name for
    // messages that say it does not.
    virtual bool cuda_aware() const { return false; }
    virtual std::string library() const { return "no MPI library (one process)"; }
    // Every rank's bytes (sizes may differ), in rank order; a collective.
    virtual std::vector<Bytes> allgather(const Bytes& mine) = 0;
    // sends[r] goes to rank r (sends[rank()] stays here); returns what each rank sent to this
    // one, in rank order. A collective: every rank calls it, with empty messages where it has
    // nothing to say.
    virtual std::vector<Bytes> exchange(const std::vector<Bytes>& sends) = 0;
    // Stops every rank of the job (one rank's failure must not leave the others waiting).
    [[noreturn]] virtual void abort(int exit_code) = 0;
};

// A group of this process alone (a reference run beside an MPI one, in tests).
std::unique_ptr<RankGroup> make_single_process_group();

// The group of this process: one process unless main() installed an MPI group.
RankGroup& process_ranks();
void set_process_ranks(std::unique_ptr<RankGroup> group);

// Whether this process was started by mpirun (OpenMPI's or PMI's environment is set).
bool started_by_mpirun();
// The MPI group of this job (MPI_Init now, MPI_Finalize when it is destroyed). Throws
// InputError when the build has no MPI.
std::unique_ptr<RankGroup> make_mpi_rank_group(int& argc, char**& argv);

// Typed helpers over bytes, for trivially copyable values.
template <class T>
Bytes to_bytes(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    Bytes b(v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(b.data(), v.data(), b.size());
    return b;
}
template <class T>
void append_from_bytes(std::vector<T>& v, const Bytes& b) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t n = b.size() / sizeof(T), at = v.size();
    v.resize(at + n);
    if (n) std::memcpy(v.data() + at, b.data(), n * sizeof(T));
}
// Every rank's values, concatenated in rank order.
template <class T>
std::vector<T> allgather_values(RankGroup& ranks, const std::vector<T>& mine) {
    std::vector<T> all;
    for (const Bytes& b : ranks.allgather(to_bytes(mine))) append_from_bytes(all, b);
    return all;
}

}  // namespace sph

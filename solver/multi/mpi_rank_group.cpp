// The ranks of an MPI job. Messages are host memory (the host backend's particles, or what a
// GPU subdomain staged); collectives keep rank order, so what every rank computes from them
// is the same, bit for bit.
#include <mpi.h>
#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>  // Open MPI's extensions: MPIX_Query_cuda_support
#endif

#include <algorithm>
#include <cstdlib>

#include <string>

#include "core/error.hpp"
#include "multi/rank_group.hpp"

namespace sph {
namespace {

void check(int rc, const char* what) {
    if (rc != MPI_SUCCESS) {
        char text[MPI_MAX_ERROR_STRING];
        int len = 0;
        MPI_Error_string(rc, text, &len);
        throw RunError(std::string(what) + " failed: " + std::string(text, std::size_t(len)));
    }
}

std::vector<int> displacements(const std::vector<int>& counts) {
    std::vector<int> at(counts.size(), 0);
    for (std::size_t i = 1; i < counts.size(); ++i) at[i] = at[i - 1] + counts[i - 1];
    return at;
}

int byte_count(std::size_t n) {
    if (n > std::size_t(1) << 31) throw RunError("an MPI message of " + std::to_string(n) + " bytes exceeds 2 GiB");
    return int(n);
}

class MpiRankGroup final : public RankGroup {
public:
    MpiRankGroup(int& argc, char**& argv) {
        int ready = 0;
        MPI_Initialized(&ready);
        if (!ready) check(MPI_Init(&argc, &argv), "MPI_Init");
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
        // Errors come back as codes, so that a failed call is reported in one sentence; a rank
        // that dies is caught by mpirun, which stops the others and names it.
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
        // The ranks sharing this rank's node (its memory, and so its GPUs).
        MPI_Comm node = MPI_COMM_NULL;
        check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
              "MPI_Comm_split_type");
        MPI_Comm_rank(node, &local_rank_);
        MPI_Comm_size(node, &local_size_);
        MPI_Comm_free(&node);
    }
    ~MpiRankGroup() override {
        int done = 0;
        MPI_Finalized(&done);
        if (!done) MPI_Finalize();
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    int local_rank() const override { return local_rank_; }
    int local_size() const override { return local_size_; }
    std::string description() const override { return "MPI, " + std::to_string(size_) + " ranks"; }
    // Open MPI says at compile time (MPIX_CUDA_AWARE_SUPPORT) and at run time
    // (MPIX_Query_cuda_support) whether it takes GPU memory; another library is taken not to.
    bool cuda_aware() const override {
#if defined(MPIX_CUDA_AWARE_SUPPORT)
        return MPIX_Query_cuda_support() == 1;
#else
        return false;
#endif
    }
    std::string library() const override {
        char text[MPI_MAX_LIBRARY_VERSION_STRING] = {};
        int len = 0;
        MPI_Get_library_version(text, &len);
        const std::string all(text, std::size_t(len));
        return all.substr(0, all.find_first_of(",\n"));  // "Open MPI v4.1.4"
    }

    std::vector<Bytes> allgather(const Bytes& mine) override {
        const int n = byte_count(mine.size());
        std::vector<int> counts(size_);
        check(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
        const std::vector<int> at = displacements(counts);
        Bytes all(std::size_t(at.back()) + std::size_t(counts.back()));
        check(MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD),
              "MPI_Allgatherv");
        return split(all, counts, at);
    }

    std::vector<Bytes> exchange(const std::vector<Bytes>& sends) override {
        std::vector<int> send_counts(size_), receive_counts(size_);
        for (int r = 0; r < size_; ++r) send_counts[r] = r == rank_ ? 0 : byte_count(sends.at(r).size());
        check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, MPI_COMM_WORLD),
              "MPI_Alltoall");
        const std::vector<int> send_at = displacements(send_counts), receive_at = displacements(receive_counts);
        Bytes out(std::size_t(send_at.back()) + std::size_t(send_counts.back()));
        for (int r = 0; r < size_; ++r)
            if (r != rank_ && !sends[r].empty()) std::copy(sends[r].begin(), sends[r].end(), out.begin() + send_at[r]);
        Bytes in(std::size_t(receive_at.back()) + std::size_t(receive_counts.back()));
        check(MPI_Alltoallv(out.data(), send_counts.data(), send_at.data(), MPI_BYTE, in.data(), receive_counts.data(),
                            receive_at.data(), MPI_BYTE, MPI_COMM_WORLD),
              "MPI_Alltoallv");
        std::vector<Bytes> received = split(in, receive_counts, receive_at);
        received[rank_] = sends.at(rank_);
        return received;
    }

    [[noreturn]] void abort(int exit_code) override {
        MPI_Abort(MPI_COMM_WORLD, exit_code);
        std::exit(exit_code);  // MPI_Abort does not return; this satisfies [[noreturn]]
    }

private:
    static std::vector<Bytes> split(const Bytes& all, const std::vector<int>& counts, const std::vector<int>& at) {
        std::vector<Bytes> parts(counts.size());
        for (std::size_t r = 0; r < counts.size(); ++r)
            parts[r].assign(all.begin() + at[r], all.begin() + at[r] + counts[r]);
        return parts;
    }

    int rank_ = 0, size_ = 1, local_rank_ = 0, local_size_ = 1;
};

}  // namespace

std::unique_ptr<RankGroup> make_mpi_rank_group(int& argc, char**& argv) {
    return std::make_unique<MpiRankGroup>(argc, argv);
}

}  // namespace sph

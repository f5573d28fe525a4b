#pragma once
// How the particles a subdomain sends to another MPI rank reach the host memory of the
// message, and how what arrived reaches a receive area (SlabExchange::carry packs and unpacks
// between the two). Host subdomains are read and written in place. GPU subdomains are staged
// through page-locked host memory (cuda_rank_staging.cu): copies on copy streams of the
// staging's own, ordered by events after the subdomain's work, and finished before MPI reads
// the memory or the receiver's next work runs.
#include <memory>
#include <string>
#include <vector>

#include "backend/subdomain.hpp"
#include "multi/particle_transport.hpp"

namespace sph {

// The path particles between ranks take, for the run's metadata (rank_transport).
enum class RankTransport { none, host_memory, staged_pinned };
const char* rank_transport_label(RankTransport kind);  // "" (one process), "host-memory", "staged-pinned"

struct RankTransportChoice {
    RankTransport kind = RankTransport::none;
    std::string note;  // when what was asked is not what runs, why
};

// The path for a run of `ranks` processes on `backend`. GPU-direct (device buffers handed to
// a CUDA-aware MPI) is checked and refused, one sentence each, with the host backend, in one
// process, and of an MPI library without CUDA support; on a CUDA-aware library the particles
// are still staged (device buffers are not handed to MPI yet), and the note says so.
RankTransportChoice choose_rank_transport(BackendKind backend, int ranks, bool gpu_direct, bool mpi_cuda_aware,
                                          const std::string& mpi_library);

// `count` particles of local subdomain `sub` from `first`: of its sorted particles (going
// out), or of its receive area (coming in); `arrays` says which of their arrays travel (a
// refresh of ghosts between list rebuilds carries the state, not the ids).
struct StagedPiece {
    int sub = 0;
    std::size_t first = 0, count = 0;
    TransferArrays arrays = TransferArrays::whole;
};

// `count` particles of `span` from `first` (the same memory).
ParticleSpan sub_span(const ParticleSpan& span, std::size_t first, std::size_t count);
// What outgoing piece `p` reads of its subdomain: its sorted particles, or their state.
inline ParticleSpan piece_source(Subdomain& sub, const StagedPiece& p) {
    return source_arrays(sub, p.first, p.count, p.arrays);
}

class RankStaging {
public:
    virtual ~RankStaging() = default;
    // Paper section 5.3, as ParticleTransport::mark_ready: subdomain `local`'s boundary area
    // is queued for update, and copies from or into it wait for that, not for the inner update
    // queued after it. Without a mark since the last exchange, they wait for all the work
    // queued on the subdomain.
    virtual void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int local) {
        (void)subs;
        (void)local;
    }
    // Host memory holding each outgoing piece, in order; it can be read when this returns
    // (the copies are done) until the next call.
    virtual std::vector<ParticleSpan> stage_out(std::vector<std::unique_ptr<Subdomain>>& subs,
                                                const std::vector<StagedPiece>& pieces) = 0;
    // Host memory for each incoming piece of the receive areas (one per local subdomain), to
    // unpack the messages into; then deliver_in puts them in the areas, and orders each
    // receiver's later work after them.
    virtual std::vector<ParticleSpan> stage_in(const std::vector<StagedPiece>& pieces,
                                               const std::vector<ParticleSpan>& areas) = 0;
    virtual void deliver_in(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<StagedPiece>& pieces,
                            const std::vector<ParticleSpan>& areas) = 0;
};

// The staging for `kind` (none: nullptr; host_memory: in place; staged_pinned: pinned memory).
std::unique_ptr<RankStaging> make_rank_staging(RankTransport kind, const std::vector<std::unique_ptr<Subdomain>>& subs);
// cuda_rank_staging.cu; without CUDA (no_cuda_rank_staging.cpp) a build without it says so.
std::unique_ptr<RankStaging> make_pinned_rank_staging(const std::vector<std::unique_ptr<Subdomain>>& subs);

}  // namespace sph

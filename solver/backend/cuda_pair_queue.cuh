#pragma once
// A warp's queue of neighbour pairs (the force loop's compacted form, cuda_cell_forces.cu): the
// lanes test candidates of their own particles, push the pairs inside the support, and every
// 32 queued pairs the warp evaluates the pair body with all 32 lanes busy, one pair each,
// whichever particle the pairs belong to. Each particle's terms then go back to its own lane,
// which adds them in the order they were pushed: its visiting order, so the sums are those of
// the per-thread loop, bit for bit (PairTotals, add_uncontracted).
//
// Why: in the per-thread loop a warp runs the body as often as its busiest lane needs, and
// the lanes' neighbours overlap so little chunk by chunk that about 15 of 32 lanes do work
// (docs/force-loop-notes.md, change 7).
//
// The queue is a ring of 64 entries in shared memory: a push round adds at most one pair per
// lane (32) and the warp drains whenever 32 are waiting, so at most 63 are ever held. An
// entry is the candidate j and, packed, the owner lane and the cell offset (dx, dy, dz) of the
// range it came from: the drain forms the separation from them as the test did.
#include <cstdint>

#include "backend/cuda_launch.cuh"
#include "physics/interaction.hpp"

namespace sph::gpu {

struct PairQueueStorage {
    static constexpr unsigned capacity = 64;
    std::uint32_t j[capacity];
    std::uint32_t meta[capacity];  // owner lane | (dx + 8) << 5 | (dy + 8) << 9 | (dz + 8) << 13
    real4 terms[32];               // the drained batch's pair terms (acc, drho), by batch position
    real diffusion[32];            // and their density diffusion (PairTerms)
    std::uint32_t owned[32];       // per owner lane: the batch positions holding its pairs
};

template <class Kernel, bool Diffusion>
class WarpPairQueue {
public:
    // `first` is the particle of lane 0; every lane of the warp must construct and use the
    // queue together (its calls are warp-collective).
    __device__ WarpPairQueue(PairQueueStorage& s, const ForceInputs& in, const PhysicsParams& p, const Kernel& k,
                             std::uint32_t first)
        : s_(s), body_(in, p, k), first_(first), lane_(threadIdx.x % 32) {}

    // One round: each lane with pairs left in `hits` (bits over candidates base + k) pushes
    // its lowest; call until no lane has any (the return value says whether some lane pushed).
    // dz_of(j) gives the candidate's z cell offset.
    template <class ZOffset>
    __device__ bool push_round(std::uint32_t& hits, std::uint32_t base, int dx, int dy, const ZOffset& dz_of,
                               PairTotals& totals) {
        const std::uint32_t ballot = __ballot_sync(full_warp, hits != 0);
        if (ballot == 0) return false;
        if (hits != 0) {
            const std::uint32_t j = base + std::uint32_t(lowest_set_bit(hits));
            hits &= hits - 1;
            const unsigned slot = (tail_ + __popc(ballot & ((1u << lane_) - 1))) % PairQueueStorage::capacity;
            s_.j[slot] = j;
            s_.meta[slot] = lane_ | unsigned(dx + 8) << 5 | unsigned(dy + 8) << 9 | unsigned(dz_of(j) + 8) << 13;
        }
        tail_ += __popc(ballot);
        if (tail_ - head_ >= 32) drain(32, totals);
        return true;
    }

    // The pairs still queued (fewer than 32): call once, after the last push.
    __device__ void flush(PairTotals& totals) {
        if (tail_ != head_) drain(tail_ - head_, totals);
    }

private:
    // The body of pairs head .. head + count - 1, one per lane; then each owner lane adds its
    // pairs' terms in queue order.
    __device__ void drain(unsigned count, PairTotals& totals) {
        s_.owned[lane_] = 0;
        __syncwarp();
        unsigned owner = 32;  // none
        if (lane_ < count) {
            const unsigned slot = (head_ + lane_) % PairQueueStorage::capacity;
            const std::uint32_t j = s_.j[slot], meta = s_.meta[slot];
            owner = meta & 31;
            const ParticleSide a = particle_side(body_.in, first_ + owner);
            const RangeSeparation sep(a.pos, int(meta >> 5 & 15) - 8, int(meta >> 9 & 15) - 8, body_.in.grid.cell_size);
            const real3 rij = sep(body_.in.pos[j], int(meta >> 13 & 15) - 8);
            const PairTerms t = body_.terms(a, j, body_.in.velrho[j], rij, dot(rij, rij));
            s_.terms[lane_] = make4(t.acc, t.drho);
            s_.diffusion[lane_] = t.diffusion;
        }
        const unsigned same_owner = __match_any_sync(full_warp, owner);
        if (owner < 32 && lane_ == unsigned(lowest_set_bit(same_owner))) s_.owned[owner] = same_owner;
        __syncwarp();
        for (std::uint32_t mine = s_.owned[lane_]; mine != 0; mine &= mine - 1) {
            const int k = lowest_set_bit(mine);
            const real4 t = s_.terms[k];
            totals.accumulate(PairTerms{xyz(t), t.w, s_.diffusion[k]});
        }
        __syncwarp();  // the next drain reuses terms and owned
        head_ += count;
    }

    PairQueueStorage& s_;
    PairBody<Kernel, Diffusion> body_;
    std::uint32_t first_;
    unsigned lane_;
    unsigned head_ = 0, tail_ = 0;  // pairs drained, pairs pushed (the same in every lane)
};

}  // namespace sph::gpu

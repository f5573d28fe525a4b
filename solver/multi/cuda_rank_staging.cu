// GPU particles to and from the host memory of MPI messages, through page-locked memory
// (rank_staging.hpp). The copies run on a copy stream per subdomain, ordered by events: out,
// after the sender's boundary update (or all its queued work, without the overlap) and
// waited for on the host before MPI reads the memory; in, after the receiver's boundary
// update (its receive area was last read before it: at the settle, or, for a refresh of
// Verlet lists' ghosts, whose area is the live ghost slots, by this step's forces), with the receiver's later
// work ordered after them (so the settle at the next step's start sees them) and waited for
// on the host before the memory is reused. The inner update, queued on the compute streams
// before the exchange is issued, runs under both.
#include <set>

#include "core/error.hpp"
#include "multi/cuda_copy_streams.cuh"
#include "multi/rank_staging.hpp"

namespace sph {
namespace {

std::size_t total(const std::vector<StagedPiece>& pieces) {
    std::size_t n = 0;
    for (const StagedPiece& p : pieces) n += p.count;
    return n;
}

class PinnedRankStaging final : public RankStaging {
public:
    explicit PinnedRankStaging(const std::vector<std::unique_ptr<Subdomain>>& subs)
        : lanes_(subs), marked_(subs.size(), false) {
        for (auto& s : subs) devices_.push_back(s->device());
    }
    void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int local) override {
        lanes_.mark_ready(local, static_cast<cudaStream_t>(subs[local]->stream()));
        marked_[local] = true;
    }
    std::vector<ParticleSpan> stage_out(std::vector<std::unique_ptr<Subdomain>>& subs,
                                        const std::vector<StagedPiece>& pieces) override {
        std::vector<ParticleSpan> spans;
        if (total(pieces) == 0) return spans;
        const std::set<int> involved = copy_after_ready(subs, pieces);
        const PinnedStaging::Layout host = out_.particles(total(pieces));
        std::size_t at = 0;
        for (const StagedPiece& p : pieces) {
            // A refresh's pieces carry no ids: the message packs only what the span holds.
            spans.push_back(carried_arrays(staged_span(host, at, p.count), p.arrays));
            SPH_CUDA_CHECK(cudaSetDevice(devices_[p.sub]));
            copy_particles_async(spans.back(), piece_source(*subs[p.sub], p), p.count, lanes_.copy(p.sub));
            at += p.count;
        }
        wait(involved);  // MPI reads the memory next
        return spans;
    }
    std::vector<ParticleSpan> stage_in(const std::vector<StagedPiece>& pieces, const std::vector<ParticleSpan>&) override {
        std::vector<ParticleSpan> spans;
        if (total(pieces) == 0) return spans;
        const PinnedStaging::Layout host = in_.particles(total(pieces));
        std::size_t at = 0;
        for (const StagedPiece& p : pieces) {
            spans.push_back(carried_arrays(staged_span(host, at, p.count), p.arrays));
            at += p.count;
        }
        in_spans_ = spans;
        return spans;
    }
    void deliver_in(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<StagedPiece>& pieces,
                    const std::vector<ParticleSpan>& areas) override {
        if (total(pieces) > 0) {
            if (in_spans_.size() != pieces.size()) throw RunError("deliver_in was called without stage_in");
            const std::set<int> involved = copy_after_ready(subs, pieces);
            for (std::size_t i = 0; i < pieces.size(); ++i) {
                const StagedPiece& p = pieces[i];
                SPH_CUDA_CHECK(cudaSetDevice(devices_[p.sub]));
                copy_particles_async(sub_span(areas[p.sub], p.first, p.count), in_spans_[i], p.count, lanes_.copy(p.sub));
            }
            std::set<std::pair<int, int>> receivers;
            for (int d : involved) {
                lanes_.mark_done(d);
                receivers.insert({d, d});
            }
            lanes_.finish(subs, receivers);  // each receiver's later work after its copies (no host wait)
            wait(involved);                  // the staging memory is reused next time
        }
        in_spans_.clear();
        marked_.assign(marked_.size(), false);  // this exchange is done; the next one marks anew
    }

private:
    // The copy stream of every subdomain a piece touches waits for its mark, or, unmarked,
    // for all the work queued on it now.
    std::set<int> copy_after_ready(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<StagedPiece>& pieces) {
        std::set<int> involved;
        for (const StagedPiece& p : pieces)
            if (p.count) involved.insert(p.sub);
        for (int d : involved) {
            if (!marked_[d]) lanes_.mark_ready(d, static_cast<cudaStream_t>(subs[d]->stream()));
            lanes_.copy_after_ready(d, d);
        }
        return involved;
    }
    void wait(const std::set<int>& lanes) {
        for (int d : lanes) SPH_CUDA_CHECK(cudaStreamSynchronize(lanes_.copy(d)));
    }

    CopyStreams lanes_;
    std::vector<int> devices_;
    std::vector<bool> marked_;
    PinnedStaging out_, in_;
    std::vector<ParticleSpan> in_spans_;
};

}  // namespace

std::unique_ptr<RankStaging> make_pinned_rank_staging(const std::vector<std::unique_ptr<Subdomain>>& subs) {
    return std::make_unique<PinnedRankStaging>(subs);
}

}  // namespace sph

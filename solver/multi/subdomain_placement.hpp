#pragma once
// Which rank holds which subdomain: contiguous blocks in rank order (rank r holds
// [first(r), first(r) + count(r))), so that concatenating per-rank data in rank order gives
// per-subdomain data in subdomain order.
#include <string>

#include "core/error.hpp"

namespace sph {

class SubdomainPlacement {
public:
    SubdomainPlacement(int subdomains, int ranks) : subdomains_(subdomains), ranks_(ranks) {
        if (ranks > subdomains)
            throw InputError(std::to_string(ranks) + " MPI ranks were started for " + std::to_string(subdomains) +
                             " subdomains, but each rank needs at least one; ask for at least " +
                             std::to_string(ranks) + " devices (--devices) or start fewer ranks");
    }
    int subdomains() const { return subdomains_; }
    int ranks() const { return ranks_; }
    // The first ranks hold one subdomain more when the division is not even.
    int count(int rank) const { return subdomains_ / ranks_ + (rank < subdomains_ % ranks_ ? 1 : 0); }
    int first(int rank) const {
        const int base = subdomains_ / ranks_, extra = subdomains_ % ranks_;
        return rank * base + (rank < extra ? rank : extra);
    }
    int rank_of(int subdomain) const {
        for (int r = 0; r + 1 < ranks_; ++r)
            if (subdomain < first(r + 1)) return r;
        return ranks_ - 1;
    }

private:
    int subdomains_, ranks_;
};

}  // namespace sph

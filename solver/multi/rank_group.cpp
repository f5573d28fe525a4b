#include "multi/rank_group.hpp"

#include <cstdlib>

namespace sph {
namespace {

class SingleProcess final : public RankGroup {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::string description() const override { return "one process"; }
    std::vector<Bytes> allgather(const Bytes& mine) override { return {mine}; }
    std::vector<Bytes> exchange(const std::vector<Bytes>& sends) override { return {sends.at(0)}; }
    [[noreturn]] void abort(int exit_code) override { std::exit(exit_code); }
};

std::unique_ptr<RankGroup>& installed() {
    static std::unique_ptr<RankGroup> group = std::make_unique<SingleProcess>();
    return group;
}

}  // namespace

std::unique_ptr<RankGroup> make_single_process_group() { return std::make_unique<SingleProcess>(); }

RankGroup& process_ranks() { return *installed(); }

void set_process_ranks(std::unique_ptr<RankGroup> group) {
    installed() = group ? std::move(group) : std::make_unique<SingleProcess>();
}

bool started_by_mpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
           std::getenv("PMIX_RANK") != nullptr;
}

}  // namespace sph

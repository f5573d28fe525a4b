// MPI runs with CUDA subdomains, what CI can hold without a GPU: which GPU each rank's
// subdomains take (multi/gpu_choice.hpp), the path particles between ranks take and its
// refusals (multi/rank_staging.hpp), each refusal one sentence.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/error.hpp"
#include "multi/gpu_choice.hpp"
#include "multi/rank_staging.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

std::string refusal(const GpuChoiceInput& in) {
    try {
        choose_gpus(in);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// Rank `rank` of `ranks`, all on one node, holding `per_rank` subdomains each.
GpuChoiceInput on_one_node(int rank, int ranks, int per_rank, int gpus) {
    GpuChoiceInput in;
    in.rank = in.local_rank = rank;
    in.ranks = in.ranks_on_node = ranks;
    in.first_subdomain = rank * per_rank;
    in.subdomains = per_rank;
    in.gpus_visible = gpus;
    return in;
}

TEST(GpuChoice, OneProcessGoesRoundTheGpusAsBefore) {
    GpuChoiceInput in;
    in.subdomains = 4;
    in.gpus_visible = 2;
    EXPECT_EQ(choose_gpus(in), (std::vector<int>{0, 1, 0, 1}));
    in.gpus_visible = 1;
    EXPECT_EQ(choose_gpus(in), (std::vector<int>{0, 0, 0, 0}));  // several subdomains on one GPU (testing)
}

TEST(GpuChoice, RanksOfANodeTakeGpusOfTheirOwn) {
    EXPECT_EQ(choose_gpus(on_one_node(0, 2, 1, 2)), std::vector<int>{0});
    EXPECT_EQ(choose_gpus(on_one_node(1, 2, 1, 2)), std::vector<int>{1});
    // Two subdomains per rank on four GPUs: a block of two each.
    EXPECT_EQ(choose_gpus(on_one_node(0, 2, 2, 4)), (std::vector<int>{0, 1}));
    EXPECT_EQ(choose_gpus(on_one_node(1, 2, 2, 4)), (std::vector<int>{2, 3}));
    // One subdomain per rank on four GPUs: the first of each block.
    EXPECT_EQ(choose_gpus(on_one_node(1, 2, 1, 4)), std::vector<int>{2});
    // Without sharing, no two ranks of a node ever meet on a GPU, whatever the counts.
    for (int gpus = 1; gpus <= 8; ++gpus)
        for (int ranks = 1; ranks <= gpus; ++ranks)
            for (int per_rank = 1; per_rank <= 3; ++per_rank) {
                std::set<int> taken;
                for (int r = 0; r < ranks; ++r) {
                    std::set<int> mine;
                    for (int g : choose_gpus(on_one_node(r, ranks, per_rank, gpus))) {
                        ASSERT_GE(g, 0);
                        ASSERT_LT(g, gpus);
                        mine.insert(g);
                    }
                    for (int g : mine) EXPECT_TRUE(taken.insert(g).second) << gpus << " GPUs, " << ranks << " ranks";
                }
            }
}

TEST(GpuChoice, MoreRanksThanGpusIsRefusedUnlessSharingIsAsked) {
    EXPECT_EQ(refusal(on_one_node(1, 2, 1, 1)),
              "2 MPI ranks run on one node, which has 1 GPU: start at most 1 per node, or let ranks share GPUs with "
              "--share-gpus (spec key share_gpus = true)");
    GpuChoiceInput in = on_one_node(1, 2, 1, 1);
    in.share = true;
    EXPECT_EQ(choose_gpus(in), std::vector<int>{0});
    // Shared: rank l from GPU l mod G, its subdomains round every GPU from there.
    for (int r = 0; r < 3; ++r) {
        in = on_one_node(r, 3, 2, 2);
        in.share = true;
        EXPECT_EQ(choose_gpus(in), (std::vector<int>{r % 2, (r + 1) % 2})) << "rank " << r;
    }
    // With a device map too, more ranks on the node than GPUs needs sharing asked for (a map
    // that puts two ranks on one GPU of a node with enough GPUs is the map's to decide).
    in = on_one_node(1, 2, 1, 1);
    in.device_map = {0, 0};
    EXPECT_NE(refusal(in).find("--share-gpus"), std::string::npos);
    in.share = true;
    EXPECT_EQ(choose_gpus(in), std::vector<int>{0});
}

TEST(GpuChoice, TheDeviceMapDecidesAndAGpuARankLacksIsNamed) {
    GpuChoiceInput in = on_one_node(1, 2, 2, 2);
    in.device_map = {0, 1, 1, 0};
    EXPECT_EQ(choose_gpus(in), (std::vector<int>{1, 0}));
    in.device_map = {0, 1, 1, 7};
    EXPECT_EQ(refusal(in), "the device map (--device-map, device_map) puts subdomain 3 on GPU 7, but rank 1 sees 2 "
                           "GPUs (indices 0 to 1 on its node)");
    // In one process the sentence names no rank.
    GpuChoiceInput one;
    one.subdomains = 2;
    one.gpus_visible = 1;
    one.device_map = {0, 7};
    EXPECT_EQ(refusal(one), "the device map (--device-map, device_map) puts subdomain 1 on GPU 7, but this process "
                            "sees 1 GPU (indices 0 to 0)");
    one.device_map = {0};
    EXPECT_NE(refusal(one).find("names 1 GPU for 2 subdomains"), std::string::npos) << refusal(one);
}

TEST(GpuChoice, NoGpuVisibleIsOneSentence) {
    EXPECT_EQ(refusal(on_one_node(1, 2, 1, 0)), "the CUDA backend was asked for, but no CUDA GPU is visible");
    GpuChoiceInput one;
    EXPECT_EQ(refusal(one), "the CUDA backend was asked for, but no CUDA GPU is visible");
}

std::string refusal(BackendKind backend, int ranks, bool gpu_direct, bool aware) {
    try {
        choose_rank_transport(backend, ranks, gpu_direct, aware, "Open MPI v4.1.4");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(RankTransport, TheRunsMetadataSaysWhichPathParticlesTake) {
    EXPECT_EQ(choose_rank_transport(BackendKind::host, 1, false, false, "").kind, RankTransport::none);
    EXPECT_EQ(choose_rank_transport(BackendKind::cuda, 1, false, false, "").kind, RankTransport::none);
    EXPECT_EQ(choose_rank_transport(BackendKind::host, 2, false, false, "").kind, RankTransport::host_memory);
    const RankTransportChoice gpu = choose_rank_transport(BackendKind::cuda, 4, false, false, "");
    EXPECT_EQ(gpu.kind, RankTransport::staged_pinned);
    EXPECT_EQ(gpu.note, "");
    EXPECT_STREQ(rank_transport_label(RankTransport::staged_pinned), "staged-pinned");
    EXPECT_STREQ(rank_transport_label(RankTransport::host_memory), "host-memory");
    EXPECT_STREQ(rank_transport_label(RankTransport::none), "");
    // GPU-direct on a CUDA-aware MPI: still staged, and the note says so.
    const RankTransportChoice direct = choose_rank_transport(BackendKind::cuda, 2, true, true, "Open MPI v5.0.3");
    EXPECT_EQ(direct.kind, RankTransport::staged_pinned);
    EXPECT_NE(direct.note.find("not handed to MPI yet"), std::string::npos) << direct.note;
}

TEST(RankTransport, GpuDirectThatCannotBeHadIsRefused) {
    EXPECT_EQ(refusal(BackendKind::cuda, 2, true, false),
              "GPU-direct (--gpu-direct, spec key gpu_direct) was asked for, but the MPI library (Open MPI v4.1.4) has "
              "no CUDA support (MPIX_Query_cuda_support); drop --gpu-direct to stage particles through pinned host "
              "memory, or use a CUDA-aware MPI");
    EXPECT_EQ(refusal(BackendKind::host, 2, true, true),
              "GPU-direct (--gpu-direct, spec key gpu_direct) hands GPU memory to MPI, but this run uses the host "
              "backend; drop --gpu-direct or run with --backend cuda");
    EXPECT_NE(refusal(BackendKind::cuda, 1, true, true).find("this run is one process"), std::string::npos);
    EXPECT_EQ(refusal(BackendKind::cuda, 2, false, false), "");
}

TEST(RankTransport, ASimulationRefusesGpuDirectBeforeAllocatingAnything) {
    const Scene s = test::small_dambreak("0.05");
    SolverOptions o;
    o.subdomains = 2;
    o.gpu_direct = true;
    try {
        Simulation sim(s, o);
        FAIL() << "GPU-direct on the host backend was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("host backend"), std::string::npos) << e.what();
    }
    o.gpu_direct = false;
    o.share_gpus = true;  // nothing to share on the host: no effect
    Simulation sim(s, o);
    EXPECT_EQ(sim.rank_transport_name(), "");
}

}  // namespace
}  // namespace sph

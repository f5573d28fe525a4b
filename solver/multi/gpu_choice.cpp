#include "multi/gpu_choice.hpp"

#include <string>

#include "core/error.hpp"

namespace sph {
namespace {

std::string gpus(int n) { return std::to_string(n) + (n == 1 ? " GPU" : " GPUs"); }

}  // namespace

std::vector<int> choose_gpus(const GpuChoiceInput& in) {
    const bool mpi = in.ranks > 1;
    const std::string who = mpi ? "rank " + std::to_string(in.rank) : "this process";
    const int g = in.gpus_visible;
    // (Under sphbench the rank at fault is named in front of every sentence, so only the
    // device map's, which needs it mid-sentence, names it.)
    if (g < 1) throw InputError("the CUDA backend was asked for, but no CUDA GPU is visible");
    if (in.ranks_on_node > g && !in.share)
        throw InputError(std::to_string(in.ranks_on_node) + " MPI ranks run on one node, which has " + gpus(g) +
                         ": start at most " + std::to_string(g) + " per node, or let ranks share GPUs with " +
                         "--share-gpus (spec key share_gpus = true)");
    std::vector<int> out;
    if (!in.device_map.empty()) {
        if (int(in.device_map.size()) < in.first_subdomain + in.subdomains)
            throw InputError("the device map names " + gpus(int(in.device_map.size())) + " for " +
                             std::to_string(in.first_subdomain + in.subdomains) + " subdomains (allowed: one per subdomain)");
        for (int d = 0; d < in.subdomains; ++d) {
            const int sub = in.first_subdomain + d, gpu = in.device_map[sub];
            if (gpu < 0 || gpu >= g)
                throw InputError(std::string("the device map (--device-map, device_map) ") +
                                 "puts subdomain " + std::to_string(sub) + " on GPU " + std::to_string(gpu) + ", but " +
                                 who + " sees " + gpus(g) + " (indices 0 to " + std::to_string(g - 1) +
                                 (mpi ? " on its node)" : ")"));
            out.push_back(gpu);
        }
        return out;
    }
    const int l = in.local_rank, n = in.ranks_on_node;
    for (int d = 0; d < in.subdomains; ++d) {
        if (n > g) {
            out.push_back((l % g + d) % g);  // shared: from l mod G round all of them
        } else {
            const int first = l * g / n, size = (l + 1) * g / n - first;  // this rank's block, at least one GPU
            out.push_back(first + d % size);
        }
    }
    return out;
}

}  // namespace sph

#pragma once
// Which GPU each of a rank's subdomains runs on. A pure function of what the rank knows (its
// subdomains, its place on its node, the GPUs it sees, the device map, whether ranks may
// share a GPU), so that CI tests every rule and every refusal without a GPU.
//
// With a device map the map decides: subdomain g runs on GPU device_map[g], an index among
// the GPUs its rank sees on its node. Without one, the ranks of a node split its GPUs into
// contiguous blocks (rank l of L takes GPUs [l G / L, (l + 1) G / L); one rank per GPU when L
// = G) and a rank's subdomains go round its block; when ranks share (L > G, allowed only when
// asked), rank l starts at GPU l mod G and its subdomains go round all G from there. One
// process is the case L = 1: subdomain d on GPU d mod G, as before MPI.
#include <vector>

namespace sph {

struct GpuChoiceInput {
    int rank = 0, ranks = 1;                  // this rank of the job (messages name it under MPI)
    int first_subdomain = 0, subdomains = 1;  // its subdomains: global [first, first + subdomains)
    int local_rank = 0, ranks_on_node = 1;    // its place among the ranks of its node
    int gpus_visible = 0;                     // the GPUs it sees (CUDA_VISIBLE_DEVICES applied)
    std::vector<int> device_map;              // GPU of every global subdomain; empty: none
    bool share = false;                       // ranks of a node may share a GPU (--share-gpus)
};

// The GPU of each of the rank's subdomains, in order. Throws InputError, one sentence, when
// no GPU is visible, when more ranks run on the node than it has GPUs and sharing was not
// asked, or when the device map names a GPU the rank does not see (or does not give one GPU
// per subdomain).
std::vector<int> choose_gpus(const GpuChoiceInput& in);

}  // namespace sph

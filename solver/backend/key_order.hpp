#pragma once
// The host backend's sort by (cell, id): `order` (0..n-1 on entry) becomes the permutation
// that sorts `keys`. In a translation unit of its own: next to the force loop, the merge's
// template code changed how GCC inlined that loop (7-10% slower forces on the host with the
// same particles, measured).
#include <cstdint>
#include <vector>

namespace sph {

void order_by_keys(const std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& order);

}  // namespace sph

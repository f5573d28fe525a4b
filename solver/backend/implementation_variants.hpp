#pragma once
// Implementation variants: the registry of the named ways the CUDA backend may run a phase
// that do not change its physics (the same neighbours, sums equal up to rounding), kept apart
// from the launch policies that tune each way (cuda_launch_policy.cuh), as CUB keeps tuning
// policies apart from dispatch. Each entry has a name, its allowed values (the default first)
// and a one-line why; the harness's settings table makes a spec key and a `simulate` flag of
// each and writes them into every result's provenance. A variant travels in SubdomainConfig to
// the CUDA drivers; none is read from the environment. The host backend has one loop each and
// ignores them.
//
// Only variants that are a fallback (needed where the default cannot run) stay here;
// variants measured slower and not needed otherwise left (docs/force-loop-notes.md, "The
// variant registry").
#include <cstdint>
#include <string>
#include <vector>

namespace sph {

// The cell searches' force loop.
enum class ForceLoopVariant : std::uint8_t {
    automatic,   // "auto": the launch policy's choice per search (ForceLoopPolicySm90::compacted)
    per_thread,  // "per-thread": forces_kernel for every search
};
// How a rebuild writes the Verlet lists.
enum class ListBuildVariant : std::uint8_t {
    automatic,  // "auto": a warp per cell where the stencil allows it, else with the lanes in step
    per_lane,   // "per-lane": lane by lane everywhere
    in_step,    // "in-step": a warp's lanes walking their stencils in step wherever they can
};
// What a Verlet list's entry holds.
enum class ListEntriesVariant : std::uint8_t {
    automatic,  // "auto": the neighbour and its cell offset (ListEntry) where they fit
    plain,      // "plain": the neighbour's index only, everywhere
};

struct ImplementationVariants {
    ForceLoopVariant force_loop = ForceLoopVariant::automatic;
    ListBuildVariant list_build = ListBuildVariant::automatic;
    ListEntriesVariant list_entries = ListEntriesVariant::automatic;
    // Spelled out: the CUDA sources that include this are compiled as C++17.
    bool operator==(const ImplementationVariants& o) const {
        return force_loop == o.force_loop && list_build == o.list_build && list_entries == o.list_entries;
    }
    bool operator!=(const ImplementationVariants& o) const { return !(*this == o); }
};

// One entry of the registry. A variant's value is its index in `values` (the enum's order).
struct ImplementationVariant {
    const char* name;                 // the spec key, the runs.csv column: "list_build"
    std::vector<std::string> values;  // what it accepts, the default first
    const char* why;                  // one line: what each value runs, and why the default
    int (*get)(const ImplementationVariants&);
    void (*set)(ImplementationVariants&, int);
    const std::string& fallback() const { return values.front(); }
};

// force_loop, list_build, list_entries.
const std::vector<ImplementationVariant>& implementation_variant_registry();
const ImplementationVariant* find_implementation_variant(const std::string& name);

// Sets one variant; throws InputError "NAME: 'VALUE' is not one of ..." or "unknown
// implementation variant 'NAME' (known: ...)".
void set_implementation_variant(ImplementationVariants& v, const std::string& name, const std::string& value);
const std::string& implementation_variant_value(const ImplementationVariants& v, const ImplementationVariant& entry);

// Every variant as name=value, in the registry's order: "force_loop=auto list_build=per-lane
// list_entries=auto" (what provenance records).
std::string describe_implementation_variants(const ImplementationVariants& v);
// Several runs' variants in one line: per variant the values the runs used, in the order they
// first appear, joined by '|': "force_loop=auto|per-thread list_build=auto list_entries=auto".
std::string describe_implementation_variants(const std::vector<ImplementationVariants>& runs);

}  // namespace sph

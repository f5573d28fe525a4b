#include "backend/implementation_variants.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace sph {
namespace {

std::string quoted_list(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i)
        out += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + ("\"" + items[i] + "\"");
    return out;
}

}  // namespace

// The measurements each why cites are in docs/force-loop-notes.md (changes 7, 9 and 12).
const std::vector<ImplementationVariant>& implementation_variant_registry() {
    static const std::vector<ImplementationVariant> registry = {
        {"force_loop",
         {"auto", "per-thread"},
         "CUDA cell-search force loop: auto compacts each warp's pairs on cells of the support (-12% a step) and "
         "runs the per-thread loop elsewhere; per-thread everywhere is the fallback for merged z-runs across a "
         "periodic z face",
         [](const ImplementationVariants& v) { return int(v.force_loop); },
         [](ImplementationVariants& v, int k) { v.force_loop = ForceLoopVariant(k); }},
        {"list_build",
         {"auto", "per-lane", "in-step"},
         "CUDA Verlet-list build: auto gives each cell a warp whose lanes test shared candidates (stencils of at "
         "most 32 columns on an open z; change 22); in-step, a warp's lanes walking their own stencils in step, is "
         "the fallback elsewhere; per-lane the one for merged z-runs across a periodic z face",
         [](const ImplementationVariants& v) { return int(v.list_build); },
         [](ImplementationVariants& v, int k) { v.list_build = ListBuildVariant(k); }},
        {"list_entries",
         {"auto", "plain"},
         "CUDA Verlet-list entries: auto stores each neighbour's cell offset where it fits (open grids, stencils of "
         "at most 3 cells a side, under 2^23 particles; -6 to -10% a step); plain, the index only, is the fallback "
         "elsewhere",
         [](const ImplementationVariants& v) { return int(v.list_entries); },
         [](ImplementationVariants& v, int k) { v.list_entries = ListEntriesVariant(k); }},
    };
    return registry;
}

const ImplementationVariant* find_implementation_variant(const std::string& name) {
    for (const auto& e : implementation_variant_registry())
        if (name == e.name) return &e;
    return nullptr;
}

void set_implementation_variant(ImplementationVariants& v, const std::string& name, const std::string& value) {
    const ImplementationVariant* e = find_implementation_variant(name);
    if (!e) {
        std::vector<std::string> known;
        for (const auto& k : implementation_variant_registry()) known.emplace_back(k.name);
        throw InputError("unknown implementation variant '" + name + "' (known: " + quoted_list(known) + ")");
    }
    const auto it = std::find(e->values.begin(), e->values.end(), value);
    if (it == e->values.end())
        throw InputError(name + ": '" + value + "' is not one of " + quoted_list(e->values));
    e->set(v, int(it - e->values.begin()));
}

const std::string& implementation_variant_value(const ImplementationVariants& v, const ImplementationVariant& entry) {
    return entry.values.at(std::size_t(entry.get(v)));
}

std::string describe_implementation_variants(const ImplementationVariants& v) {
    return describe_implementation_variants(std::vector<ImplementationVariants>{v});
}

std::string describe_implementation_variants(const std::vector<ImplementationVariants>& runs) {
    std::string out;
    for (const auto& e : implementation_variant_registry()) {
        std::vector<std::string> used;
        for (const auto& v : runs) {
            const std::string& value = implementation_variant_value(v, e);
            if (std::find(used.begin(), used.end(), value) == used.end()) used.push_back(value);
        }
        if (used.empty()) used.push_back(e.fallback());
        std::string joined;
        for (const auto& u : used) joined += (joined.empty() ? "" : "|") + u;
        out += (out.empty() ? "" : " ") + std::string(e.name) + "=" + joined;
    }
    return out;
}

}  // namespace sph

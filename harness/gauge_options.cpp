#include "gauge_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <set>

#include "core/error.hpp"
#include "solver_settings.hpp"

namespace sph {

namespace {

std::vector<std::string> keys_of(GaugeKind kind) {
    switch (kind) {
    case GaugeKind::pressure:
    case GaugeKind::velocity: return {"x", "y", "z"};
    case GaugeKind::water_level: return {"x", "y"};
    case GaugeKind::max_height: return {"x", "y", "radius"};
    case GaugeKind::force: return {"body"};
    }
    return {};
}

std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
    return out;
}

double number_of(const std::string& text, const std::string& key, const std::string& where) {
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(v))
        throw InputError(where + ": '" + key + "' must be a number, got '" + text + "'");
    return v;
}

}  // namespace

Gauge make_gauge(const std::string& kind_name, const std::map<std::string, std::string>& keys, const std::string& where) {
    Gauge g;
    try {
        g.kind = gauge_kind(kind_name);
    } catch (const InputError& e) {
        throw InputError(where + ": " + e.what());
    }
    std::vector<std::string> position = keys_of(g.kind);
    std::vector<std::string> known = position;
    known.insert(known.end(), {"every", "name"});
    for (const auto& [k, v] : keys)
        if (std::find(known.begin(), known.end(), k) == known.end())
            throw InputError(where + ": unknown key '" + k + "' for a " + kind_name + " gauge (its keys: " + join(known) + ")");
    position.push_back("every");
    for (const auto& k : position)
        if (!keys.count(k)) throw InputError(where + ": a " + kind_name + " gauge needs '" + k + "' (its keys: " + join(known) + ")");
    for (const auto& [k, v] : keys) {
        if (k == "name") {
            if (v.empty() || filename_safe(v) != v)
                throw InputError(where + ": 'name' must be letters, digits, '.', '_' or '-', got '" + v + "'");
            g.name = v;
        } else if (k == "body") {
            g.body = v;
        } else {
            const double x = number_of(v, k, where);
            if (k == "x") g.x = x;
            else if (k == "y") g.y = x;
            else if (k == "z") g.z = x;
            else if (k == "radius") g.radius = x;
            else if (k == "every") g.every = x;
        }
    }
    if (!(g.every > 0)) throw InputError(where + ": 'every' must be above 0 simulated seconds, got " + keys.at("every"));
    if (g.kind == GaugeKind::max_height && !(g.radius > 0))
        throw InputError(where + ": 'radius' must be above 0 m, got " + keys.at("radius"));
    return g;
}

Gauge parse_gauge_option(const std::string& text) {
    const std::string where = "--gauge '" + text + "'";
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos)
        throw InputError(where + ": expected KIND:key=value,... (e.g. water_level:x=0.6,y=0.335,every=0.01)");
    std::map<std::string, std::string> keys;
    std::size_t start = colon + 1;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError(where + ": '" + item + "' is not key=value");
        const std::string key = item.substr(0, eq);
        if (keys.count(key)) throw InputError(where + ": '" + key + "' is given twice");
        keys[key] = item.substr(eq + 1);
        start = comma + 1;
    }
    return make_gauge(text.substr(0, colon), keys, where);
}

void name_gauges(std::vector<Gauge>& gauges) {
    int count[5] = {0, 0, 0, 0, 0};
    std::set<std::string> names;
    for (Gauge& g : gauges) {
        const int k = int(g.kind);
        ++count[k];
        if (g.name.empty()) g.name = gauge_kind_name(g.kind) + std::to_string(count[k]);
        if (!names.insert(g.name).second) throw InputError("gauge name '" + g.name + "' is used twice");
    }
}

std::vector<Gauge> merge_gauges(const std::vector<Gauge>& from_case, const std::vector<Gauge>& requested) {
    // A name the request gives twice would replace one case gauge twice: refused as it would
    // be without a case.
    std::vector<Gauge> request_named = requested;
    name_gauges(request_named);
    std::vector<Gauge> gauges = from_case;
    const auto case_end = std::ptrdiff_t(from_case.size());
    for (const Gauge& g : requested) {
        const auto same = std::find_if(gauges.begin(), gauges.begin() + case_end,
                                       [&](const Gauge& c) { return !g.name.empty() && c.name == g.name; });
        if (same != gauges.begin() + case_end) *same = g;
        else gauges.push_back(g);
    }
    name_gauges(gauges);
    return gauges;
}

}  // namespace sph

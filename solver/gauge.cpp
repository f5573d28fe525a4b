#include "gauge.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/water_mass_threshold.hpp"

namespace sph {

namespace {

const char* const kind_names[] = {"pressure", "velocity", "water_level", "max_height", "force"};

std::string describe(const Gauge& g) { return "gauge '" + g.name + "' (" + gauge_kind_name(g.kind) + ")"; }

GaugeProbe probe_at(GaugeKind kind, const double x[3], const Grid& grid) {
    GaugeProbe p;
    p.kind = kind;
    const real3 cs = grid.view.cell_size;
    const double size[3] = {cs.x, cs.y, cs.z};
    const int n[3] = {grid.view.nx, grid.view.ny, grid.view.nz};
    const bool periodic[3] = {grid.view.periodic_x, grid.view.periodic_y, grid.view.periodic_z};
    int c[3];
    double off[3];
    for (int a = 0; a < 3; ++a) {
        const double rel = x[a] - grid.origin[a];
        c[a] = int(std::floor(rel / size[a]));
        off[a] = rel - c[a] * size[a];
        if (periodic[a]) c[a] = wrap_index(c[a], n[a]);
    }
    p.cell = {c[0], c[1], c[2]};
    p.offset = make3(real(off[0]), real(off[1]), real(off[2]));
    return p;
}

// The water level's line: every dp / 2 from the domain's bottom to its top.
int level_samples(const Scene& s) { return int(std::floor((s.hi[2] - s.lo[2]) / (0.5 * s.dp) + 1e-9)) + 1; }

}  // namespace

const char* gauge_kind_name(GaugeKind kind) { return kind_names[int(kind)]; }

GaugeKind gauge_kind(const std::string& name) {
    for (int k = 0; k < 5; ++k)
        if (name == kind_names[k]) return GaugeKind(k);
    throw InputError("unknown gauge kind '" + name + "'; the kinds are pressure, velocity, water_level, max_height, force");
}

std::vector<std::string> gauge_columns(const Gauge& g) {
    if (g.kind == GaugeKind::velocity || g.kind == GaugeKind::force) return {g.name + "_x", g.name + "_y", g.name + "_z"};
    return {g.name};
}

void check_gauge(const Gauge& g, const Scene& s) {
    if (g.kind == GaugeKind::force) {
        if (s.body(g.body)) return;
        std::string known;
        for (const auto& b : s.bodies) known += (known.empty() ? "'" : ", '") + b.name + "'";
        throw InputError(describe(g) + ": scene '" + s.name + "' has no body '" + g.body + "'" +
                         (known.empty() ? " (it names none)" : "; its bodies are " + known));
    }
    const bool line = g.kind == GaugeKind::water_level || g.kind == GaugeKind::max_height;
    const double x[3] = {g.x, g.y, g.z};
    static const char* axis[] = {"x", "y", "z"};
    for (int a = 0; a < (line ? 2 : 3); ++a)
        if (!(x[a] >= s.lo[a] && x[a] <= s.hi[a])) {
            std::ostringstream m;
            m << describe(g) << ": " << axis[a] << " = " << x[a] << " lies outside the domain of scene '" << s.name
              << "' (" << axis[a] << " from " << s.lo[a] << " to " << s.hi[a] << " m)";
            throw InputError(m.str());
        }
    if (g.kind == GaugeKind::max_height && !(g.radius > 0))
        throw InputError(describe(g) + ": radius must be above 0 m, got " + std::to_string(g.radius));
}

std::vector<GaugeProbe> gauge_probes(const Gauge& g, const Scene& s, const Grid& grid) {
    if (g.kind == GaugeKind::force) {
        const BoundaryBody* b = s.body(g.body);
        GaugeProbe p;
        p.kind = GaugeKind::force;
        p.body_first = std::uint32_t(b->first);
        p.body_end = std::uint32_t(b->first + b->count);
        return {p};
    }
    if (g.kind == GaugeKind::water_level) {
        std::vector<GaugeProbe> line;
        for (int k = 0; k < level_samples(s); ++k) {
            const double x[3] = {g.x, g.y, s.lo[2] + 0.5 * s.dp * k};
            line.push_back(probe_at(g.kind, x, grid));
        }
        return line;
    }
    const double x[3] = {g.x, g.y, g.kind == GaugeKind::max_height ? 0.5 * (s.lo[2] + s.hi[2]) : g.z};
    GaugeProbe p = probe_at(g.kind, x, grid);
    p.radius = real(g.radius);
    return {p};
}

std::vector<double> gauge_values(const Gauge& g, const Scene& s, const Grid& grid, const GaugeSum* sums) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const GaugeSum& a = sums[0];
    switch (g.kind) {
    case GaugeKind::pressure: return {a.v[3] > 0 ? a.v[0] / a.v[3] : nan};
    case GaugeKind::velocity:
        if (!(a.v[3] > 0)) return {nan, nan, nan};
        return {a.v[0] / a.v[3], a.v[1] / a.v[3], a.v[2] / a.v[3]};
    case GaugeKind::force: return {a.v[0], a.v[1], a.v[2]};
    case GaugeKind::max_height: return {a.v[3] > 0 ? grid.origin[2] + a.v[0] : nan};
    case GaugeKind::water_level:
        return {first_threshold_crossing(std::size_t(level_samples(s)), s.lo[2], 0.5 * s.dp,
                                        water_mass_threshold(double(s.params.mass), s.dp),
                                        [&](std::size_t k) { return sums[k].v[0]; })};
    }
    return {nan};
}

}  // namespace sph

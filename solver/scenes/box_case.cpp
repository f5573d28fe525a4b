#include "scenes/box_case.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "scenes/lattice.hpp"
#include "scenes/mesh_fill.hpp"

namespace sph {
namespace {

constexpr double tolerance = 1e-9;  // metres: a box on a face of another is on it, not across
const char* const axis_name[3] = {"x", "y", "z"};

std::string point_text(const std::array<double, 3>& p) {
    std::ostringstream o;
    o.precision(10);
    o << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
    return o.str();
}

std::string number_text(double v) {
    std::ostringstream o;
    o.precision(6);
    o << v;
    return o.str();
}

bool inside(const CaseBox& inner, const CaseBox& outer, bool open_top) {
    for (int a = 0; a < 3; ++a) {
        if (inner.min[a] < outer.min[a] - tolerance) return false;
        if (inner.max[a] > outer.max[a] + tolerance && !(a == 2 && open_top)) return false;
    }
    return true;
}

bool overlap(const CaseBox& a, const CaseBox& b) {
    for (int k = 0; k < 3; ++k)
        if (std::min(a.max[k], b.max[k]) - std::max(a.min[k], b.min[k]) <= tolerance) return false;
    return true;
}

// Inclusive lattice index ranges of the boxes, from the tank's min corner.
struct IndexBox {
    long lo[3], hi[3];
    bool holds(long i, long j, long k) const {
        return i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2];
    }
};

class CaseLattice {
public:
    CaseLattice(const CaseTank& tank, double dp) : dp_(dp), open_top_(tank.open_top) {
        for (int a = 0; a < 3; ++a) origin_[a] = tank.min[a];
        tank_ = index_box(tank);
    }
    long index(int axis, double x) const { return lattice_index(x - origin_[axis], dp_); }
    IndexBox index_box(const CaseBox& b) const {
        IndexBox r;
        for (int a = 0; a < 3; ++a) {
            r.lo[a] = index(a, b.min[a]);
            r.hi[a] = index(a, b.max[a]);
        }
        return r;
    }
    const IndexBox& tank() const { return tank_; }
    const double* origin() const { return origin_; }
    // A point of the tank's box that holds a wall particle (its innermost layer).
    bool wall(long i, long j, long k) const {
        return i == 0 || i == tank_.hi[0] || j == 0 || j == tank_.hi[1] || k == 0 || (k == tank_.hi[2] && !open_top_);
    }
    // Whether the face of a box at index `at` along `axis` lies on a wall (so it is no face).
    bool on_wall(int axis, long at) const {
        return at == 0 || (at == tank_.hi[axis] && (axis < 2 || !open_top_));
    }
    std::array<double, 3> position(long i, long j, long k) const {
        return {origin_[0] + dp_ * i, origin_[1] + dp_ * j, origin_[2] + dp_ * k};
    }

private:
    double dp_;
    bool open_top_;
    double origin_[3];
    IndexBox tank_;
};

void check_spacing(const CaseBox& b, const std::string& what, double dp) {
    for (int a = 0; a < 3; ++a)
        if (b.max[a] - b.min[a] < dp - tolerance)
            throw InputError(b.where + ": " + what + " is " + number_text(b.max[a] - b.min[a]) + " m in " + axis_name[a] +
                             " ('max' - 'min'), less than one spacing (dp = " + number_text(dp) + " m)");
}

void add_obstacle(Scene& s, const CaseLattice& lat, const IndexBox& b, int layers, const std::vector<IndexBox>& earlier) {
    constexpr long far = std::numeric_limits<long>::max();
    for (long i = b.lo[0]; i <= b.hi[0]; ++i)
        for (long j = b.lo[1]; j <= b.hi[1]; ++j)
            for (long k = b.lo[2]; k <= b.hi[2]; ++k) {
                if (lat.wall(i, j, k)) continue;
                if (std::any_of(earlier.begin(), earlier.end(), [&](const IndexBox& e) { return e.holds(i, j, k); })) continue;
                // Depth below the faces the fluid can reach (a face on a wall is none).
                const long at[3] = {i, j, k};
                long depth = far;
                for (int a = 0; a < 3; ++a) {
                    if (!lat.on_wall(a, b.lo[a])) depth = std::min(depth, at[a] - b.lo[a]);
                    if (!lat.on_wall(a, b.hi[a])) depth = std::min(depth, b.hi[a] - at[a]);
                }
                if (depth >= layers) continue;
                s.position.push_back(lat.position(i, j, k));
                s.velocity.push_back({0, 0, 0});
            }
}

// The free surface of a hydrostatic box: half a spacing above its top layer.
struct Column {
    IndexBox box;
    double surface;
};

}  // namespace

const std::vector<std::string>& box_case_option_keys() {
    static const std::vector<std::string> keys = {"dp",      "kernel", "c0_factor", "alpha", "delta", "density_diffusion",
                                                  "gravity", "rho0",   "coef_h",    "cfl"};
    return keys;
}

void check_box_case(const BoxCase& c) {
    auto check_order = [](const CaseBox& b) {
        for (int a = 0; a < 3; ++a)
            if (!(b.max[a] > b.min[a]))
                throw InputError(b.where + ": 'max' " + point_text(b.max) + " must be above 'min' " + point_text(b.min) +
                                 " along " + axis_name[a]);
    };
    check_order(c.tank);
    const std::string tank_text = " the tank ([case.tank] 'min' " + point_text(c.tank.min) + ", 'max' " +
                                  point_text(c.tank.max) + ")";
    for (const auto& f : c.fluids) {
        check_order(f);
        if (!inside(f, c.tank, false))
            throw InputError(f.where + ": the fluid box ('min' " + point_text(f.min) + ", 'max' " + point_text(f.max) +
                             ") reaches outside" + tank_text);
    }
    for (const auto& o : c.obstacles) {
        check_order(o);
        if (!inside(o, c.tank, c.tank.open_top))
            throw InputError(o.where + ": obstacle '" + o.name + "' ('min' " + point_text(o.min) + ", 'max' " +
                             point_text(o.max) + ") reaches outside" + tank_text);
        for (const auto& f : c.fluids)
            if (overlap(f, o))
                throw InputError(f.where + ": the fluid box ('min' " + point_text(f.min) + ", 'max' " + point_text(f.max) +
                                 ") overlaps obstacle '" + o.name + "' (" + o.where + ")");
    }
}

Scene build_box_case(const BoxCase& c, const std::map<std::string, std::string>& options) {
    std::map<std::string, std::string> merged = c.options;
    for (const auto& [k, v] : options) merged[k] = v;
    SceneOptions opt(merged);
    Scene s;
    s.name = c.name;
    s.dp = opt.number("dp", c.dp, 1e-6, 10);
    const double dp = s.dp;
    check_box_case(c);
    check_spacing(c.tank, "the tank", dp);
    for (const auto& f : c.fluids) check_spacing(f, "the fluid box", dp);
    for (const auto& o : c.obstacles) check_spacing(o, "obstacle '" + o.name + "'", dp);
    const CaseLattice lat(c.tank, dp);

    // Boundary: the tank's walls, then each obstacle, each a body.
    const IndexBox& t = lat.tank();
    add_box_boundary(s, lat.origin(), {{t.lo[0], t.lo[1], t.lo[2]}, {t.hi[0], t.hi[1], t.hi[2]}}, c.tank.layers,
                     c.tank.open_top);
    s.bodies.push_back({c.tank.name, 0, s.size()});
    std::vector<IndexBox> obstacles;
    for (const auto& o : c.obstacles) {
        const std::size_t first = s.size();
        const IndexBox b = lat.index_box(o);
        add_obstacle(s, lat, b, o.layers > 0 ? o.layers : c.tank.layers, obstacles);
        obstacles.push_back(b);
        s.bodies.push_back({o.name, first, s.size() - first});
    }
    s.n_boundary = s.size();

    // Fluid: the boxes, then the meshes; a point already taken is not made twice.
    auto on_obstacle = [&](long i, long j, long k) {
        return std::any_of(obstacles.begin(), obstacles.end(), [&](const IndexBox& b) { return b.holds(i, j, k); });
    };
    std::vector<IndexBox> fluid_boxes;
    std::vector<Column> columns;
    std::vector<int> column_of;  // per fluid particle: its hydrostatic column, or -1
    double water_height = 0;     // the highest water above the floor, for the sound speed
    for (const auto& f : c.fluids) {
        const IndexBox b = lat.index_box(f);
        const int column = f.hydrostatic ? int(columns.size()) : -1;
        if (f.hydrostatic) columns.push_back({b, lat.origin()[2] + (double(b.hi[2]) + 0.5) * dp});
        const std::array<float, 3> v = {float(f.velocity[0]), float(f.velocity[1]), float(f.velocity[2])};
        for (long i = b.lo[0]; i <= b.hi[0]; ++i)
            for (long j = b.lo[1]; j <= b.hi[1]; ++j)
                for (long k = b.lo[2]; k <= b.hi[2]; ++k) {
                    if (lat.wall(i, j, k) || on_obstacle(i, j, k)) continue;
                    if (std::any_of(fluid_boxes.begin(), fluid_boxes.end(), [&](const IndexBox& e) { return e.holds(i, j, k); }))
                        continue;
                    s.position.push_back(lat.position(i, j, k));
                    s.velocity.push_back(v);
                    column_of.push_back(column);
                }
        fluid_boxes.push_back(b);
        water_height = std::max(water_height, f.max[2] - c.tank.min[2]);
    }
    std::vector<MeshFill> fills;
    for (const auto& m : c.meshes) {
        const std::string path = find_mesh(m.file);
        const TriangleMesh shaped = z_up_scaled(read_obj(path, MeshCheck::AllowSmallHoles), m.height, m.y_up);
        const TriangleMesh mesh = translated(shaped, {m.min[0] - shaped.lo.x, m.min[1] - shaped.lo.y, m.min[2] - shaped.lo.z});
        CaseBox bounds{{mesh.lo.x, mesh.lo.y, mesh.lo.z}, {mesh.hi.x, mesh.hi.y, mesh.hi.z}, m.where};
        if (!inside(bounds, c.tank, false))
            throw InputError(m.where + ": mesh '" + m.file + "' placed at 'min' " + point_text(m.min) + " reaches to " +
                             point_text(bounds.max) + ", outside the tank ([case.tank] 'max' " + point_text(c.tank.max) + ")");
        const MeshInsideTest test(mesh);
        const MeshFill fill = fill_mesh(mesh, test, dp, {lat.origin()[0], lat.origin()[1], lat.origin()[2]});
        auto in_fill = [](const MeshFill& f, long i, long j, long k) {
            const long a = i - f.first_index[0], b = j - f.first_index[1], d = k - f.first_index[2];
            if (a < 0 || b < 0 || d < 0 || a >= f.n[0] || b >= f.n[1] || d >= f.n[2]) return false;
            return f.inside[(std::size_t(a) * f.n[1] + b) * f.n[2] + d] != 0;
        };
        for (long i = fill.first_index[0]; i < fill.first_index[0] + fill.n[0]; ++i)
            for (long j = fill.first_index[1]; j < fill.first_index[1] + fill.n[1]; ++j)
                for (long k = fill.first_index[2]; k < fill.first_index[2] + fill.n[2]; ++k) {
                    if (!in_fill(fill, i, j, k) || lat.wall(i, j, k)) continue;
                    if (on_obstacle(i, j, k)) {
                        const auto p = lat.position(i, j, k);
                        throw InputError(m.where + ": mesh '" + m.file + "' overlaps an obstacle at " + point_text(p));
                    }
                    if (std::any_of(fluid_boxes.begin(), fluid_boxes.end(), [&](const IndexBox& e) { return e.holds(i, j, k); }) ||
                        std::any_of(fills.begin(), fills.end(), [&](const MeshFill& e) { return in_fill(e, i, j, k); }))
                        continue;
                    s.position.push_back(lat.position(i, j, k));
                    s.velocity.push_back({0, 0, 0});
                    column_of.push_back(-1);
                }
        fills.push_back(fill);
        water_height = std::max(water_height, mesh.hi.z - c.tank.min[2]);
    }

    const double g = opt.number("gravity", 9.81, 0, 1e3);
    set_common_physics(s, opt, opt.number("c0_factor", 20, 1, 1000) * std::sqrt(g * water_height), "wendland");

    // Hydrostatic start: each fluid particle by its column's surface; a wall or obstacle
    // particle within the tank's wall layers of a column's footprint by the deepest such column.
    if (!columns.empty()) {
        auto density = [&](double depth) {
            const double p = s.params.rho0 * g * std::max(0.0, depth);
            return float(s.params.rho0 * std::pow(1 + p / s.params.tait_b, 1.0 / 7.0));
        };
        s.density.resize(s.size());
        const long reach = c.tank.layers;
        for (std::size_t n = 0; n < s.n_boundary; ++n) {
            const auto& x = s.position[n];
            const long i = lat.index(0, x[0]), j = lat.index(1, x[1]);
            double depth = 0;
            for (const auto& col : columns)
                if (i >= col.box.lo[0] - reach && i <= col.box.hi[0] + reach && j >= col.box.lo[1] - reach &&
                    j <= col.box.hi[1] + reach)
                    depth = std::max(depth, col.surface - x[2]);
            s.density[n] = density(depth);
        }
        for (std::size_t n = s.n_boundary; n < s.size(); ++n) {
            const int col = column_of[n - s.n_boundary];
            s.density[n] = density(col < 0 ? 0.0 : columns[std::size_t(col)].surface - s.position[n][2]);
        }
    }

    // Domain: the tank grown by its walls and a spacing (more than the lattice's half-spacing
    // rounding of its faces needs), unless the case gives one or its top.
    const double margin = (c.tank.layers + 1) * dp;
    for (int a = 0; a < 3; ++a) {
        s.lo[a] = c.has_domain ? c.domain_lo[a] : c.tank.min[a] - margin;
        s.hi[a] = c.has_domain ? c.domain_hi[a] : c.tank.max[a] + margin;
    }
    if (c.domain_top > 0) s.hi[2] = c.domain_top;
    if (c.has_domain || c.domain_top > 0)
        for (const auto& x : s.position)
            for (int a = 0; a < 3; ++a)
                if (x[a] < s.lo[a] || x[a] > s.hi[a])
                    throw InputError(c.domain_where + ": the domain does not hold the particle at " + point_text(x) +
                                     " (the walls reach " + std::to_string(c.tank.layers - 1) +
                                     " spacings beyond the tank's faces, which the lattice may move by half a spacing)");
    opt.finish(s.name);
    s.settings = opt.resolved();
    s.settings["case"] = c.source;
    return s;
}

}  // namespace sph

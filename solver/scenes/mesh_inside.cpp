#include "scenes/mesh_inside.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace sph {

namespace {

inline double coord(const Vec3d& p, int a) { return a == 0 ? p.x : a == 1 ? p.y : p.z; }

struct EdgeTest {
    double w;  // twice the signed area of (a, b, p); barycentric weight of the opposite vertex
    int s;     // its sign under the perturbation p + (eps, eps^2): never 0 for a real edge
};

// Side of p relative to the directed 2D edge a->b. The value is computed with the endpoints
// in a canonical (lexicographic) order and negated for the reverse direction, so the two
// triangles sharing an edge see exactly opposite results even in floating point; exact zeros
// are resolved by the symbolic perturbation p + (eps, eps^2), eps -> 0+, which is the same
// point for every triangle. Hence a ray through an edge or vertex is claimed exactly once.
inline EdgeTest edge_test(double au, double av, double bu, double bv, double pu, double pv) {
    const bool flip = bu < au || (bu == au && bv < av);
    if (flip) {
        std::swap(au, bu);
        std::swap(av, bv);
    }
    const double du = bu - au, dv = bv - av;
    // p == b must give an exact 0; with FMA contraction du*dv - dv*du might not.
    const double w = (pu == bu && pv == bv) ? 0.0 : du * (pv - av) - dv * (pu - au);
    // e(p + (eps, eps^2)) = w + du*eps^2 - dv*eps; after canonical ordering du >= 0.
    int s = w > 0 ? 1 : w < 0 ? -1 : dv != 0 ? (dv < 0 ? 1 : -1) : du > 0 ? 1 : 0;
    return flip ? EdgeTest{-w, -s} : EdgeTest{w, s};
}

inline int bin_of(double x, double lo, double inv, int n) {
    const int i = static_cast<int>((x - lo) * inv);  // x >= lo, so truncation is floor
    return std::clamp(i, 0, n - 1);
}

// First lattice index t in [0, n] with x0 + h*t > c (n if none): the same comparison that
// contains() makes, so both classify a lattice point identically.
inline long first_above(double x0, double h, long n, double c) {
    if (!(c < std::numeric_limits<double>::infinity())) return n;
    double g = std::ceil((c - x0) / h);
    long t = static_cast<long>(std::clamp(g, 0.0, static_cast<double>(n)));
    while (t > 0 && x0 + h * static_cast<double>(t - 1) > c) --t;
    while (t < n && !(x0 + h * static_cast<double>(t) > c)) ++t;
    return t;
}

std::vector<std::array<double, 9>> finite_triangles(const TriangleMesh& mesh) {
    const long nv = static_cast<long>(mesh.vertices.size());
    std::vector<std::array<double, 9>> tri;
    tri.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
        std::array<double, 9> c{};
        for (int k = 0; k < 3; ++k) {
            if (t[k] < 0 || t[k] >= nv) throw std::invalid_argument("MeshInsideTest: triangle index out of range");
            const Vec3d& v = mesh.vertices[t[k]];
            c[3 * k] = v.x, c[3 * k + 1] = v.y, c[3 * k + 2] = v.z;
        }
        if (std::all_of(c.begin(), c.end(), [](double x) { return std::isfinite(x); })) tri.push_back(c);
    }
    return tri;
}

// Six times the signed volume (sum of tetrahedra to the origin): its sign is the orientation.
double signed_volume6(const std::vector<std::array<double, 9>>& tri) {
    double v = 0;
    for (const auto& c : tri)
        v += c[0] * (c[4] * c[8] - c[5] * c[7]) - c[1] * (c[3] * c[8] - c[5] * c[6]) + c[2] * (c[3] * c[7] - c[4] * c[6]);
    return v;
}

}  // namespace

MeshInsideTest::MeshInsideTest(const TriangleMesh& mesh)
    : tri_(finite_triangles(mesh)), winding_(tri_), orientation_(signed_volume6(tri_) < 0 ? -1.0 : 1.0) {
    for (int a = 0; a < 3; ++a) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        AxisGrid& g = grid_[a];
        // Projected boxes; triangles seen edge-on (zero width or height) can never be
        // crossed by a perturbed ray, so they are left out of this axis's grid.
        struct Box { double u0, u1, v0, v1; };
        std::vector<Box> box(tri_.size());
        std::vector<int> used;
        used.reserve(tri_.size());
        double lo_u = HUGE_VAL, hi_u = -HUGE_VAL, lo_v = HUGE_VAL, hi_v = -HUGE_VAL;
        for (size_t i = 0; i < tri_.size(); ++i) {
            const auto& c = tri_[i];
            Box b{std::min({c[u], c[3 + u], c[6 + u]}), std::max({c[u], c[3 + u], c[6 + u]}),
                  std::min({c[v], c[3 + v], c[6 + v]}), std::max({c[v], c[3 + v], c[6 + v]})};
            if (b.u0 == b.u1 || b.v0 == b.v1) continue;
            box[i] = b;
            used.push_back(static_cast<int>(i));
            lo_u = std::min(lo_u, b.u0), hi_u = std::max(hi_u, b.u1);
            lo_v = std::min(lo_v, b.v0), hi_v = std::max(hi_v, b.v1);
        }
        g.start.assign(2, 0);
        if (used.empty()) continue;  // hi < lo: every ray misses
        g.lo_u = lo_u, g.hi_u = hi_u, g.lo_v = lo_v, g.hi_v = hi_v;
        // About one bin per triangle, shaped like the projected box: bins come out near the
        // typical triangle size, so each ray tests only a handful of candidates.
        const double W = hi_u - lo_u, H = hi_v - lo_v, n = static_cast<double>(used.size());
        g.nu = static_cast<int>(std::clamp(std::ceil(std::sqrt(n * W / H)), 1.0, 2048.0));
        g.nv = static_cast<int>(std::clamp(std::ceil(std::sqrt(n * H / W)), 1.0, 2048.0));
        g.inv_u = g.nu / W, g.inv_v = g.nv / H;
        g.start.assign(static_cast<size_t>(g.nu) * g.nv + 1, 0);
        auto for_bins = [&](const Box& b, auto&& f) {
            const int i0 = bin_of(b.u0, lo_u, g.inv_u, g.nu), i1 = bin_of(b.u1, lo_u, g.inv_u, g.nu);
            const int j0 = bin_of(b.v0, lo_v, g.inv_v, g.nv), j1 = bin_of(b.v1, lo_v, g.inv_v, g.nv);
            for (int i = i0; i <= i1; ++i)
                for (int j = j0; j <= j1; ++j) f(static_cast<size_t>(i) * g.nv + j);
        };
        for (int t : used) for_bins(box[t], [&](size_t bin) { ++g.start[bin + 1]; });
        for (size_t k = 1; k < g.start.size(); ++k) g.start[k] += g.start[k - 1];
        g.items.resize(static_cast<size_t>(g.start.back()));
        std::vector<int> fill(g.start.begin(), g.start.end() - 1);
        for (int t : used) for_bins(box[t], [&](size_t bin) { g.items[fill[bin]++] = t; });
    }
}

void MeshInsideTest::crossings(int a, double pu, double pv, std::vector<double>& out) const {
    out.clear();
    const AxisGrid& g = grid_[a];
    if (!(pu >= g.lo_u && pu <= g.hi_u && pv >= g.lo_v && pv <= g.hi_v)) return;
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    const size_t bin = static_cast<size_t>(bin_of(pu, g.lo_u, g.inv_u, g.nu)) * g.nv +
                       bin_of(pv, g.lo_v, g.inv_v, g.nv);
    for (int k = g.start[bin]; k < g.start[bin + 1]; ++k) {
        const auto& c = tri_[g.items[k]];
        const double u0 = c[u], v0 = c[v], u1 = c[3 + u], v1 = c[3 + v], u2 = c[6 + u], v2 = c[6 + v];
        // Cheap box rejection; non-strict so boundary cases reach the exact rule below.
        if (pu < std::min({u0, u1, u2}) || pu > std::max({u0, u1, u2}) || pv < std::min({v0, v1, v2}) ||
            pv > std::max({v0, v1, v2}))
            continue;
        const EdgeTest e01 = edge_test(u0, v0, u1, v1, pu, pv);
        const EdgeTest e12 = edge_test(u1, v1, u2, v2, pu, pv);
        if (e01.s == 0 || e01.s != e12.s) continue;
        const EdgeTest e20 = edge_test(u2, v2, u0, v0, pu, pv);
        if (e20.s != e01.s) continue;
        const double sum = e12.w + e20.w + e01.w;
        if (sum == 0) continue;  // rounding on a sliver; cannot place the crossing
        const double a0 = c[a], a1 = c[3 + a], a2 = c[6 + a];
        const double x = (e12.w * a0 + e20.w * a1 + e01.w * a2) / sum;
        out.push_back(std::clamp(x, std::min({a0, a1, a2}), std::max({a0, a1, a2})));
    }
}

bool MeshInsideTest::inside_by_winding(Vec3d p) const {
    // The far field as dipoles is good to a few percent; near 1/2 it is summed exactly.
    const double w = orientation_ * winding_.at(p);
    if (std::fabs(w - 0.5) > 0.2) return w > 0.5;
    return orientation_ * winding_.at(p, 0.0) > 0.5;
}

bool MeshInsideTest::decide(unsigned rays, Vec3d p) const {
    const unsigned in = rays & 7u, odd = rays >> 3 & 7u;
    if (odd == 0 && (in == 0 || in == 7)) return in == 7;  // all of a closed mesh's points
    // Lines with an even count are likely right, but two holes on one line (or facing holes
    // across a tunnel) fool them as they fool the winding number: inside needs both.
    int even_in = 0, even_out = 0;
    for (int a = 0; a < 3; ++a)
        if (!(odd >> a & 1u)) ++((in >> a & 1u) ? even_in : even_out);
    if (even_out > even_in) return false;
    return inside_by_winding(p);
}

bool MeshInsideTest::contains(Vec3d p) const {
    std::vector<double> c;
    unsigned rays = 0;
    for (int a = 0; a < 3; ++a) {
        const double x = coord(p, a);
        crossings(a, coord(p, (a + 1) % 3), coord(p, (a + 2) % 3), c);
        if (c.size() & 1) rays |= 8u << a;
        // Parity of crossings before x (a ray to -infinity), as in lattice_inside.
        if (std::count_if(c.begin(), c.end(), [x](double q) { return q < x; }) & 1) rays |= 1u << a;
    }
    return decide(rays, p);
}

std::vector<uint8_t> MeshInsideTest::lattice_inside(Vec3d origin, double spacing, int nx, int ny, int nz) const {
    if (nx < 0 || ny < 0 || nz < 0) throw std::invalid_argument("lattice_inside: negative lattice size");
    if (!(spacing > 0) || !std::isfinite(spacing)) throw std::invalid_argument("lattice_inside: bad spacing");
    const long n[3] = {nx, ny, nz};
    const size_t stride[3] = {static_cast<size_t>(ny) * nz, static_cast<size_t>(nz), 1};
    const double o[3] = {origin.x, origin.y, origin.z};
    const double h = spacing;
    // Per point and axis a: bit a when that axis's ray found it inside, bit 3 + a when the line
    // crossed the mesh an odd number of times (each pass writes each point at most once per
    // bit and lines are disjoint, so the parallel passes need no synchronisation).
    std::vector<uint8_t> votes(static_cast<size_t>(nx) * ny * nz, 0);
    if (votes.empty()) return votes;

    for (int a = 0; a < 3; ++a) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        const long nlines = n[u] * n[v];
        uint8_t* vote = votes.data();
#ifdef _OPENMP
#pragma omp parallel
#endif
        {
            std::vector<double> c;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 64)
#endif
            for (long line = 0; line < nlines; ++line) {
                const long ju = line / n[v], jv = line % n[v];
                crossings(a, o[u] + h * static_cast<double>(ju), o[v] + h * static_cast<double>(jv), c);
                if (c.empty()) continue;
                std::sort(c.begin(), c.end());
                const size_t base = static_cast<size_t>(ju) * stride[u] + static_cast<size_t>(jv) * stride[v];
                // Inside where an odd number of crossings lie below: (c0, c1], (c2, c3], ...
                // With an odd count (a hole) the last interval runs to the end: every point
                // of the line is marked, and left to the winding number.
                if (c.size() & 1)
                    for (long t = 0; t < n[a]; ++t) vote[base + static_cast<size_t>(t) * stride[a]] |= uint8_t(8u << a);
                for (size_t k = 0; k < c.size(); k += 2) {
                    const double hi = k + 1 < c.size() ? c[k + 1] : std::numeric_limits<double>::infinity();
                    const long t0 = first_above(o[a], h, n[a], c[k]), t1 = first_above(o[a], h, n[a], hi);
                    for (long t = t0; t < t1; ++t) vote[base + static_cast<size_t>(t) * stride[a]] |= uint8_t(1u << a);
                }
            }
        }
    }
    // Unanimous rays on even lines decide at once; the rest (none for a closed mesh) may ask the
    // winding number, in parallel since there may be many lines through a hole.
    const long total = static_cast<long>(votes.size());
    uint8_t* flag = votes.data();
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 256)
#endif
    for (long i = 0; i < total; ++i) {
        const long ix = i / (static_cast<long>(ny) * nz), iy = (i / nz) % ny, iz = i % nz;
        flag[i] = decide(flag[i], {o[0] + h * static_cast<double>(ix), o[1] + h * static_cast<double>(iy),
                                   o[2] + h * static_cast<double>(iz)});
    }
    return votes;
}

}  // namespace sph

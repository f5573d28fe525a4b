#include "scenes/winding_number.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sph {

namespace {

constexpr int leaf_size = 8;

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee 1983):
// positive when the triangle's normal, by its winding, points away from the origin.
double solid_angle(const double* a, const double* b, const double* c) {
    const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0]);
    const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    const double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
    return 2.0 * std::atan2(det, la * lb * lc + ab * lc + bc * la + ca * lb);
}

double centroid(const std::array<double, 9>& t, int axis) { return (t[axis] + t[3 + axis] + t[6 + axis]) / 3.0; }

}  // namespace

WindingNumber::WindingNumber(std::vector<std::array<double, 9>> triangles) : tri_(std::move(triangles)) {
    nodes_.reserve(2 * tri_.size() / leaf_size + 2);
    if (!tri_.empty()) build(0, static_cast<int>(tri_.size()));
}

int WindingNumber::build(int first, int count) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    Node nd{};
    nd.first = first, nd.count = count, nd.left = nd.right = -1;
    double area_sum = 0, lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int i = first; i < first + count; ++i) {
        const auto& t = tri_[i];
        const double e1[3] = {t[3] - t[0], t[4] - t[1], t[5] - t[2]}, e2[3] = {t[6] - t[0], t[7] - t[1], t[8] - t[2]};
        const double n[3] = {0.5 * (e1[1] * e2[2] - e1[2] * e2[1]), 0.5 * (e1[2] * e2[0] - e1[0] * e2[2]),
                             0.5 * (e1[0] * e2[1] - e1[1] * e2[0])};
        const double area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        area_sum += area;
        for (int k = 0; k < 3; ++k) {
            nd.n[k] += n[k];
            nd.c[k] += area * centroid(t, k);
            lo[k] = std::min(lo[k], centroid(t, k)), hi[k] = std::max(hi[k], centroid(t, k));
        }
    }
    for (int k = 0; k < 3; ++k)
        nd.c[k] = area_sum > 0 ? nd.c[k] / area_sum : 0.5 * (lo[k] + hi[k]);
    for (int i = first; i < first + count; ++i)
        for (int v = 0; v < 3; ++v) {
            const double* q = &tri_[i][3 * v];
            const double d[3] = {q[0] - nd.c[0], q[1] - nd.c[1], q[2] - nd.c[2]};
            nd.r = std::max(nd.r, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
    if (count > leaf_size) {
        int axis = 0;  // split the centroids' longest extent at its median
        for (int k = 1; k < 3; ++k)
            if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
        const int half = count / 2;
        std::nth_element(tri_.begin() + first, tri_.begin() + first + half, tri_.begin() + first + count,
                         [axis](const auto& a, const auto& b) { return centroid(a, axis) < centroid(b, axis); });
        nd.left = build(first, half);
        nd.right = build(first + half, count - half);
    }
    nodes_[id] = nd;
    return id;
}

double WindingNumber::at(Vec3d p, double accuracy) const {
    if (nodes_.empty()) return 0;
    const double P[3] = {p.x, p.y, p.z};
    double omega = 0;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& nd = nodes_[stack[--top]];
        const double d[3] = {nd.c[0] - P[0], nd.c[1] - P[1], nd.c[2] - P[2]};
        const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (accuracy > 0 && dist > accuracy * nd.r) {
            omega += (nd.n[0] * d[0] + nd.n[1] * d[1] + nd.n[2] * d[2]) / (dist * dist * dist);
        } else if (nd.left < 0 || top + 2 > 128) {
            for (int i = nd.first; i < nd.first + nd.count; ++i) {
                const auto& t = tri_[i];
                const double a[3] = {t[0] - P[0], t[1] - P[1], t[2] - P[2]};
                const double b[3] = {t[3] - P[0], t[4] - P[1], t[5] - P[2]};
                const double c[3] = {t[6] - P[0], t[7] - P[1], t[8] - P[2]};
                omega += solid_angle(a, b, c);
            }
        } else {
            stack[top++] = nd.left;
            stack[top++] = nd.right;
        }
    }
    return omega / (4.0 * std::numbers::pi);
}

}  // namespace sph

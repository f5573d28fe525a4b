// Smoothing kernels: normalisation, gradient, antisymmetry, compact support.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/smoothing_kernels.hpp"

namespace sph {
namespace {

template <class K>
class KernelTest : public ::testing::Test {};
using Kernels = ::testing::Types<WendlandC2, CubicSpline>;
TYPED_TEST_SUITE(KernelTest, Kernels);

TYPED_TEST(KernelTest, IntegratesToOneOverItsSupport) {
    for (double h : {0.01, 0.5, 3.0}) {
        const TypeParam k{real(h)};
        // Radial integral of 4 pi r^2 W(r) over [0, 2h] by the midpoint rule (in double).
        const int n = 20000;
        const double dr = 2 * h / n;
        double sum = 0;
        for (int i = 0; i < n; ++i) {
            const double r = (i + 0.5) * dr;
            sum += 4 * M_PI * r * r * double(k.w(real(r))) * dr;
        }
        EXPECT_NEAR(sum, 1.0, 2e-4) << "h = " << h;
    }
}

TYPED_TEST(KernelTest, GradientMatchesFiniteDifference) {
    const double h = 0.1;
    const TypeParam k{real(h)};
    for (double q : {0.05, 0.3, 0.7, 0.99, 1.01, 1.5, 1.9}) {
        const double r = q * h, e = 1e-3 * h;  // float W: a wider step keeps rounding out
        const double dwdr = (double(k.w(real(r + e))) - double(k.w(real(r - e)))) / (2 * e);
        const double grad = double(k.grad_factor(real(r))) * r;
        EXPECT_NEAR(grad, dwdr, 1e-2 * std::abs(dwdr) + 1e-3) << "q = " << q;
        EXPECT_LT(grad, 0.0) << "W must decrease with distance, q = " << q;
    }
}

TYPED_TEST(KernelTest, GradientIsAntisymmetric) {
    const TypeParam k{real(0.2)};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.4f, 0.4f);
    for (int t = 0; t < 100; ++t) {
        const real3 rij = make3(u(rng), u(rng), u(rng));
        const real3 rji = make3(-rij.x, -rij.y, -rij.z);
        const real fi = k.grad_factor(sqrt_r(dot(rij, rij))), fj = k.grad_factor(sqrt_r(dot(rji, rji)));
        EXPECT_EQ(fi * rij.x, -(fj * rji.x));
        EXPECT_EQ(fi * rij.y, -(fj * rji.y));
        EXPECT_EQ(fi * rij.z, -(fj * rji.z));
    }
}

TYPED_TEST(KernelTest, VanishesAtAndBeyondTheSupport) {
    const double h = 0.3;
    const TypeParam k{real(h)};
    for (double q : {2.0, 2.0001, 2.5, 10.0}) {
        EXPECT_EQ(k.w(real(q * h)), 0) << "q = " << q;
        EXPECT_EQ(k.grad_factor(real(q * h)), 0) << "q = " << q;
    }
    EXPECT_GT(k.w(real(1.99 * h)), 0);
}

}  // namespace
}  // namespace sph

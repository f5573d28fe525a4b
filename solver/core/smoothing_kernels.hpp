#pragma once
// Smoothing kernels W(r, h) in 3D, both with support 2h. grad_factor(r) returns
// (dW/dr) / r, so that grad W = r_ij * grad_factor: one multiply per component.
#include "core/types.hpp"

namespace sph {

struct WendlandC2 {
    static constexpr const char* name = "wendland";
    static constexpr bool tensile_correction = false;
    real inv_h, norm;  // norm = 21 / (16 pi h^3)
    SPH_HD explicit WendlandC2(real h) : inv_h(1 / h), norm(real(21.0 / (16.0 * 3.14159265358979323846)) / (h * h * h)) {}
    SPH_HD real w(real r) const {
        const real q = r * inv_h;
        if (q >= 2) return 0;
        const real t = 1 - q / 2;
        const real t2 = t * t;
        return norm * t2 * t2 * (2 * q + 1);
    }
    // dW/dr = norm * (-5 q (1 - q/2)^3) / h
    SPH_HD real grad_factor(real r) const {
        const real q = r * inv_h;
        if (q >= 2) return 0;
        const real t = 1 - q / 2;
        return norm * real(-5) * t * t * t * inv_h * inv_h;  // (-5 q t^3 / h) / r, with q / r = 1 / h
    }
};

struct CubicSpline {
    static constexpr const char* name = "cubic";
    // Monaghan's (2000) correction of the tensile instability, which DualSPHysics applies
    // with this kernel (GetKernelCubic_Tensil): the pressure term gains
    // f^4 (R_i + R_j), f = W(r) / W(h / 1.5), R = P / rho^2 times 0.01 (P > 0) or -0.2.
    static constexpr bool tensile_correction = true;
    real inv_h, norm;  // norm = 1 / (pi h^3)
    SPH_HD explicit CubicSpline(real h) : inv_h(1 / h), norm(real(1.0 / 3.14159265358979323846) / (h * h * h)) {}
    SPH_HD real w(real r) const { return norm * shape(r * inv_h); }
    // (W(r) / W(h / 1.5))^4, W(h / 1.5) = norm 5/9: the tensile correction's weight.
    SPH_HD real tensile_weight(real r) const {
        real f = shape(r * inv_h) * real(1.8);
        f *= f;
        return f * f;
    }
    // W / norm at q = r / h. Both pieces evaluated and one selected, as in grad_factor: the
    // tensile weight takes it in every pair of the force loops, whose lanes sit on both sides of
    // q = 1.
    SPH_HD static real shape(real q) {
        const real t = 2 - q;
        const real inner = 1 - real(1.5) * q * q + real(0.75) * q * q * q;
        const real outer = real(0.25) * t * t * t;
        return q >= 2 ? real(0) : (q < 1 ? inner : outer);
    }
    // Both pieces evaluated and one selected: lanes of a warp sit on both sides of q = 1, and
    // two branches cost the GPU both paths plus their bookkeeping.
    SPH_HD real grad_factor(real r) const {
        const real q = r * inv_h;
        if (q >= 2) return 0;
        const real inner = norm * (real(-3) + real(2.25) * q) * inv_h * inv_h;  // (-3q + 2.25q^2)/h / r
        const real t = 2 - q;
        const real outer = fast_divide(norm * real(-0.75) * t * t * inv_h, r > 0 ? r : real(1));
        return q < 1 ? inner : outer;
    }
};

enum class KernelType { wendland, cubic };

}  // namespace sph

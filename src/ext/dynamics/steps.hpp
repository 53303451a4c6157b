// The seven free-body integrators as scalar steps on (q_world_body, m = I omega) in the principal
// frame, written once; the one-body loops (integrate) and the loops over a chunk of bodies
// (rollout, vectorised by the compiler) call the same function, so a body gets the same bits
// on either path.  Formulas and references: inertia/dynamics/integrators.py.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "common/isa.hpp"

#define INERTIA_INLINE inline __attribute__((always_inline))

namespace inertia::dynamics {
INERTIA_ISA_BEGIN

enum Method : int { EulerExplicit, EulerImplicit, Rk4, Splitting, Dmv, Dmv4, Midpoint, METHOD_COUNT };

// Newton of the implicit methods (dmv, dmv4, midpoint): at most NEWTON_MAX_ITER iterations, stop once
// every correction is below NEWTON_RTOL |c| (quadratic convergence leaves ~1e-20 relative); after
// the last iteration a relative residual above NEWTON_FAIL_RTOL is a failure.
constexpr int NEWTON_MAX_ITER = 40;
constexpr double NEWTON_RTOL = 1e-10;
constexpr double NEWTON_FAIL_RTOL = 1e-10;

struct State {
    double q[4];  // q_world_body (w, x, y, z)
    double m[3];  // body angular momentum I omega
};

struct Inertia {
    double I[3];  // principal moments
    double W[3];  // 1 / I: every omega is m * W (a division per use would bound the speed)
};

// ---------------------------------------------------------------------------- sin and cos
// (sin x, cos x) without a branch or a call, so a loop over bodies vectorises; within an ulp or two.
// x = n pi/2 + r, |r| <= pi/4: n is x 2/pi rounded to nearest by adding 1.5 2^52, whose low
// mantissa bits then hold n mod 4; pi/2 = HI + LO with HI of 33 bits, so n HI is exact for
// |n| < 2^20.  Beyond |x| = 2^50 the rounding of x exceeds pi/4: the angle carries no digit and
// r is set to 0.  Polynomials: fdlibm's __kernel_sin and __kernel_cos (minimax on |r| <= pi/4,
// error below 2^-58), by Estrin's scheme (short dependency chains).
// a if take_a else b, by a bit mask: the same value as the ternary, but a select GCC vectorises
// without AVX-512's masks (a ternary on doubles kept the rollout loops scalar on AVX2)
INERTIA_INLINE double bit_select(bool take_a, double a, double b) {
    uint64_t ab, bb;
    std::memcpy(&ab, &a, 8);
    std::memcpy(&bb, &b, 8);
    const uint64_t m = uint64_t(0) - uint64_t(take_a);
    const uint64_t r = (ab & m) | (bb & ~m);
    double out;
    std::memcpy(&out, &r, 8);
    return out;
}

INERTIA_INLINE void sincos_poly(double x, double &sin_x, double &cos_x) {
    constexpr double TWO_OVER_PI = 0.63661977236758134308, PIO2_HI = 1.57079632673412561417e+00,
                     PIO2_LO = 6.07710050650619224932e-11, SHIFT = 0x1.8p52, NOISE = 0x1p50;
    constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                     S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                     S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
    constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                     C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                     C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
    const double shifted = x * TWO_OVER_PI + SHIFT, fn = shifted - SHIFT;
    double r = (x - fn * PIO2_HI) - fn * PIO2_LO;
    r = bit_select(std::fabs(x) > NOISE, 0.0, r);
    const double z = r * r, z2 = z * z, z4 = z2 * z2;
    const double ps = ((S1 + z * S2) + z2 * (S3 + z * S4)) + z4 * (S5 + z * S6);
    const double pc = ((C1 + z * C2) + z2 * (C3 + z * C4)) + z4 * (C5 + z * C6);
    const double s = r + (r * z) * ps, c = (1.0 - 0.5 * z) + z2 * pc;
    uint64_t n, sb, cb;
    std::memcpy(&n, &shifted, 8);
    const bool odd = n & 1;  // sin and cos swap
    const double sn = bit_select(odd, c, s), cs = bit_select(odd, s, c);
    std::memcpy(&sb, &sn, 8);
    std::memcpy(&cb, &cs, 8);
    sb ^= (n << 62) & (uint64_t(1) << 63);        // n = 2, 3 (mod 4): sin negative
    cb ^= ((n + 1) << 62) & (uint64_t(1) << 63);  // n = 1, 2: cos negative
    std::memcpy(&sin_x, &sb, 8);
    std::memcpy(&cos_x, &cb, 8);
}

// ---------------------------------------------------------------------------- helpers
INERTIA_INLINE void normalize(double q[4]) {
    const double inv = 1.0 / std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; ++k) q[k] *= inv;
}

// The same for a product of unit quaternions, |q|^2 = 1 + e with e a few ulps: one Newton step
// of 1/sqrt about 1, 1.5 - n2/2, whose error 3 e^2 / 8 is far below rounding (and which converges
// quadratically from any |q| near 1); no square root and no division in the vector loops.
INERTIA_INLINE void renormalize(double q[4]) {
    const double inv = 1.5 - 0.5 * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; ++k) q[k] *= inv;
}

// r = q (x) p
INERTIA_INLINE void quat_mul(const double q[4], const double p[4], double r[4]) {
    r[0] = q[0] * p[0] - q[1] * p[1] - q[2] * p[2] - q[3] * p[3];
    r[1] = q[0] * p[1] + q[1] * p[0] + q[2] * p[3] - q[3] * p[2];
    r[2] = q[0] * p[2] - q[1] * p[3] + q[2] * p[0] + q[3] * p[1];
    r[3] = q[0] * p[3] + q[1] * p[2] - q[2] * p[1] + q[3] * p[0];
}

// q <- q (x) exp(h w / 2), normalised: the exact attitude update for a constant body omega.
INERTIA_INLINE void exp_step(double q[4], const double w[3], double h) {
    const double v[3] = {h * w[0], h * w[1], h * w[2]};
    const double theta = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double sh, ch;
    sincos_poly(0.5 * theta, sh, ch);
    // sin(t/2)/t = 1/2 - t^2/48 + t^4/3840 below 1e-4 (both computed: a select, not a branch)
    const double t2 = theta * theta;
    const double series = 0.5 - t2 * (1.0 / 48.0) + t2 * t2 * (1.0 / 3840.0), ratio = sh / theta;
    const double k = bit_select(theta < 1e-4, series, ratio);
    const double p[4] = {ch, k * v[0], k * v[1], k * v[2]}, q0[4] = {q[0], q[1], q[2], q[3]};
    quat_mul(q0, p, q);
    renormalize(q);
}

// A x = b for 3x3 A by the adjugate (positive definite, well conditioned systems).
INERTIA_INLINE void solve3(const double a[3][3], const double b[3], double x[3]) {
    const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1], c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2],
                 c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0], c10 = a[0][2] * a[2][1] - a[0][1] * a[2][2],
                 c11 = a[0][0] * a[2][2] - a[0][2] * a[2][0], c12 = a[0][1] * a[2][0] - a[0][0] * a[2][1],
                 c20 = a[0][1] * a[1][2] - a[0][2] * a[1][1], c21 = a[0][2] * a[1][0] - a[0][0] * a[1][2],
                 c22 = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    const double inv_det = 1.0 / (a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02);
    x[0] = (c00 * b[0] + c10 * b[1] + c20 * b[2]) * inv_det;
    x[1] = (c01 * b[0] + c11 * b[1] + c21 * b[2]) * inv_det;
    x[2] = (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv_det;
}

// max that propagates NaN (a NaN iterate must not pass for converged)
INERTIA_INLINE double max2(double a, double b) { return (a > b || a != a) ? a : b; }
INERTIA_INLINE double max3(double a, double b, double c) { return max2(max2(a, b), c); }

// Newton on c_j = beta(c) chat_j + f_j c_k c_l (j, k, l cyclic), beta = 1 + |c|^2 (DMV) or 1
// (implicit midpoint).  False when it did not converge; `resid` is then the relative residual.
template <bool dmv>
INERTIA_INLINE bool solve_quadratic(const double ch[3], const double f[3], double c[3], double &resid) {
    c[0] = ch[0] + f[0] * ch[1] * ch[2];  // explicit first guess, exact to O(h^3)
    c[1] = ch[1] + f[1] * ch[2] * ch[0];
    c[2] = ch[2] + f[2] * ch[0] * ch[1];
    const double d[3] = {2.0 * ch[0], 2.0 * ch[1], 2.0 * ch[2]};
    auto residual = [&](double r[3]) {
        const double beta = dmv ? 1.0 + c[0] * c[0] + c[1] * c[1] + c[2] * c[2] : 1.0;
        for (int j = 0; j < 3; ++j) r[j] = c[j] - beta * ch[j] - f[j] * c[(j + 1) % 3] * c[(j + 2) % 3];
    };
    for (int it = 0; it < NEWTON_MAX_ITER; ++it) {
        double r[3], e[3], J[3][3];
        residual(r);
        // J_ji = delta_ji - 2 chat_j c_i [DMV only] - d(f_j c_k c_l)/dc_i
        for (int j = 0; j < 3; ++j) {
            const int k = (j + 1) % 3, l = (j + 2) % 3;
            const double dj = dmv ? d[j] : 0.0;
            J[j][j] = 1.0 - dj * c[j];
            J[j][k] = -dj * c[k] - f[j] * c[l];
            J[j][l] = -dj * c[l] - f[j] * c[k];
        }
        solve3(J, r, e);
        for (int j = 0; j < 3; ++j) c[j] -= e[j];
        const double size = max3(std::fabs(c[0]), std::fabs(c[1]), std::fabs(c[2]));
        if (max3(std::fabs(e[0]), std::fabs(e[1]), std::fabs(e[2])) <= NEWTON_RTOL * size + 1e-300) return true;
    }
    double r[3];
    residual(r);
    resid = max3(std::fabs(r[0]), std::fabs(r[1]), std::fabs(r[2])) /
            max2(max3(std::fabs(c[0]), std::fabs(c[1]), std::fabs(c[2])), 1e-300);
    return std::isfinite(resid) && resid <= NEWTON_FAIL_RTOL;
}

// (dq/dt, dm/dt) = (1/2 q (x) (0, w), m x w + tau) with w = W (m - hP): a body carrying wheels of
// momentum hP (gyrostat.hpp; hP = 0 for a free body, the same bits: m - 0 = m); dq without its
// factor 1/2, which the caller folds into its step sizes (a power of two: the same bits).  T is
// double, or std::complex<double> for the complex-step Jacobians.
template <class T>
INERTIA_INLINE void gyro_rate(const T q[4], const T m[3], const T hP[3], const double W[3], const T t[3], T dq[4],
                              T dm[3]) {
    const T a = (m[0] - hP[0]) * W[0], b = (m[1] - hP[1]) * W[1], c = (m[2] - hP[2]) * W[2];
    dq[0] = -q[1] * a - q[2] * b - q[3] * c;
    dq[1] = q[0] * a + q[2] * c - q[3] * b;
    dq[2] = q[0] * b - q[1] * c + q[3] * a;
    dq[3] = q[0] * c + q[1] * b - q[2] * a;
    dm[0] = (m[1] * c - m[2] * b) + t[0];
    dm[1] = (m[2] * a - m[0] * c) + t[1];
    dm[2] = (m[0] * b - m[1] * a) + t[2];
}

INERTIA_INLINE void rk4_rate(const double q[4], const double m[3], const Inertia &b, const double t[3], double dq[4],
                             double dm[3]) {
    constexpr double none[3] = {0.0, 0.0, 0.0};
    gyro_rate(q, m, none, b.W, t, dq, dm);
}

// Exact flow of H_j = m_j^2 / (2 I_j) over dt: the body spins about axis j at m_j / I_j,
// m <- Rot(e_j, -theta) m, q <- q (x) (cos(theta/2), sin(theta/2) e_j).
template <int j>
INERTIA_INLINE void rotor(State &s, const Inertia &b, double dt) {
    constexpr int k = (j + 1) % 3, l = (j + 2) % 3;
    double sh, ch;
    sincos_poly(s.m[j] * ((0.5 * dt) * b.W[j]), sh, ch);  // (0.5 dt) W_j: hoisted by a one-body loop
    const double sh2 = sh + sh, sn = sh2 * ch, cs = 1.0 - sh2 * sh;  // sin, cos of theta (sh + sh = 2 sh)
    const double mk = s.m[k], ml = s.m[l];
    s.m[k] = cs * mk + sn * ml;
    s.m[l] = cs * ml - sn * mk;
    const double qw = s.q[0], qj = s.q[1 + j], qk = s.q[1 + k], ql = s.q[1 + l];
    s.q[0] = qw * ch - qj * sh;
    s.q[1 + j] = qj * ch + qw * sh;
    s.q[1 + k] = qk * ch + ql * sh;
    s.q[1 + l] = ql * ch - qk * sh;
}

// One free DMV step with inverse moments W: solve for the body increment (1, c)/|.|, then
// q+ = q (x) (1, c)/|.|, m+ = F^T m.
INERTIA_INLINE bool dmv_core(State &s, const double W[3], double h, double &resid) {
    const double I[3] = {1.0 / W[0], 1.0 / W[1], 1.0 / W[2]}, hh = 0.5 * h;
    const double ch[3] = {hh * s.m[0] * W[0], hh * s.m[1] * W[1], hh * s.m[2] * W[2]};
    const double f[3] = {(I[1] - I[2]) * W[0], (I[2] - I[0]) * W[1], (I[0] - I[1]) * W[2]};
    double c[3];
    const bool ok = solve_quadratic<true>(ch, f, c, resid);
    const double sc = 1.0 / std::sqrt(1.0 + (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]));
    const double p[4] = {sc, sc * c[0], sc * c[1], sc * c[2]}, q0[4] = {s.q[0], s.q[1], s.q[2], s.q[3]};
    quat_mul(q0, p, s.q);
    renormalize(s.q);
    const double v[3] = {-sc * c[0], -sc * c[1], -sc * c[2]}, m[3] = {s.m[0], s.m[1], s.m[2]};
    const double u[3] = {2.0 * (v[1] * m[2] - v[2] * m[1]), 2.0 * (v[2] * m[0] - v[0] * m[2]),
                         2.0 * (v[0] * m[1] - v[1] * m[0])};
    s.m[0] = m[0] + sc * u[0] + (v[1] * u[2] - v[2] * u[1]);
    s.m[1] = m[1] + sc * u[1] + (v[2] * u[0] - v[0] * u[2]);
    s.m[2] = m[2] + sc * u[2] + (v[0] * u[1] - v[1] * u[0]);
    return ok;
}

INERTIA_INLINE void kick(State &s, const double t[3], double h) {
    for (int k = 0; k < 3; ++k) s.m[k] = s.m[k] + (0.5 * h) * t[k];
}

// ---------------------------------------------------------------------------- the step
// One step of method M with the torque t held in the body frame; false when an implicit
// method's Newton iteration failed (`resid` its relative residual).  A zero torque is added.
template <Method M>
INERTIA_INLINE bool step(State &s, const Inertia &b, const double t[3], double h, double &resid) {
    const double *W = b.W, *I = b.I;
    double *m = s.m;
    if constexpr (M == EulerExplicit) {
        // w+ = w + h I^-1 (tau - w x I w) ; q+ = q (x) exp(h w+ / 2)
        const double w[3] = {m[0] * W[0], m[1] * W[1], m[2] * W[2]};
        const double n[3] = {m[0] + h * ((m[1] * w[2] - m[2] * w[1]) + t[0]),
                             m[1] + h * ((m[2] * w[0] - m[0] * w[2]) + t[1]),
                             m[2] + h * ((m[0] * w[1] - m[1] * w[0]) + t[2])};
        const double wn[3] = {n[0] * W[0], n[1] * W[1], n[2] * W[2]};
        exp_step(s.q, wn, h);
        for (int k = 0; k < 3; ++k) m[k] = n[k];
        return true;
    } else if constexpr (M == EulerImplicit) {
        // one Newton step of backward Euler: (I - h D) dw = h f(w), D = [I w]x - [w]x I
        const double w[3] = {m[0] * W[0], m[1] * W[1], m[2] * W[2]};
        const double g[3] = {(I[1] - I[2]) * h, (I[2] - I[0]) * h, (I[0] - I[1]) * h};
        const double f[3] = {h * ((m[1] * w[2] - m[2] * w[1]) + t[0]), h * ((m[2] * w[0] - m[0] * w[2]) + t[1]),
                             h * ((m[0] * w[1] - m[1] * w[0]) + t[2])};
        const double A[3][3] = {{I[0], -g[0] * w[2], -g[0] * w[1]},
                                {-g[1] * w[2], I[1], -g[1] * w[0]},
                                {-g[2] * w[1], -g[2] * w[0], I[2]}};
        double d[3];
        solve3(A, f, d);
        const double wn[3] = {w[0] + d[0], w[1] + d[1], w[2] + d[2]};
        exp_step(s.q, wn, h);
        for (int k = 0; k < 3; ++k) m[k] = I[k] * wn[k];
        return true;
    } else if constexpr (M == Rk4) {
        // classical RK4 on the 7-vector (q as 4 plain components, m), q renormalised at the end
        const double h2 = 0.5 * h, hq2 = 0.5 * h2, hq = 0.5 * h, h6 = h / 6.0, hq6 = 0.5 * h6;
        double k1q[4], k1m[3], k2q[4], k2m[3], k3q[4], k3m[3], k4q[4], k4m[3], q[4], mm[3];
        rk4_rate(s.q, m, b, t, k1q, k1m);
        for (int k = 0; k < 4; ++k) q[k] = s.q[k] + hq2 * k1q[k];
        for (int k = 0; k < 3; ++k) mm[k] = m[k] + h2 * k1m[k];
        rk4_rate(q, mm, b, t, k2q, k2m);
        for (int k = 0; k < 4; ++k) q[k] = s.q[k] + hq2 * k2q[k];
        for (int k = 0; k < 3; ++k) mm[k] = m[k] + h2 * k2m[k];
        rk4_rate(q, mm, b, t, k3q, k3m);
        for (int k = 0; k < 4; ++k) q[k] = s.q[k] + hq * k3q[k];
        for (int k = 0; k < 3; ++k) mm[k] = m[k] + h * k3m[k];
        rk4_rate(q, mm, b, t, k4q, k4m);
        // k1 + 2 (k2 + k3) + k4, the doubling as an addition (exact, and off the multiplier)
        for (int k = 0; k < 4; ++k) {
            const double mid = k2q[k] + k3q[k];
            s.q[k] = s.q[k] + hq6 * (k1q[k] + (mid + mid) + k4q[k]);
        }
        for (int k = 0; k < 3; ++k) {
            const double mid = k2m[k] + k3m[k];
            m[k] = m[k] + h6 * (k1m[k] + (mid + mid) + k4m[k]);
        }
        normalize(s.q);
        return true;
    } else if constexpr (M == Splitting) {
        // kick, R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2), kick (Strang)
        kick(s, t, h);
        rotor<0>(s, b, 0.5 * h);
        rotor<1>(s, b, 0.5 * h);
        rotor<2>(s, b, h);
        rotor<1>(s, b, 0.5 * h);
        rotor<0>(s, b, 0.5 * h);
        kick(s, t, h);
        renormalize(s.q);
        return true;
    } else if constexpr (M == Dmv || M == Dmv4) {
        kick(s, t, h);
        double Wm[3] = {W[0], W[1], W[2]};
        if constexpr (M == Dmv4) {
            // Hairer & Vilmart (2006) modified inverse moments 1/I~_j = css / I_j + cdd
            const double prod = I[0] * I[1] * I[2], s1 = (I[0] + I[1] + I[2]) / (6.0 * prod),
                         s2 = -(W[0] + W[1] + W[2]) / 3.0, d1 = -1.0 / (3.0 * prod);
            const double half_g2 = 0.5 * (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            const double energy = 0.5 * (m[0] * m[0] * W[0] + m[1] * m[1] * W[1] + m[2] * m[2] * W[2]);
            const double h2 = h * h, css = 1.0 + h2 * (s1 * half_g2 + s2 * energy),
                         cdd = h2 * (d1 * half_g2 + s1 * energy);
            for (int k = 0; k < 3; ++k) Wm[k] = css * W[k] + cdd;
        }
        const bool ok = dmv_core(s, Wm, h, resid);
        kick(s, t, h);
        return ok;
    } else {
        // implicit midpoint: y = m + h/2 (y x W y + tau), m+ = 2 y - m, q+ = q (x) exp(h W y / 2)
        static_assert(M == Midpoint);
        const double hh = 0.5 * h;
        const double bq[3] = {m[0] + hh * t[0], m[1] + hh * t[1], m[2] + hh * t[2]};
        const double f[3] = {hh * (W[2] - W[1]), hh * (W[0] - W[2]), hh * (W[1] - W[0])};
        double y[3];
        const bool ok = solve_quadratic<false>(bq, f, y, resid);
        const double wy[3] = {W[0] * y[0], W[1] * y[1], W[2] * y[2]};
        exp_step(s.q, wy, h);
        for (int k = 0; k < 3; ++k) m[k] = 2.0 * y[k] - m[k];
        return ok;
    }
}

// f(std::integral_constant<Method, M>{}) for the runtime `method` (checked by the caller).
template <class F>
decltype(auto) with_method(int method, F &&f) {
    switch (method) {
        case EulerExplicit: return f(std::integral_constant<Method, EulerExplicit>{});
        case EulerImplicit: return f(std::integral_constant<Method, EulerImplicit>{});
        case Rk4: return f(std::integral_constant<Method, Rk4>{});
        case Splitting: return f(std::integral_constant<Method, Splitting>{});
        case Dmv: return f(std::integral_constant<Method, Dmv>{});
        case Dmv4: return f(std::integral_constant<Method, Dmv4>{});
        default: return f(std::integral_constant<Method, Midpoint>{});
    }
}

INERTIA_ISA_END
}  // namespace inertia::dynamics

// The gyrostat: a rigid body carrying wheels along fixed body axes.  In the principal frame P of
// the body's own inertia I (the wheels' spin inertia about their axes excluded), with the wheels'
// axial angular momenta h_w (absolute, h_w' = u, the motor torques) and hP = A h_w their sum in P
// (A: the wheel axes as columns), the state is (q_world_P, m = I w + hP) and
//     m' = m x w + tau,   w = W (m - hP),   q' = q (x) (0, w) / 2,   h_w' = u
// (Hughes, Spacecraft Attitude Dynamics, ch. 9; Wie, Space Vehicle Dynamics and Control, 7.7).
// One step template over the scalar type T: double for the rollouts, std::complex<double> for the
// complex-step Jacobians, so a Jacobian is the derivative of the very step that runs.
#pragma once
#include <complex>

#include "dynamics/steps.hpp"

namespace inertia::dynamics {

constexpr int MAX_WHEELS = 6;

using cplx = std::complex<double>;

INERTIA_INLINE double re(double x) { return x; }
INERTIA_INLINE double re(const cplx &x) { return x.real(); }
INERTIA_INLINE void sincos_t(double x, double &s, double &c) { sincos_poly(x, s, c); }
INERTIA_INLINE void sincos_t(const cplx &x, cplx &s, cplx &c) { s = std::sin(x), c = std::cos(x); }
INERTIA_INLINE double rsqrt_t(double x) { return 1.0 / std::sqrt(x); }
INERTIA_INLINE cplx rsqrt_t(const cplx &x) { return 1.0 / std::sqrt(x); }

// x clipped to [lo, hi] by the real parts; a clipped value is the bound (and carries its derivative).
template <class T>
INERTIA_INLINE T clip(const T &x, const T &lo, const T &hi) {
    return re(x) < re(lo) ? lo : (re(x) > re(hi) ? hi : x);
}

// Wheel torque u held over `hold` s: first within the momentum limit (h_w + u hold in [-hmax, hmax]),
// then within the torque limit; since 0 lies in the first range (|h_w| <= hmax), the second clip
// keeps the first.  A wheel beyond hmax is brought back as fast as its torque allows.
template <class T>
INERTIA_INLINE T saturate(const T &u, const T &hw, double umax, double hmax, double hold) {
    const T v = clip(u, T((-hmax - hw) / hold), T((hmax - hw) / hold));
    return clip(v, T(-umax), T(umax));
}

// Exact flow over dt of H_j = (m_j - hP_j)^2 / (2 I_j): a spin about axis j at W_j (m_j - hP_j),
// m <- Rot(e_j, -theta) m, q <- q (x) (cos theta/2, sin theta/2 e_j).
template <int j, class T>
INERTIA_INLINE void gyro_rotor(T q[4], T m[3], const T hP[3], const double W[3], double dt) {
    constexpr int k = (j + 1) % 3, l = (j + 2) % 3;
    T sh, ch;
    sincos_t((m[j] - hP[j]) * ((0.5 * dt) * W[j]), sh, ch);
    const T sh2 = sh + sh, sn = sh2 * ch, cs = 1.0 - sh2 * sh;
    const T mk = m[k], ml = m[l];
    m[k] = cs * mk + sn * ml;
    m[l] = cs * ml - sn * mk;
    const T qw = q[0], qj = q[1 + j], qk = q[1 + k], ql = q[1 + l];
    q[0] = qw * ch - qj * sh;
    q[1 + j] = qj * ch + qw * sh;
    q[1 + k] = qk * ch + ql * sh;
    q[1 + l] = ql * ch - qk * sh;
}

// One step of h with the body torque t (P) and the wheels' torque dh = A u (P) held; hP the wheels'
// momentum at the start.  Splitting: kick (t, dh over h/2), R1 R2 R3 R2 R1 with hP frozen, kick;
// keeps |m| and the world L = R m to rounding (tau = 0), second order.  Rk4: classical RK4 on
// (q, m) with hP(s) = hP + s dh, q renormalised.
template <Method M, class T>
INERTIA_INLINE void gyro_step(T q[4], T m[3], const T hP[3], const T dh[3], const T t[3], const double W[3],
                              double h) {
    static_assert(M == Splitting || M == Rk4, "the gyrostat steps are splitting and rk4");
    if constexpr (M == Splitting) {
        const T hm[3] = {hP[0] + (0.5 * h) * dh[0], hP[1] + (0.5 * h) * dh[1], hP[2] + (0.5 * h) * dh[2]};
        for (int k = 0; k < 3; ++k) m[k] = m[k] + (0.5 * h) * t[k];
        gyro_rotor<0>(q, m, hm, W, 0.5 * h);
        gyro_rotor<1>(q, m, hm, W, 0.5 * h);
        gyro_rotor<2>(q, m, hm, W, h);
        gyro_rotor<1>(q, m, hm, W, 0.5 * h);
        gyro_rotor<0>(q, m, hm, W, 0.5 * h);
        for (int k = 0; k < 3; ++k) m[k] = m[k] + (0.5 * h) * t[k];
        const T inv = 1.5 - 0.5 * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (int k = 0; k < 4; ++k) q[k] = q[k] * inv;
    } else {
        const double h2 = 0.5 * h, hq2 = 0.5 * h2, h6 = h / 6.0, hq6 = 0.5 * h6;
        const T hh[3] = {hP[0] + h2 * dh[0], hP[1] + h2 * dh[1], hP[2] + h2 * dh[2]};
        const T h1[3] = {hP[0] + h * dh[0], hP[1] + h * dh[1], hP[2] + h * dh[2]};
        T k1q[4], k1m[3], k2q[4], k2m[3], k3q[4], k3m[3], k4q[4], k4m[3], y[4], z[3];
        gyro_rate(q, m, hP, W, t, k1q, k1m);
        for (int k = 0; k < 4; ++k) y[k] = q[k] + hq2 * k1q[k];
        for (int k = 0; k < 3; ++k) z[k] = m[k] + h2 * k1m[k];
        gyro_rate(y, z, hh, W, t, k2q, k2m);
        for (int k = 0; k < 4; ++k) y[k] = q[k] + hq2 * k2q[k];
        for (int k = 0; k < 3; ++k) z[k] = m[k] + h2 * k2m[k];
        gyro_rate(y, z, hh, W, t, k3q, k3m);
        for (int k = 0; k < 4; ++k) y[k] = q[k] + h2 * k3q[k];
        for (int k = 0; k < 3; ++k) z[k] = m[k] + h * k3m[k];
        gyro_rate(y, z, h1, W, t, k4q, k4m);
        for (int k = 0; k < 4; ++k) {
            const T mid = k2q[k] + k3q[k];
            q[k] = q[k] + hq6 * (k1q[k] + (mid + mid) + k4q[k]);
        }
        for (int k = 0; k < 3; ++k) {
            const T mid = k2m[k] + k3m[k];
            m[k] = m[k] + h6 * (k1m[k] + (mid + mid) + k4m[k]);
        }
        const T inv = rsqrt_t(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (int k = 0; k < 4; ++k) q[k] = q[k] * inv;
    }
}

}  // namespace inertia::dynamics

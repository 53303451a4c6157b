// Gyrostat kernels: closed-loop rollouts over a batch (bodies in chunks held as a structure of
// arrays, each loop over a chunk vectorised by the compiler, disjoint chunks on std::thread; the
// last chunk padded with copies of its last body, so a body's bits do not depend on the batch,
// its place there or the thread count), and complex-step Jacobians of the same step.
//
// Everything is in the principal frame P of each body.  Per body (rows of `plant`, 1 or N):
//   [mass, I1, I2, I3, wheel axes a_1..a_n (3 each, P), max torque (n), max momentum (n),
//    force (3, world), torque (3, P)]
// and of the controller (rows of `control`, 1 or N):
//   [K (n x (3 + n), row-major), omega_ref (3, P), h_ref (n), u_ff (n), monitored axis s (3, P)]
// The wheel torque, computed once per control period (substeps steps of h) and held over it, is
//   u = saturate(u_ff - K [omega - omega_ref; h_w - h_ref]),
// so K = 0 is an open-loop run with the torques u_ff.  The state (13 + n) is
//   [p_world, v_world, q_world_P, omega_P, h_w].
#include <algorithm>
#include <string>
#include <vector>

#include "common/parallel.hpp"
#include "dynamics/gyrostat.hpp"
#include "dynamics/kernels.hpp"

namespace inertia::dynamics {

namespace {

constexpr size_t CHUNK = 16;  // bodies per chunk (the buffer of 6 wheels, 135 x 16 doubles, stays in L1)
constexpr size_t LANES = 8;   // the widest SIMD vector of doubles

constexpr size_t plant_cols(size_t n) { return 10 + 5 * n; }
constexpr size_t control_cols(size_t n) { return n * (3 + n) + 6 + 2 * n; }

// rows of the chunk buffer, each CHUNK long
template <size_t n>
struct Rows {
    static constexpr size_t P = 0, V = 3, Q = 6, MOM = 10, W = 13, HW = 16, AX = HW + n, UMAX = AX + 3 * n,
                            HMAX = UMAX + n, AH = HMAX + n, AHH = AH + 3, TAU = AHH + 3, U = TAU + 3, K = U + n,
                            WREF = K + n * (3 + n), HREF = WREF + 3, UFF = HREF + n, SAX = UFF + n, TILT = SAX + 3,
                            SIN2 = TILT + 1, ROWS = TILT + 2;
};

struct Job {
    const double *x0, *plant, *control, *g;
    size_t N, Np, Nc;
    double h;
    int64_t substeps, n_steps, every;
    double *out, *tilt;
};

INERTIA_INLINE size_t body_of(size_t b0, size_t i, size_t active) { return b0 + std::min(i, active - 1); }

// The wheels' momentum in P, hP = A h_w.
template <size_t n, class T>
INERTIA_INLINE void wheel_sum(const double *b, size_t i, const T *hw, T hP[3]) {
    using R = Rows<n>;
    for (size_t k = 0; k < 3; ++k) {
        T s = 0.0;
        for (size_t w = 0; w < n; ++w) s = s + b[(R::AX + 3 * w + k) * CHUNK + i] * hw[w];
        hP[k] = s;
    }
}

template <size_t n>
void load(double *b, const Job &J, size_t b0, size_t active, size_t lanes) {
    using R = Rows<n>;
    constexpr size_t NX = 13 + n;
    for (size_t i = 0; i < lanes; ++i) {
        const size_t bi = body_of(b0, i, active);
        const double *x = J.x0 + NX * bi, *pl = J.plant + plant_cols(n) * (J.Np > 1 ? bi : 0),
                     *ct = J.control + control_cols(n) * (J.Nc > 1 ? bi : 0);
        auto at = [&](size_t row) -> double & { return b[row * CHUNK + i]; };
        for (size_t k = 0; k < 10; ++k) at(k) = x[k];
        for (size_t w = 0; w < n; ++w) at(R::HW + w) = x[13 + w];
        for (size_t k = 0; k < 3 * n; ++k) at(R::AX + k) = pl[4 + k];
        for (size_t w = 0; w < n; ++w) {
            at(R::UMAX + w) = pl[4 + 3 * n + w];
            at(R::HMAX + w) = pl[4 + 4 * n + w];
        }
        double hP[3];
        wheel_sum<n>(b, i, x + 13, hP);
        for (size_t k = 0; k < 3; ++k) {
            at(R::W + k) = 1.0 / pl[1 + k];
            at(R::MOM + k) = pl[1 + k] * x[10 + k] + hP[k];  // m = I w + A h_w
            const double a = pl[4 + 5 * n + k] / pl[0] + J.g[k];
            at(R::AH + k) = a * J.h;
            at(R::AHH + k) = a * (0.5 * J.h * J.h);
            at(R::TAU + k) = pl[7 + 5 * n + k];
            at(R::WREF + k) = ct[n * (3 + n) + k];
            at(R::SAX + k) = ct[n * (3 + n) + 3 + 2 * n + k];
        }
        for (size_t k = 0; k < n * (3 + n); ++k) at(R::K + k) = ct[k];
        for (size_t w = 0; w < n; ++w) {
            at(R::HREF + w) = ct[n * (3 + n) + 3 + w];
            at(R::UFF + w) = ct[n * (3 + n) + 3 + n + w];
        }
        at(R::TILT) = 2.0;
        at(R::SIN2) = -1.0;
    }
}

// The controller of every lane: u = saturate(u_ff - K z), held for the control period.
template <size_t n>
__attribute__((noinline)) void control_step(double *__restrict b, size_t lanes, double hold) {
    using R = Rows<n>;
    for (size_t i = 0; i < lanes; ++i) {
        auto at = [&](size_t row) -> double & { return b[row * CHUNK + i]; };
        double hw[n > 0 ? n : 1], hP[3], z[3 + n];
        for (size_t w = 0; w < n; ++w) hw[w] = at(R::HW + w);
        wheel_sum<n>(b, i, hw, hP);
        for (size_t k = 0; k < 3; ++k) z[k] = (at(R::MOM + k) - hP[k]) * at(R::W + k) - at(R::WREF + k);
        for (size_t w = 0; w < n; ++w) z[3 + w] = hw[w] - at(R::HREF + w);
        for (size_t w = 0; w < n; ++w) {
            double u = at(R::UFF + w);
            for (size_t k = 0; k < 3 + n; ++k) u = u - at(R::K + w * (3 + n) + k) * z[k];
            at(R::U + w) = saturate(u, hw[w], at(R::UMAX + w), at(R::HMAX + w), hold);
        }
    }
}

// One plant step of h of every lane, the torques held.
template <Method M, size_t n>
__attribute__((noinline)) void plant_step(double *__restrict b, size_t lanes, double h) {
    using R = Rows<n>;
    for (size_t i = 0; i < lanes; ++i) {
        auto at = [&](size_t row) -> double & { return b[row * CHUNK + i]; };
        double q[4], m[3], W[3], t[3], hw[n > 0 ? n : 1], u[n > 0 ? n : 1], hP[3], dh[3];
        for (size_t k = 0; k < 4; ++k) q[k] = at(R::Q + k);
        for (size_t k = 0; k < 3; ++k) m[k] = at(R::MOM + k), W[k] = at(R::W + k), t[k] = at(R::TAU + k);
        for (size_t w = 0; w < n; ++w) hw[w] = at(R::HW + w), u[w] = at(R::U + w);
        wheel_sum<n>(b, i, hw, hP);
        wheel_sum<n>(b, i, u, dh);
        gyro_step<M>(q, m, hP, dh, t, W, h);
        for (size_t k = 0; k < 4; ++k) at(R::Q + k) = q[k];
        for (size_t k = 0; k < 3; ++k) at(R::MOM + k) = m[k];
        for (size_t w = 0; w < n; ++w) at(R::HW + w) = hw[w] + h * u[w];
        for (size_t k = 0; k < 3; ++k) {
            const double v = at(R::V + k);
            at(R::P + k) = at(R::P + k) + v * h + at(R::AHH + k);
            at(R::V + k) = v + at(R::AH + k);
        }
    }
}

// The running least cosine and largest squared sine of the angle between the monitored axis s and
// the total angular momentum m (the sine from |s x m|: exact for small angles, where 1 - cos is not).
template <size_t n>
__attribute__((noinline)) void monitor(double *__restrict b, size_t lanes) {
    using R = Rows<n>;
    for (size_t i = 0; i < lanes; ++i) {
        auto at = [&](size_t row) -> double & { return b[row * CHUNK + i]; };
        const double m0 = at(R::MOM), m1 = at(R::MOM + 1), m2 = at(R::MOM + 2);
        const double s0 = at(R::SAX), s1 = at(R::SAX + 1), s2 = at(R::SAX + 2);
        const double c0 = s1 * m2 - s2 * m1, c1 = s2 * m0 - s0 * m2, c2 = s0 * m1 - s1 * m0;
        const double mm = m0 * m0 + m1 * m1 + m2 * m2;
        const double c = (s0 * m0 + s1 * m1 + s2 * m2) / std::sqrt(mm);
        at(R::TILT) = std::min(at(R::TILT), c);
        at(R::SIN2) = std::max(at(R::SIN2), (c0 * c0 + c1 * c1 + c2 * c2) / mm);
    }
}

// The active lanes' states as row r of out, omega = W (m - A h_w); the largest tilt since the last save.
template <size_t n>
void save(double *b, const Job &J, size_t r, size_t b0, size_t active) {
    using R = Rows<n>;
    constexpr size_t NX = 13 + n;
    for (size_t i = 0; i < active; ++i) {
        auto at = [&](size_t row) -> double & { return b[row * CHUNK + i]; };
        double *o = J.out + NX * (r * J.N + b0 + i), hw[n > 0 ? n : 1], hP[3];
        for (size_t k = 0; k < 10; ++k) o[k] = at(k);
        for (size_t w = 0; w < n; ++w) o[13 + w] = hw[w] = at(R::HW + w);
        wheel_sum<n>(b, i, hw, hP);
        for (size_t k = 0; k < 3; ++k) o[10 + k] = (at(R::MOM + k) - hP[k]) * at(R::W + k);
        // below 60 degrees (cos > 1/2) the sine orders the angles and keeps their digits
        const double c = at(R::TILT);
        J.tilt[r * J.N + b0 + i] = c > 0.5 ? std::asin(std::sqrt(std::min(1.0, at(R::SIN2))))
                                           : std::acos(std::max(-1.0, c));
        at(R::TILT) = 2.0;
        at(R::SIN2) = -1.0;
    }
}

template <Method M, size_t n>
void run_chunks(const Job &job, size_t c_lo, size_t c_hi) {
    const Job J = job;  // this thread's own copy, read at every step (see rollout_kernels.cpp)
    std::vector<double> buffer(Rows<n>::ROWS * CHUNK);
    double *b = buffer.data();
    const double hold = J.h * static_cast<double>(J.substeps);
    for (size_t c = c_lo; c < c_hi; ++c) {
        const size_t b0 = c * CHUNK, active = std::min(CHUNK, J.N - b0);
        const size_t lanes = (active + LANES - 1) / LANES * LANES;
        load<n>(b, J, b0, active, lanes);
        monitor<n>(b, lanes);
        if (J.every > 0) save<n>(b, J, 0, b0, active);
        for (int64_t t = 0; t < J.n_steps; ++t) {
            control_step<n>(b, lanes, hold);
            for (int64_t s = 0; s < J.substeps; ++s) plant_step<M, n>(b, lanes, J.h);
            monitor<n>(b, lanes);
            if (J.every > 0 && (t + 1) % J.every == 0) save<n>(b, J, static_cast<size_t>((t + 1) / J.every), b0, active);
        }
        if (J.every == 0) save<n>(b, J, 0, b0, active);
    }
}

template <class F>
void with_wheels(size_t n, F &&f) {
    switch (n) {
        case 0: return f(std::integral_constant<size_t, 0>{});
        case 1: return f(std::integral_constant<size_t, 1>{});
        case 2: return f(std::integral_constant<size_t, 2>{});
        case 3: return f(std::integral_constant<size_t, 3>{});
        case 4: return f(std::integral_constant<size_t, 4>{});
        case 5: return f(std::integral_constant<size_t, 5>{});
        default: return f(std::integral_constant<size_t, 6>{});
    }
}

template <class F>
void with_gyro_method(int method, F &&f) {
    if (method == Splitting) return f(std::integral_constant<Method, Splitting>{});
    if (method == Rk4) return f(std::integral_constant<Method, Rk4>{});
    input_error("method index " + std::to_string(method) + ": the gyrostat steps are splitting (" +
                std::to_string(Splitting) + ") and rk4 (" + std::to_string(Rk4) + ")");
}

size_t wheels_of(size_t state_cols) {
    if (state_cols < 13 || state_cols > 13 + MAX_WHEELS)
        input_error("a gyrostat state has 13 + n columns (0 <= n <= " + std::to_string(MAX_WHEELS) + " wheels), got " +
                    std::to_string(state_cols));
    return state_cols - 13;
}

void check_plant(const In2<double> &plant, size_t n, size_t N) {
    check_rows(plant.shape(0), N, "plant");
    check_length(plant.shape(1), plant_cols(n), "plant (axis 1)");
    for (size_t r = 0; r < plant.shape(0); ++r) {
        const double *p = plant.data() + plant_cols(n) * r;
        for (size_t k = 0; k < 4; ++k)
            if (!(p[k] > 0.0))
                input_error("plant row " + std::to_string(r) + ": mass and moments must be positive, got " +
                            std::to_string(p[k]) + " in column " + std::to_string(k));
        for (size_t k = 4 + 3 * n; k < 4 + 5 * n; ++k)
            if (!(p[k] > 0.0))
                input_error("plant row " + std::to_string(r) + ": wheel limits must be positive (inf for none), got " +
                            std::to_string(p[k]) + " in column " + std::to_string(k));
    }
}

}  // namespace

void gyro_rollout(int method, In2<double> x0, In2<double> plant, In2<double> control, In1<double> gravity, double h,
                  int64_t substeps, int64_t n_steps, int64_t save_every, int threads, Out3 out, Out2<double> tilt) {
    const size_t N = x0.shape(0), n = wheels_of(x0.shape(1));
    check_plant(plant, n, N);
    check_rows(control.shape(0), N, "control");
    check_length(control.shape(1), control_cols(n), "control (axis 1)");
    check_length(gravity.shape(0), 3, "gravity");
    if (!(h > 0.0) || !std::isfinite(h)) input_error("h must be positive and finite, got " + std::to_string(h));
    if (substeps < 1) input_error("substeps must be >= 1, got " + std::to_string(substeps));
    const size_t S = saved_states(n_steps, save_every, threads);
    check_length(out.shape(0), S, "out");
    check_length(out.shape(1), N, "out (axis 1)");
    check_length(out.shape(2), 13 + n, "out (axis 2)");
    check_length(tilt.shape(0), S, "tilt");
    check_length(tilt.shape(1), N, "tilt (axis 1)");
    if (N == 0) return;
    const Job J{x0.data(), plant.data(), control.data(), gravity.data(), N, plant.shape(0), control.shape(0),
                h, substeps, n_steps, save_every, out.data(), tilt.data()};
    with_gyro_method(method, [&](auto M) {
        with_wheels(n, [&](auto W) {
            auto run = run_chunks<decltype(M)::value, decltype(W)::value>;
            parallel_for((N + CHUNK - 1) / CHUNK, threads, 1, [&](size_t c0, size_t c1) { run(J, c0, c1); });
        });
    });
}

// d x_next / d dx and d x_next / d u in the error state [dp, dv, dtheta (right, P), domega, dh_w] by
// the complex step: each direction is one step of the same template on complex numbers,
// f(x + i e d) = f(x) + i e J d + O(e^2), exact to rounding for e = 1e-20 (no difference is taken).
void gyro_jacobians(int method, In2<double> x, In2<double> u, In2<double> plant, In1<double> gravity, double h,
                    int64_t substeps, Out3 A, Out3 B) {
    const size_t N = x.shape(0), n = wheels_of(x.shape(1)), nx = 12 + n, nu = 6 + n;
    check_plant(plant, n, N);
    check_rows(u.shape(0), N, "u");
    check_length(u.shape(1), nu, "u (axis 1)");
    check_length(gravity.shape(0), 3, "gravity");
    if (!(h > 0.0) || !std::isfinite(h)) input_error("h must be positive and finite, got " + std::to_string(h));
    if (substeps < 1) input_error("substeps must be >= 1, got " + std::to_string(substeps));
    check_length(A.shape(0), N, "A");
    check_length(A.shape(1), nx, "A (axis 1)");
    check_length(A.shape(2), nx, "A (axis 2)");
    check_length(B.shape(0), N, "B");
    check_length(B.shape(1), nx, "B (axis 1)");
    check_length(B.shape(2), nu, "B (axis 2)");
    constexpr double e = 1e-20;
    const double hold = h * static_cast<double>(substeps);
    with_gyro_method(method, [&](auto M) {
        for (size_t b = 0; b < N; ++b) {
            const double *xb = x.data() + (13 + n) * b, *ub = u.data() + nu * (u.shape(0) > 1 ? b : 0),
                         *pl = plant.data() + plant_cols(n) * (plant.shape(0) > 1 ? b : 0);
            const double W[3] = {1.0 / pl[1], 1.0 / pl[2], 1.0 / pl[3]};
            for (size_t d = 0; d < nx + nu; ++d) {
                // the state and input with i e along direction d
                cplx p[3], v[3], q[4], w[3], hw[MAX_WHEELS], uu[MAX_WHEELS + 6];
                for (size_t k = 0; k < 3; ++k) p[k] = xb[k], v[k] = xb[3 + k], w[k] = xb[10 + k];
                for (size_t k = 0; k < n; ++k) hw[k] = xb[13 + k];
                for (size_t k = 0; k < nu; ++k) uu[k] = ub[k];
                const cplx ie(0.0, e);
                if (d < 3) p[d] += ie;
                else if (d < 6) v[d - 3] += ie;
                else if (d < 12 && d >= 9) w[d - 9] += ie;
                else if (d >= 12 && d < nx) hw[d - 12] += ie;
                else if (d >= nx) uu[d - nx] += ie;
                const double *q0 = xb + 6;
                if (d >= 6 && d < 9) {  // q (x) (1, i e e_k / 2)
                    cplx r[4] = {1.0, 0.0, 0.0, 0.0};
                    r[1 + d - 6] = 0.5 * ie;
                    q[0] = q0[0] * r[0] - q0[1] * r[1] - q0[2] * r[2] - q0[3] * r[3];
                    q[1] = q0[0] * r[1] + q0[1] * r[0] + q0[2] * r[3] - q0[3] * r[2];
                    q[2] = q0[0] * r[2] - q0[1] * r[3] + q0[2] * r[0] + q0[3] * r[1];
                    q[3] = q0[0] * r[3] + q0[1] * r[2] - q0[2] * r[1] + q0[3] * r[0];
                } else {
                    for (size_t k = 0; k < 4; ++k) q[k] = q0[k];
                }
                // m = I w + A h_w; the torques saturated once for the control period
                cplx m[3], us[MAX_WHEELS];
                for (size_t k = 0; k < 3; ++k) {
                    cplx s = 0.0;
                    for (size_t j = 0; j < n; ++j) s = s + pl[4 + 3 * j + k] * hw[j];
                    m[k] = pl[1 + k] * w[k] + s;
                }
                for (size_t j = 0; j < n; ++j) us[j] = saturate(uu[6 + j], hw[j], pl[4 + 3 * n + j], pl[4 + 4 * n + j], hold);
                cplx a[3], t[3] = {uu[3], uu[4], uu[5]}, dh[3];
                for (size_t k = 0; k < 3; ++k) {
                    a[k] = uu[k] / pl[0] + gravity(k);
                    cplx s = 0.0;
                    for (size_t j = 0; j < n; ++j) s = s + pl[4 + 3 * j + k] * us[j];
                    dh[k] = s;
                }
                for (int64_t s = 0; s < substeps; ++s) {
                    cplx hP[3];
                    for (size_t k = 0; k < 3; ++k) {
                        cplx acc = 0.0;
                        for (size_t j = 0; j < n; ++j) acc = acc + pl[4 + 3 * j + k] * hw[j];
                        hP[k] = acc;
                    }
                    gyro_step<decltype(M)::value>(q, m, hP, dh, t, W, h);
                    for (size_t j = 0; j < n; ++j) hw[j] = hw[j] + h * us[j];
                    for (size_t k = 0; k < 3; ++k) {
                        p[k] = p[k] + v[k] * h + a[k] * (0.5 * h * h);
                        v[k] = v[k] + a[k] * h;
                    }
                }
                // the derivative of the error state of the result: Im / e; dtheta = 2 vec(conj(Re q) (x) q)
                double col[12 + MAX_WHEELS];
                const double qr[4] = {q[0].real(), -q[1].real(), -q[2].real(), -q[3].real()};
                const double qi[4] = {q[0].imag(), q[1].imag(), q[2].imag(), q[3].imag()};
                for (size_t k = 0; k < 3; ++k) {
                    col[k] = p[k].imag() / e;
                    col[3 + k] = v[k].imag() / e;
                    cplx s = 0.0;
                    for (size_t j = 0; j < n; ++j) s = s + pl[4 + 3 * j + k] * hw[j];
                    col[9 + k] = ((m[k] - s) * W[k]).imag() / e;
                }
                col[6] = 2.0 * (qr[0] * qi[1] + qr[1] * qi[0] + qr[2] * qi[3] - qr[3] * qi[2]) / e;
                col[7] = 2.0 * (qr[0] * qi[2] - qr[1] * qi[3] + qr[2] * qi[0] + qr[3] * qi[1]) / e;
                col[8] = 2.0 * (qr[0] * qi[3] + qr[1] * qi[2] - qr[2] * qi[1] + qr[3] * qi[0]) / e;
                for (size_t j = 0; j < n; ++j) col[12 + j] = hw[j].imag() / e;
                for (size_t r = 0; r < nx; ++r) {
                    if (d < nx) A.data()[(b * nx + r) * nx + d] = col[r];
                    else B.data()[(b * nx + r) * nu + (d - nx)] = col[r];
                }
            }
        }
    });
}

}  // namespace inertia::dynamics

// Rollouts of the 6-DOF transition function over a batch: bodies in chunks of CHUNK held as a
// structure of arrays, each time step a loop over the chunk that the compiler vectorises (the
// explicit methods; the implicit ones iterate Newton per body in the same layout).  Every body
// runs the same code: the last chunk is padded to a multiple of LANES with copies of its last
// body, so a body's bits do not depend on the batch size, its position or the thread count.
// Disjoint whole chunks run on threads (parallel_for).
//
// Compiled once per instruction set (CMakeLists.txt, common/isa.hpp): this file holds the loops
// only, with no nanobind and no std container; rollout.cpp checks the inputs and runs the chunks
// on threads through the table the CPU chose (dispatch.cpp).
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "common/isa.hpp"
#include "dynamics/rollout.hpp"
#include "dynamics/steps.hpp"

namespace inertia::dynamics {
INERTIA_ISA_BEGIN

namespace {

constexpr size_t CHUNK = ROLLOUT_CHUNK;
constexpr size_t LANES = 8;   // the widest SIMD vector of doubles (AVX-512)

// rows of the chunk buffer, each CHUNK long; F_ holds a h and AHH a h^2/2 (a = F / mass + g) under a
// world force, F in P under a body force
enum Row : size_t { P = 0, V = 3, Q = 6, MOM = 10, I_ = 13, W_ = 16, F_ = 19, AHH = 22, TAU = 25, MASS = 28, ROWS = 29 };

using Job = RolloutJob;

// R(q) v = v + w t + u x t, t = 2 u x v
INERTIA_INLINE void rotate(const double q[4], const double v[3], double r[3]) {
    const double t[3] = {2.0 * (q[2] * v[2] - q[3] * v[1]), 2.0 * (q[3] * v[0] - q[1] * v[2]),
                         2.0 * (q[1] * v[1] - q[2] * v[0])};
    r[0] = v[0] + q[0] * t[0] + (q[2] * t[2] - q[3] * t[1]);
    r[1] = v[1] + q[0] * t[1] + (q[3] * t[0] - q[1] * t[2]);
    r[2] = v[2] + q[0] * t[2] + (q[1] * t[1] - q[2] * t[0]);
}

// One time step of `lanes` bodies of the buffer, in place; the first failed lane or SIZE_MAX.
// Translation, world force: exact for the held force (p += v h + a h^2/2, v += a h).  Body force (F rows in the principal frame, turning with the body):
// Simpson on a(0), a(h/2), a(h), the attitude at h/2 from a half step.
template <Method M, bool BodyForce>
__attribute__((noinline)) size_t chunk_step(double *__restrict b, size_t lanes, double h, const double *g) {
    size_t bad = SIZE_MAX;
    const double hs = h * h / 6.0, h6 = h / 6.0;
    for (size_t i = 0; i < lanes; ++i) {
        auto at = [&](size_t row) -> double & { return b[row * CHUNK + i]; };
        State s;
        Inertia in;
        double t[3];
        for (size_t k = 0; k < 4; ++k) s.q[k] = at(Q + k);
        for (size_t k = 0; k < 3; ++k) {
            s.m[k] = at(MOM + k);
            in.I[k] = at(I_ + k);
            in.W[k] = at(W_ + k);
            t[k] = at(TAU + k);
        }
        const State s0 = s;
        double resid;
        bool ok = step<M>(s, in, t, h, resid);
        if constexpr (!BodyForce) {
            for (size_t k = 0; k < 3; ++k) {
                const double v = at(V + k);
                at(P + k) = at(P + k) + v * h + at(AHH + k);
                at(V + k) = v + at(F_ + k);
            }
        } else {
            State sh = s0;
            ok = step<M>(sh, in, t, 0.5 * h, resid) && ok;
            const double F[3] = {at(F_), at(F_ + 1), at(F_ + 2)}, mass = at(MASS);
            double f0[3], fh[3], f1[3];
            rotate(s0.q, F, f0);
            rotate(sh.q, F, fh);
            rotate(s.q, F, f1);
            for (size_t k = 0; k < 3; ++k) {
                const double a0 = f0[k] / mass + g[k], ah = fh[k] / mass + g[k], a1 = f1[k] / mass + g[k];
                const double v = at(V + k);
                at(P + k) = at(P + k) + v * h + (a0 + 2.0 * ah) * hs;
                at(V + k) = v + (a0 + 4.0 * ah + a1) * h6;
            }
        }
        for (size_t k = 0; k < 4; ++k) at(Q + k) = s.q[k];
        for (size_t k = 0; k < 3; ++k) at(MOM + k) = s.m[k];
        if (!ok && i < bad) bad = i;
    }
    return bad;
}

// Body b0 + i of the chunk, or for a padding lane the chunk's last body.
INERTIA_INLINE size_t body_of(size_t b0, size_t i, size_t active) { return b0 + std::min(i, active - 1); }

// States into the buffer, moved to the principal frame P: q_WP = q_WB (x) q_BP, w_P = R_BP^T w_B
// (frame row [q_BP, R_BP row-major] per body, none when P = B); m = I w_P.
void load_states(double *b, const Job &J, size_t b0, size_t active, size_t lanes) {
    for (size_t i = 0; i < lanes; ++i) {
        const size_t bi = body_of(b0, i, active), bb = J.Nb > 1 ? bi : 0;
        const double *x = J.x0 + 13 * bi;
        for (size_t k = 0; k < 6; ++k) b[k * CHUNK + i] = x[k];
        double q[4] = {x[6], x[7], x[8], x[9]}, w[3] = {x[10], x[11], x[12]};
        if (J.Nf) {
            const double *fr = J.frame + 13 * (J.Nf > 1 ? bi : 0);
            quat_mul(x + 6, fr, q);
            for (size_t k = 0; k < 3; ++k) w[k] = fr[4 + k] * x[10] + fr[7 + k] * x[11] + fr[10 + k] * x[12];
        }
        for (size_t k = 0; k < 4; ++k) b[(Q + k) * CHUNK + i] = q[k];
        for (size_t k = 0; k < 3; ++k) {
            const double I = J.moments[3 * bb + k];
            b[(I_ + k) * CHUNK + i] = I;
            b[(W_ + k) * CHUNK + i] = 1.0 / I;
            b[(MOM + k) * CHUNK + i] = I * w[k];
        }
        b[MASS * CHUNK + i] = J.mass[bb];
    }
}

// Inputs of step t: the world acceleration a = F / mass + g as a h and a h^2/2 (or the body-frame
// force), the torque.
template <bool BodyForce>
void load_inputs(double *b, const Job &J, size_t b0, size_t active, size_t lanes, int64_t t) {
    const double *ut = J.u + 6 * J.Nu * (J.T > 1 ? static_cast<size_t>(t) : 0);
    for (size_t i = 0; i < lanes; ++i) {
        const size_t bi = body_of(b0, i, active);
        const double *u = ut + 6 * (J.Nu > 1 ? bi : 0);
        const double mass = b[MASS * CHUNK + i];
        for (size_t k = 0; k < 3; ++k) {
            const double a = u[k] / mass + J.g[k];
            b[(F_ + k) * CHUNK + i] = BodyForce ? u[k] : a * J.h;
            b[(AHH + k) * CHUNK + i] = a * (0.5 * J.h * J.h);
            b[(TAU + k) * CHUNK + i] = u[3 + k];
        }
    }
}

// The active bodies' states as row r of out (S, N, 13), back in the body frame:
// q_WB = q_WP (x) q_BP^-1, w_B = R_BP w_P, w_P = m / I.
void save_states(const double *b, const Job &J, size_t r, size_t b0, size_t active) {
    for (size_t i = 0; i < active; ++i) {
        const size_t bi = b0 + i;
        double *o = J.out + 13 * (r * J.N + bi);
        for (size_t k = 0; k < 6; ++k) o[k] = b[k * CHUNK + i];
        const double q[4] = {b[Q * CHUNK + i], b[(Q + 1) * CHUNK + i], b[(Q + 2) * CHUNK + i], b[(Q + 3) * CHUNK + i]};
        double w[3];
        for (size_t k = 0; k < 3; ++k) w[k] = b[(MOM + k) * CHUNK + i] / b[(I_ + k) * CHUNK + i];
        if (!J.Nf) {
            for (size_t k = 0; k < 4; ++k) o[6 + k] = q[k];
            for (size_t k = 0; k < 3; ++k) o[10 + k] = w[k];
            continue;
        }
        const double *fr = J.frame + 13 * (J.Nf > 1 ? bi : 0);
        const double conj[4] = {fr[0], -fr[1], -fr[2], -fr[3]};
        quat_mul(q, conj, o + 6);
        for (size_t k = 0; k < 3; ++k) o[10 + k] = fr[4 + 3 * k] * w[0] + fr[5 + 3 * k] * w[1] + fr[6 + 3 * k] * w[2];
    }
}

// Chunks c_lo .. c_hi - 1: load, n_steps steps, save.
template <Method M, bool BodyForce>
void run_chunks(const Job &job, size_t c_lo, size_t c_hi) {
    // this thread's own copy of the job, read at every step: the caller's lies on the stack of
    // the thread that started the others, in cache lines that thread writes
    const Job J = job;
    alignas(64) double b[ROWS * CHUNK] = {};  // on the stack: no std container in this file
    for (size_t c = c_lo; c < c_hi; ++c) {
        const size_t b0 = c * CHUNK, active = std::min(CHUNK, J.N - b0);
        const size_t lanes = (active + LANES - 1) / LANES * LANES;
        load_states(b, J, b0, active, lanes);
        if (J.every > 0) save_states(b, J, 0, b0, active);
        for (int64_t t = 0; t < J.n_steps; ++t) {
            if (t == 0 || J.T > 1) load_inputs<BodyForce>(b, J, b0, active, lanes, t);
            const size_t bad = chunk_step<M, BodyForce>(b, lanes, J.h, J.g);
            if (bad != SIZE_MAX) {
                J.status[b0 + bad] = t;
                break;
            }
            if (J.every > 0 && (t + 1) % J.every == 0)
                save_states(b, J, static_cast<size_t>((t + 1) / J.every), b0, active);
        }
        if (J.every == 0) save_states(b, J, 0, b0, active);
    }
}

}  // namespace

INERTIA_ISA_END

// This variant's table: inertia::dynamics::rollout_kernels_<tag>, listed by dispatch.cpp.
static_assert(ROLLOUT_METHODS == METHOD_COUNT);
#define INERTIA_ROW(M) {&run_chunks<M, false>, &run_chunks<M, true>}
extern const RolloutKernels INERTIA_CAT(rollout_kernels_, INERTIA_ISA) = {
    {INERTIA_ROW(EulerExplicit), INERTIA_ROW(EulerImplicit), INERTIA_ROW(Rk4), INERTIA_ROW(Splitting),
     INERTIA_ROW(Dmv), INERTIA_ROW(Dmv4), INERTIA_ROW(Midpoint)}};
#undef INERTIA_ROW

}  // namespace inertia::dynamics

// The kernels of inertia._ext.dynamics, bound in bind.cpp.
#pragma once
#include <cstdint>
#include <string>
#include <tuple>

#include "common/arrays.hpp"

namespace inertia::dynamics {

template <int K>
using InNK = nb::ndarray<const double, nb::shape<-1, K>, nb::c_contig, nb::device::cpu>;
template <int K>
using OutNK = nb::ndarray<double, nb::shape<-1, K>, nb::c_contig, nb::device::cpu>;
template <int K>
using OutRNK = nb::ndarray<double, nb::shape<-1, -1, K>, nb::c_contig, nb::device::cpu>;
using InU = nb::ndarray<const double, nb::shape<-1, -1, 6>, nb::c_contig, nb::device::cpu>;

// (body, steps done before the failure, kind 1 Newton / 2 not finite, Newton's relative residual);
// body -1 when every body ran every step.
using Failure = std::tuple<int64_t, int64_t, int, double>;

// InputError unless 0 <= method < METHOD_COUNT.
void check_method(int method);

// A batch input of `got` rows for N bodies: 1 (shared) or N (0 too when zero_ok).
inline void check_rows(size_t got, size_t N, const char *what, bool zero_ok = false) {
    if (!(got == 1 || got == N || (zero_ok && got == 0)))
        input_error(std::string(what) + " has " + std::to_string(got) + " rows, expected 1 or " + std::to_string(N));
}

// The states a rollout saves (n_steps / save_every + 1, or 1 when save_every is 0), its step
// counts and thread count checked.
inline size_t saved_states(int64_t n_steps, int64_t save_every, int threads) {
    if (n_steps < 0 || save_every < 0) input_error("n_steps and save_every must be >= 0");
    if (save_every > 0 && n_steps % save_every) input_error("n_steps must be a multiple of save_every");
    if (threads < 1) input_error("threads must be >= 1, got " + std::to_string(threads));
    return save_every > 0 ? static_cast<size_t>(n_steps / save_every) + 1 : 1;
}

Failure advance(int method, OutNK<4> q, OutNK<3> m, InNK<3> moments, InNK<3> torque, In1<int64_t> counts,
                In1<double> hs, In1<int64_t> slots, OutRNK<4> qs, OutRNK<3> ws, bool stop_if_not_finite);

void rollout(int method, InNK<13> x0, InU u, InNK<3> moments, In1<double> mass, InNK<13> frame, In1<double> gravity,
             double h, int64_t n_steps, int64_t save_every, bool body_force, int threads, OutRNK<13> out,
             Out1<int64_t> status);

using Out3 = nb::ndarray<double, nb::ndim<3>, nb::c_contig, nb::device::cpu>;

// Gyrostat (gyrostat.cpp): closed-loop rollouts of N bodies with wheels, and complex-step Jacobians.
void gyro_rollout(int method, In2<double> x0, In2<double> plant, In2<double> control, In1<double> gravity, double h,
                  int64_t substeps, int64_t n_steps, int64_t save_every, int threads, Out3 out, Out2<double> tilt);

void gyro_jacobians(int method, In2<double> x, In2<double> u, In2<double> plant, In1<double> gravity, double h,
                    int64_t substeps, Out3 A, Out3 B);

}  // namespace inertia::dynamics

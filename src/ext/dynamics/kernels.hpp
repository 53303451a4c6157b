// The kernels of inertia._ext.dynamics, bound in bind.cpp.
#pragma once
#include <cstdint>
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

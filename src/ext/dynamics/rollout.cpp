// Rollouts of the 6-DOF transition function over a batch (the loops: rollout_kernels.cpp): the
// inputs checked, then disjoint whole chunks of bodies on threads (parallel_for), each run by the
// loops of the instruction set the CPU chose (dispatch.cpp; every variant gives the same bits).
#include <string>

#include "common/parallel.hpp"
#include "dynamics/kernels.hpp"
#include "dynamics/rollout.hpp"

namespace inertia::dynamics {

void rollout(int method, InNK<13> x0, InU u, InNK<3> moments, In1<double> mass, InNK<13> frame, In1<double> gravity,
             double h, int64_t n_steps, int64_t save_every, bool body_force, int threads, OutRNK<13> out,
             Out1<int64_t> status) {
    check_method(method);
    const size_t N = x0.shape(0), T = u.shape(0), Nu = u.shape(1), Nb = moments.shape(0), Nf = frame.shape(0);
    const size_t S = saved_states(n_steps, save_every, threads);
    if (!(T == 1 || T == static_cast<size_t>(n_steps))) input_error("u must hold 1 or n_steps inputs");
    check_rows(Nu, N, "u (axis 1)");
    check_rows(Nb, N, "moments");
    check_rows(Nf, N, "frame", true);
    check_length(mass.shape(0), Nb, "mass");
    check_length(gravity.shape(0), 3, "gravity");
    check_length(out.shape(0), S, "out");
    check_length(out.shape(1), N, "out (axis 1)");
    check_length(status.shape(0), N, "status");
    if (N == 0) return;
    for (size_t i = 0; i < N; ++i) status(i) = -1;
    const RolloutJob J{x0.data(), u.data(), moments.data(), mass.data(), frame.data(), gravity.data(), N, T, Nu, Nb,
                       Nf, h, n_steps, save_every, out.data(), status.data()};
    const RolloutChunks run = rollout_kernels().run[method][body_force ? 1 : 0];
    parallel_for((N + ROLLOUT_CHUNK - 1) / ROLLOUT_CHUNK, threads, 1, [&](size_t c0, size_t c1) { run(J, c0, c1); });
}

}  // namespace inertia::dynamics

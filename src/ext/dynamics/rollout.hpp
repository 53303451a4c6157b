// The batched rollout's job and the entry points of its loops (rollout_kernels.cpp, compiled once
// per instruction set: common/isa.hpp), which rollout.cpp calls through the table the CPU chose.
#pragma once
#include <cstddef>
#include <cstdint>

namespace inertia::dynamics {

constexpr size_t ROLLOUT_CHUNK = 64;  // bodies per chunk: the buffer (29 x 64 doubles, 15 kB) stays in L1
constexpr int ROLLOUT_METHODS = 7;    // METHOD_COUNT of steps.hpp

// One rollout, its inputs checked (rollout.cpp): N bodies, T inputs of Nu rows, Nb moments and
// masses, Nf frames (0: none), n_steps of h, a saved state every `every` steps (0: the last only).
struct RolloutJob {
    const double *x0, *u, *moments, *mass, *frame, *g;
    size_t N, T, Nu, Nb, Nf;
    double h;
    int64_t n_steps, every;
    double *out;
    int64_t *status;
};

// Chunks c_lo .. c_hi - 1 of the job (bodies c ROLLOUT_CHUNK ...): load, n_steps steps, save.
using RolloutChunks = void (*)(const RolloutJob &job, size_t c_lo, size_t c_hi);

// One variant's loops: run[method][body_force].
struct RolloutKernels {
    RolloutChunks run[ROLLOUT_METHODS][2];
};

// The table of the variant in use (dispatch.cpp).
const RolloutKernels &rollout_kernels();

}  // namespace inertia::dynamics

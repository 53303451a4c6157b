// The one-body loop of integrate / integrate_segments and of the public one-step functions:
// bodies one at a time, the state in registers, over segments of fixed steps.
#include <cmath>
#include <string>

#include "dynamics/kernels.hpp"
#include "dynamics/steps.hpp"

namespace inertia::dynamics {

namespace {

// q (B, 4), m (B, 3) hold the state and are updated in place (on failure: the state before the
// failing step); segment k takes counts[k] steps of hs[k] and writes the state at its end to
// row slots[k] of qs (R, B, 4) and ws (R, B, 3) (omega = m / I), or nowhere when -1.
template <Method M>
Failure advance_bodies(double *q, double *m, const double *moments, const double *torque, size_t B,
                       const int64_t *counts, const double *hs, const int64_t *slots, size_t S, double *qs,
                       double *ws, bool stop_if_not_finite) {
    for (size_t b = 0; b < B; ++b) {
        State s{{q[4 * b], q[4 * b + 1], q[4 * b + 2], q[4 * b + 3]}, {m[3 * b], m[3 * b + 1], m[3 * b + 2]}};
        Inertia in;
        double t[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < 3; ++k) {
            in.I[k] = moments[3 * b + k];
            in.W[k] = 1.0 / in.I[k];
            if (torque) t[k] = torque[3 * b + k];
        }
        int64_t done = 0;
        auto keep = [&](const State &x) {
            for (int k = 0; k < 4; ++k) q[4 * b + k] = x.q[k];
            for (int k = 0; k < 3; ++k) m[3 * b + k] = x.m[k];
        };
        for (size_t seg = 0; seg < S; ++seg) {
            const double h = hs[seg];
            for (int64_t j = 0; j < counts[seg]; ++j) {
                State n = s;
                double resid = 0.0;
                const bool ok = step<M>(n, in, t, h, resid);
                if (!ok || (stop_if_not_finite &&
                            !(std::isfinite(n.m[0]) && std::isfinite(n.m[1]) && std::isfinite(n.m[2])))) {
                    keep(s);
                    return {static_cast<int64_t>(b), done, ok ? 2 : 1, resid};
                }
                s = n;
                ++done;
            }
            if (slots[seg] >= 0) {
                const size_t r = static_cast<size_t>(slots[seg]) * B + b;
                for (int k = 0; k < 4; ++k) qs[4 * r + k] = s.q[k];
                for (int k = 0; k < 3; ++k) ws[3 * r + k] = s.m[k] / in.I[k];
            }
        }
        keep(s);
    }
    return {-1, 0, 0, 0.0};
}

}  // namespace

void check_method(int method) {
    if (method < 0 || method >= METHOD_COUNT)
        input_error("method index " + std::to_string(method) + " names no integrator (0.." +
                    std::to_string(METHOD_COUNT - 1) + ")");
}

Failure advance(int method, OutNK<4> q, OutNK<3> m, InNK<3> moments, InNK<3> torque, In1<int64_t> counts,
                In1<double> hs, In1<int64_t> slots, OutRNK<4> qs, OutRNK<3> ws, bool stop_if_not_finite) {
    check_method(method);
    const size_t B = q.shape(0), S = counts.shape(0), R = qs.shape(0);
    check_length(m.shape(0), B, "m");
    check_length(moments.shape(0), B, "moments");
    if (torque.shape(0) != 0) check_length(torque.shape(0), B, "torque");
    check_length(hs.shape(0), S, "hs");
    check_length(slots.shape(0), S, "slots");
    check_length(qs.shape(1), B, "qs (axis 1)");
    check_length(ws.shape(0), R, "ws");
    check_length(ws.shape(1), B, "ws (axis 1)");
    for (size_t k = 0; k < S; ++k) {
        if (counts(k) < 0) input_error("counts[" + std::to_string(k) + "] = " + std::to_string(counts(k)) + " < 0");
        if (slots(k) < -1 || slots(k) >= static_cast<int64_t>(R))
            input_error("slots[" + std::to_string(k) + "] = " + std::to_string(slots(k)) + " names no row of qs (" +
                        std::to_string(R) + ")");
    }
    return with_method(method, [&](auto M) {
        return advance_bodies<decltype(M)::value>(q.data(), m.data(), moments.data(),
                                                  torque.shape(0) ? torque.data() : nullptr, B, counts.data(),
                                                  hs.data(), slots.data(), S, qs.data(), ws.data(),
                                                  stop_if_not_finite);
    });
}

}  // namespace inertia::dynamics

// Principal moments and axes of symmetric 3x3 matrices in the canonical form of
// inertia.massprops.principal (moments ascending; axes the columns of a proper rotation; axes 1
// and 2 with their largest-magnitude component positive, the first on exact ties; axis 3 = e1 x e2;
// repeated moments within rtol times the largest: a documented choice of axes).  The eigenpairs
// come from cyclic Jacobi rotations: a diagonal matrix is left exactly as it is, and the result
// is accurate to a few ulps of the largest moment for any input.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "common/vec3.hpp"

namespace inertia::principal {

constexpr int MAX_SWEEPS = 64;  // Jacobi converges in about 5 for 3x3; the bound stops NaN input

// Eigenvalues w (ascending; ties in their diagonal order) and eigenvectors (the columns of V, row
// major) of the symmetric part of A (row major).
inline void symmetric_eigen(const double *A, double w[3], double V[9]) {
    double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = 0.5 * A[3 * i + j] + 0.5 * A[3 * j + i];  // (no overflow near DBL_MAX)
    static constexpr int P[3] = {0, 0, 1}, Q[3] = {1, 2, 2};
    for (int sweep = 0; sweep < MAX_SWEEPS; ++sweep) {
        if (a[0][1] == 0.0 && a[0][2] == 0.0 && a[1][2] == 0.0) break;
        for (int r = 0; r < 3; ++r) {
            const int p = P[r], q = Q[r];
            const double apq = a[p][q];
            if (apq == 0.0) continue;
            const double g = 100.0 * std::abs(apq);
            if (sweep > 3 && std::abs(a[p][p]) + g == std::abs(a[p][p]) && std::abs(a[q][q]) + g == std::abs(a[q][q])) {
                a[p][q] = a[q][p] = 0.0;  // below the diagonal's rounding: done
                continue;
            }
            const double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
            const double t = std::abs(theta) > 1e150 ? 0.5 / theta
                                                     : std::copysign(1.0, theta) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
            const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
            for (int k = 0; k < 3; ++k) {  // A <- J^T A J on rows and columns p, q
                const double akp = a[k][p], akq = a[k][q];
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for (int k = 0; k < 3; ++k) {
                const double apk = a[p][k], aqk = a[q][k];
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            a[p][q] = a[q][p] = 0.0;
            for (int k = 0; k < 3; ++k) {
                const double vkp = v[k][p], vkq = v[k][q];
                v[k][p] = c * vkp - s * vkq;
                v[k][q] = s * vkp + c * vkq;
            }
        }
    }
    int order[3] = {0, 1, 2};
    std::stable_sort(order, order + 3, [&](int i, int j) { return a[i][i] < a[j][j]; });
    for (int c = 0; c < 3; ++c) {
        w[c] = a[order[c]][order[c]];
        for (int k = 0; k < 3; ++k) V[3 * k + c] = v[k][order[c]];
    }
}

// v flipped so that its largest-magnitude entry is positive (the first on ties).
inline void sign_fixed(double *v) {
    int k = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(v[i]) > std::abs(v[k])) k = i;
    if (v[k] < 0)
        for (int i = 0; i < 3; ++i) v[i] = -v[i];
}

// The coordinate axis least aligned with the unit vector n (the first on ties), made
// perpendicular to n and unit.
inline void plane_axis(const double *n, double *out) {
    int k = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(n[i]) < std::abs(n[k])) k = i;
    for (int i = 0; i < 3; ++i) out[i] = (i == k ? 1.0 : 0.0) - n[k] * n[i];
    const double len = norm(out);
    for (int i = 0; i < 3; ++i) out[i] /= len;
}

// The canonical frame of one matrix: moments m (ascending), R (row major, axes as columns);
// returns bit 1 when I1 == I2 and bit 2 when I2 == I3 within rtol times the largest moment.
inline int canonical_frame(const double *A, double rtol, double m[3], double R[9]) {
    double vec[9];
    symmetric_eigen(A, m, vec);
    const double scale = std::max({std::abs(m[2]), std::abs(m[0]), std::numeric_limits<double>::min()});
    const bool c01 = std::abs(m[1] - m[0]) <= rtol * scale, c12 = std::abs(m[2] - m[1]) <= rtol * scale;
    double e[3][3];  // e[i]: axis i
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) e[i][k] = vec[3 * k + i];
    if (c01 && c12) {  // every frame is principal: keep the body's
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) e[i][k] = i == k ? 1.0 : 0.0;
    } else if (c01) {  // two equal, (1, 2): the distinct axis 3, then its plane
        double d[3] = {e[2][0], e[2][1], e[2][2]};
        sign_fixed(d);
        plane_axis(d, e[0]);
        cross(d, e[0], e[1]);
        std::copy(d, d + 3, e[2]);
    } else {
        sign_fixed(e[0]);
        if (c12) {  // two equal, (2, 3): the distinct axis 1, then its plane
            plane_axis(e[0], e[1]);
        } else {
            sign_fixed(e[1]);
        }
        cross(e[0], e[1], e[2]);
    }
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) R[3 * k + i] = e[i][k];
    return (c01 ? 1 : 0) | (c12 ? 2 : 0);
}

}  // namespace inertia::principal

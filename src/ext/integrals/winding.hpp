// Generalized winding numbers: the signed solid angles of triangles seen from each point, over
// 4 pi (+-1 inside a closed surface, 0 outside).  Solid angle of one triangle (Van Oosterom &
// Strackee 1983): tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
#pragma once
#include <cmath>
#include <cstddef>

#include "integrals/vec3.hpp"

namespace inertia {

// out[i] for points (np, 3) and triangles (nt, 3, 3).
inline void winding_numbers(const double *points, size_t np, const double *tri, size_t nt, double *out) {
    for (size_t i = 0; i < np; ++i) {
        const V3 p = row(points, i);
        double total = 0.0;
        for (size_t t = 0; t < nt; ++t) {
            const V3 a = row(tri, 3 * t) - p, b = row(tri, 3 * t + 1) - p, c = row(tri, 3 * t + 2) - p;
            const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b)), lc = std::sqrt(dot(c, c));
            const double num = dot(a, cross(b, c));
            const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
            total += 2.0 * std::atan2(num, den);
        }
        out[i] = total / (4.0 * M_PI);
    }
}

}  // namespace inertia

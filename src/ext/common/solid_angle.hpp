// Solid angle of a triangle (Van Oosterom & Strackee 1983), the term of every generalized winding
// number: tan(Omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|), with a, b, c
// the corners seen from p (summed in this order); positive when p is behind the triangle.
#pragma once
#include <cmath>

#include "common/vec3.hpp"

namespace inertia {

// In (-2 pi, 2 pi): the triangle (A, B, C) seen from p.
inline double solid_angle(const double *A, const double *B, const double *C, const V3 &p) {
    const V3 a = row(A) - p, b = row(B) - p, c = row(C) - p;
    const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b)), lc = std::sqrt(dot(c, c));
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    return 2.0 * std::atan2(num, den);
}

}  // namespace inertia

// Do two triangles cross?  An edge of one passes strictly through the interior of the other,
// every orientation decided beyond eps = rtol L^3 (L the larger box diagonal of the two):
// touching faces (a shared vertex, coplanar contact) are not crossings.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace inertia::selfcross {

// Orientation tests closer to zero than this times L^3 count as touching (distances below
// about 1e-9 L).
constexpr double CROSS_RTOL = 1e-9;

// Six times the signed volume of the tetrahedron (a, b, c, d).
inline double orient(const double *a, const double *b, const double *c, const double *d) {
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    return (uy * vz - uz * vy) * wx + (uz * vx - ux * vz) * wy + (ux * vy - uy * vx) * wz;
}

// Segment pq passes strictly through the interior of triangle abc.
inline bool edge_through(const double *p, const double *q, const double *a, const double *b, const double *c,
                         double eps) {
    const double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
    if (!((sp > eps && sq < -eps) || (sp < -eps && sq > eps))) return false;
    const double u = orient(p, q, a, b), v = orient(p, q, b, c), w = orient(p, q, c, a);
    return (u > eps && v > eps && w > eps) || (u < -eps && v < -eps && w < -eps);
}

// A triangle's corners, its normal (b - a) x (c - a) and its box diagonal.
struct Tri {
    const double *p[3];
    double n[3];
    double diag;
};

inline void face_normal(const double *a, const double *b, const double *c, double *n) {
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    n[0] = uy * vz - uz * vy;
    n[1] = uz * vx - ux * vz;
    n[2] = ux * vy - uy * vx;
}

inline Tri make_tri(const double *a, const double *b, const double *c) {
    Tri t{{a, b, c}, {0, 0, 0}, 0};
    face_normal(a, b, c, t.n);
    double dd = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double d = std::max({a[k], b[k], c[k]}) - std::min({a[k], b[k], c[k]});
        dd += d * d;
    }
    t.diag = std::sqrt(dd);
    return t;
}

// The corners of s lie strictly on both sides of t's plane.
inline bool straddles(const Tri &s, const Tri &t, double eps) {
    const double *a = t.p[0];
    bool pos = false, neg = false;
    for (int k = 0; k < 3; ++k) {
        const double *p = s.p[k];
        const double o = t.n[0] * (p[0] - a[0]) + t.n[1] * (p[1] - a[1]) + t.n[2] * (p[2] - a[2]);
        pos = pos || o > eps;
        neg = neg || o < -eps;
    }
    return pos && neg;
}

// s and t cross.  A triangle whose corners do not straddle the other's plane cannot have an
// edge through it, nor can the other: rejected after three orientations each way.
inline bool tris_cross(const Tri &s, const Tri &t, double rtol) {
    const double L = std::max(s.diag, t.diag);
    const double eps = rtol * L * L * L;
    if (!(straddles(s, t, eps) && straddles(t, s, eps))) return false;
    for (int k = 0; k < 3; ++k) {
        if (edge_through(s.p[k], s.p[(k + 1) % 3], t.p[0], t.p[1], t.p[2], eps)) return true;
        if (edge_through(t.p[k], t.p[(k + 1) % 3], s.p[0], s.p[1], s.p[2], eps)) return true;
    }
    return false;
}

// Per face of F (rows of 3 vertex numbers): its normal and box diagonal, for tris_cross.
struct Frames {
    std::vector<double> n, diag;
    Frames(const double *V, const int64_t *F, size_t nf) : n(3 * nf), diag(nf) {
        for (size_t t = 0; t < nf; ++t) {
            const Tri tr = make_tri(V + 3 * F[3 * t], V + 3 * F[3 * t + 1], V + 3 * F[3 * t + 2]);
            std::copy(tr.n, tr.n + 3, &n[3 * t]);
            diag[t] = tr.diag;
        }
    }
    Tri tri(const double *V, const int64_t *F, size_t t) const {
        return Tri{{V + 3 * F[3 * t], V + 3 * F[3 * t + 1], V + 3 * F[3 * t + 2]}, {n[3 * t], n[3 * t + 1], n[3 * t + 2]},
                   diag[t]};
    }
};

}  // namespace inertia::selfcross

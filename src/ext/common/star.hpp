// The star test of a closed, consistently outward shell: every face sees the point c strictly on
// its inner side, and a ray from c leaves through exactly one face.  The radial projection from c
// is then one-to-one, so no two faces can cross (a proof in one pass).  star_faces is the test of
// 4 faces at once, run by star_certificate here and inside the clean-solid pass of the integrals.
#pragma once
#include <algorithm>
#include <cstdint>

#include "common/isa.hpp"
#include "common/vec3.hpp"

namespace inertia {
INERTIA_ISA_BEGIN

// c must lie farther than STAR_RTOL |a| |n| from each face's plane (a: the face's first corner
// seen from c, n its normal): a face nearly edge-on to c does not certify.
constexpr double STAR_RTOL = 1e-9;
// a ray's hit within this (barycentric) of a face's edge is a graze, not countable
constexpr double STAR_EDGE_RTOL = 1e-9;
// the rays, unit, irrational-looking so that they rarely pass through an edge; the first is the
// certificate's, the others are tried when it grazes
constexpr double STAR_RAYS[3][3] = {{0.2672612419124244, 0.5345224838248488, 0.8017837257372732},
                                    {-0.6396021490668313, 0.42640143271122083, 0.6396021490668313},
                                    {0.5163977794943222, -0.7745966692414834, 0.3651483716701107}};

// Per lane: off, c not strictly inside the face's plane; graze, the first ray passes within the
// margin of an edge or a vertex; hit, it leaves through the face's interior.
struct StarLanes {
    m4 off, graze, hit;
};

// Four faces in lanes: a = first corner - c, e1, e2 the edges from it, n = e1 x e2, d = a . n.
// Moller-Trumbore with det = -(ray . n) < 0, without division (s = ns / un, w = nw / un).
inline StarLanes star_faces(const V3x4 &a, const V3x4 &e1, const V3x4 &e2, const V3x4 &n, const d4 &d) {
    const V3x4 u = {d4{} + STAR_RAYS[0][0], d4{} + STAR_RAYS[0][1], d4{} + STAR_RAYS[0][2]};
    const m4 inside = (d > 0.0) & (d * d > STAR_RTOL * STAR_RTOL * dot(a, a) * dot(n, n));
    const d4 un = dot(u, n);
    const d4 ns = dot(a, cross(u, e2));
    const V3x4 q = {-a.y * e1.z + a.z * e1.y, -a.z * e1.x + a.x * e1.z, -a.x * e1.y + a.y * e1.x};
    const d4 nw = -dot(u, q);
    const d4 m = STAR_EDGE_RTOL * un;
    // turned away (the ray cannot leave through it), or outside the face beyond the margin
    const m4 miss = (un <= 0.0) | (ns < -m) | (nw < -m) | (ns + nw > un + m);
    const m4 edge = (ns < m) | (nw < m) | (ns + nw > un - m);
    return {~inside, ~miss & edge, ~miss & ~edge};
}

// Faces the ray from c along u crosses (Moller-Trumbore), or -1 when a hit is within rounding
// of an edge or a vertex.
inline int64_t ray_hits(const double *V, const int64_t *F, size_t nf, const double *c, const double *u) {
    const double rtol = STAR_EDGE_RTOL;
    int64_t hits = 0;
    for (size_t t = 0; t < nf; ++t) {
        const double *A = V + 3 * F[3 * t], *B = V + 3 * F[3 * t + 1], *C = V + 3 * F[3 * t + 2];
        const double ax = A[0] - c[0], ay = A[1] - c[1], az = A[2] - c[2];
        const double e1x = B[0] - c[0] - ax, e1y = B[1] - c[1] - ay, e1z = B[2] - c[2] - az;
        const double e2x = C[0] - c[0] - ax, e2y = C[1] - c[1] - ay, e2z = C[2] - c[2] - az;
        const double px = u[1] * e2z - u[2] * e2y, py = u[2] * e2x - u[0] * e2z, pz = u[0] * e2y - u[1] * e2x;
        const double det = e1x * px + e1y * py + e1z * pz;
        if (det == 0.0) continue;  // the ray runs parallel to the face
        const double s = (-ax * px - ay * py - az * pz) / det;
        const double qx = -ay * e1z + az * e1y, qy = -az * e1x + ax * e1z, qz = -ax * e1y + ay * e1x;
        const double w = (u[0] * qx + u[1] * qy + u[2] * qz) / det;
        if (s < -rtol || w < -rtol || s + w > 1.0 + rtol) continue;
        if (s < rtol || w < rtol || s + w > 1.0 - rtol) return -1;
        if ((e2x * qx + e2y * qy + e2z * qz) / det > 0.0) hits += 1;
    }
    return hits;
}

// True when the shell (faces F, indices checked) is star-shaped from c with a one-to-one radial
// projection: one pass of star_faces, the other rays only when the first grazes an edge.
inline bool star_certificate(const double *V, const int64_t *F, size_t nf, const double *c) {
    const V3 o = {0.0, 0.0, 0.0}, p = row(c);
    m4 graze = {}, hits = {};
    for (size_t i = 0; i < nf; i += 4) {
        const size_t m = std::min<size_t>(4, nf - i);
        const int64_t *f = F + 3 * i;
        const V3x4 A = corners(V, f, m, 0, o), e1 = corners(V, f, m, 1, o) - A, e2 = corners(V, f, m, 2, o) - A;
        const V3x4 a = {A.x - p.x, A.y - p.y, A.z - p.z}, n = cross(e1, e2);
        const StarLanes star = star_faces(a, e1, e2, n, dot(a, n));
        const m4 valid = first_lanes(m);
        if (any(star.off & valid)) return false;  // a face does not see c strictly inside
        graze |= star.graze & valid;
        hits += star.hit & valid;
    }
    if (!any(graze)) return true_count(hits) == 1;
    for (int k = 1; k < 3; ++k) {
        const int64_t n = ray_hits(V, F, nf, c, STAR_RAYS[k]);
        if (n >= 0) return n == 1;
    }
    return false;
}

INERTIA_ISA_END
}  // namespace inertia

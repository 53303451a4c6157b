// The star certificate of a closed, consistently outward shell: every face sees the point c
// strictly on its inner side, and a ray from c leaves through exactly one face.  The radial
// projection from c is then one-to-one, so no two faces can cross (a proof in one pass).
// star_face is the per-face test, shared with the clean-solid pass of the integrals family.
#pragma once
#include <cmath>
#include <cstdint>

namespace inertia::selfcross {

// c must be farther than STAR_RTOL |a| from each face's plane (a: the face's first corner seen
// from c): a face nearly edge-on to c does not certify.
constexpr double STAR_RTOL = 1e-9;
// a ray's hit within this (barycentric) of a face's edge is not countable
constexpr double STAR_EDGE_RTOL = 1e-9;
// the rays, unit, irrational-looking so that they rarely pass through an edge
constexpr double STAR_RAYS[3][3] = {{0.2672612419124244, 0.5345224838248488, 0.8017837257372732},
                                    {-0.6396021490668313, 0.42640143271122083, 0.6396021490668313},
                                    {0.5163977794943222, -0.7745966692414834, 0.3651483716701107}};

// What the faces seen so far say: `hits` faces the first ray leaves through; `state` 0 while
// every face sees c strictly inside, 1 once one does not, 2 if the ray grazes an edge.
struct StarTally {
    int64_t hits = 0;
    int state = 0;
};

// One face: a = its first corner - c, e1, e2 its edges from a, n = e1 x e2, d = a . n.
inline void star_face(double ax, double ay, double az, double e1x, double e1y, double e1z, double e2x, double e2y,
                      double e2z, double nx, double ny, double nz, double d, StarTally &star) {
    if (!(d > 0.0 && d * d > STAR_RTOL * STAR_RTOL * (ax * ax + ay * ay + az * az) * (nx * nx + ny * ny + nz * nz))) {
        star.state = 1;
        return;
    }
    const double ux = STAR_RAYS[0][0], uy = STAR_RAYS[0][1], uz = STAR_RAYS[0][2];
    const double un = ux * nx + uy * ny + uz * nz;
    if (un <= 0.0) return;  // the ray cannot leave through a face turned away
    // Moller-Trumbore with det = -un < 0: barycentrics s = ns / un, w = nw / un, no division
    const double px = uy * e2z - uz * e2y, py = uz * e2x - ux * e2z, pz = ux * e2y - uy * e2x;
    const double ns = ax * px + ay * py + az * pz;
    const double qx = -ay * e1z + az * e1y, qy = -az * e1x + ax * e1z, qz = -ax * e1y + ay * e1x;
    const double nw = -(ux * qx + uy * qy + uz * qz);
    const double m = STAR_EDGE_RTOL * un;
    if (ns < -m || nw < -m || ns + nw > un + m) return;
    if (ns < m || nw < m || ns + nw > un - m) {
        star.state = 2;  // through an edge or a vertex, to rounding
        return;
    }
    star.hits += 1;
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

// True when the shell is star-shaped from c with a one-to-one radial projection: one pass of
// star_face, the other rays only when the first grazes an edge.
inline bool star_certificate(const double *V, const int64_t *F, size_t nf, const double *c) {
    StarTally star;
    for (size_t t = 0; t < nf; ++t) {
        const double *A = V + 3 * F[3 * t], *B = V + 3 * F[3 * t + 1], *C = V + 3 * F[3 * t + 2];
        const double ax = A[0] - c[0], ay = A[1] - c[1], az = A[2] - c[2];
        const double e1x = B[0] - A[0], e1y = B[1] - A[1], e1z = B[2] - A[2];
        const double e2x = C[0] - A[0], e2y = C[1] - A[1], e2z = C[2] - A[2];
        const double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
        star_face(ax, ay, az, e1x, e1y, e1z, e2x, e2y, e2z, nx, ny, nz, ax * nx + ay * ny + az * nz, star);
        if (star.state == 1) return false;  // a face does not see c strictly inside
    }
    if (star.state == 0) return star.hits == 1;
    for (int k = 1; k < 3; ++k) {
        const int64_t n = ray_hits(V, F, nf, c, STAR_RAYS[k]);
        if (n >= 0) return n == 1;
    }
    return false;
}

}  // namespace inertia::selfcross

// The star test of faces (shared by clean_solid and the self-crossing check): a closed, outward
// shell whose every face sees a point p strictly inside its plane, and which a ray from p
// leaves through exactly one face, is star-shaped from p with a one-to-one radial projection,
// so it cannot cross itself.
#pragma once
#include <cstdint>

#include "integrals/vec3.hpp"

namespace inertia {

// The certificate's first ray (unit (1, 2, 3)) and its tolerances: p must lie farther than
// STAR_RTOL |a| |n| from each face's plane; a hit within STAR_EDGE_MARGIN (barycentric) of an
// edge is a graze.
constexpr V3 STAR_RAY = {0.2672612419124244, 0.5345224838248488, 0.8017837257372732};
constexpr double STAR_RTOL = 1e-9;
constexpr double STAR_EDGE_MARGIN = 1e-9;

// Per lane: off, p not strictly inside the face's plane; graze, the ray passes within the margin
// of an edge or a vertex; hit, it leaves through the face's interior.
struct StarLanes {
    m4 off, graze, hit;
};

// Four faces in lanes: a = first corner - p, e1, e2 the edges from it, n = e1 x e2, d = a . n.
// Moller-Trumbore with det = -(ray . n) < 0, without division (s = ns / un, w = nw / un).
inline StarLanes star_faces(const V3x4 &a, const V3x4 &e1, const V3x4 &e2, const V3x4 &n, const d4 &d) {
    const V3x4 u = {d4{} + STAR_RAY.x, d4{} + STAR_RAY.y, d4{} + STAR_RAY.z};
    const m4 inside = (d > 0.0) & (d * d > STAR_RTOL * STAR_RTOL * dot(a, a) * dot(n, n));
    const d4 un = dot(u, n);
    const d4 ns = dot(a, cross(u, e2));
    const V3x4 q = {-a.y * e1.z + a.z * e1.y, -a.z * e1.x + a.x * e1.z, -a.x * e1.y + a.y * e1.x};
    const d4 nw = -dot(u, q);
    const d4 m = STAR_EDGE_MARGIN * un;
    // turned away (the ray cannot leave through it), or outside the face beyond the margin
    const m4 miss = (un <= 0.0) | (ns < -m) | (nw < -m) | (ns + nw > un + m);
    const m4 edge = (ns < m) | (nw < m) | (ns + nw > un - m);
    return {~inside, ~miss & edge, ~miss & ~edge};
}

}  // namespace inertia

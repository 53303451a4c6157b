// One face of the star certificate (shared by clean_solid and the self-crossing check): a
// closed, outward shell whose every face sees a point p strictly inside its plane, and which a
// ray from p leaves through exactly one face, is star-shaped from p with a one-to-one radial
// projection, so it cannot cross itself.
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

struct StarTally {
    int64_t through = 0;  // faces the ray leaves through
    int state = 0;        // 0 so far so good; 1 a face does not see p strictly inside; 2 the ray grazes
};

// a = first corner - p, e1, e2 the edges from it, n = e1 x e2, d = a . n.  Moller-Trumbore
// with det = -(ray . n) < 0, written without division.
inline void star_face(const V3 &a, const V3 &e1, const V3 &e2, const V3 &n, double d, StarTally &st) {
    if (!(d > 0.0 && d * d > STAR_RTOL * STAR_RTOL * dot(a, a) * dot(n, n))) {
        st.state = 1;
        return;
    }
    const V3 &u = STAR_RAY;
    const double un = dot(u, n);
    if (un <= 0.0) return;  // the ray cannot leave through a face turned away
    const double ns = dot(a, cross(u, e2));  // s = ns / un
    const V3 q = {-a.y * e1.z + a.z * e1.y, -a.z * e1.x + a.x * e1.z, -a.x * e1.y + a.y * e1.x};
    const double nw = -dot(u, q);  // w = nw / un
    const double m = STAR_EDGE_MARGIN * un;
    if (ns < -m || nw < -m || ns + nw > un + m) return;
    if (ns < m || nw < m || ns + nw > un - m) {
        st.state = 2;  // through an edge or a vertex, to rounding
        return;
    }
    ++st.through;
}

}  // namespace inertia

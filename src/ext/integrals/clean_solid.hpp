// The common case of a solid mesh, checks and volume sums in one pass: is the mesh one closed,
// consistently wound, outward, non-degenerate shell?  When it answers no, the caller runs the
// full analysis, which names each defect; so this never explains anything, it only has to be
// right when it answers yes.
//
// Half-edges are filed under their lower vertex (CSR), matched per vertex (each other vertex
// exactly twice, once each way), and the faces of each edge joined by union-find: one component
// when exactly F - 1 joins merge two.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/isa.hpp"
#include "common/buffer.hpp"
#include "common/star.hpp"
#include "common/union_find.hpp"
#include "integrals/sums.hpp"

namespace inertia {
INERTIA_ISA_BEGIN

namespace detail {

// A half-edge filed under its lower vertex i: upper = the other vertex + 1, negated when the
// edge runs down to i; owner = 4 t + k, its face t and corner k (the edge runs from corner k).
struct HalfEdge {
    int32_t upper, owner;
};

// The faces of half-edges h and g (4 t + k) share an edge: with Join, join their sets (1 if
// they were apart); with Note, note each as the other's twin across it (adj[t, k]: the edge from
// corner k to k + 1).
template <bool Join, bool Note>
inline int join_faces(int32_t *parent, int64_t *adj, int32_t h, int32_t g) {
    const int32_t t = h >> 2, u = g >> 2;
    if (Note) {
        adj[3 * t + (h & 3)] = u;
        adj[3 * u + (g & 3)] = t;
    }
    return Join && union_low(parent, t, u) ? 1 : 0;
}

// Match the half-edges listed under each vertex i, he[end[i - 1] .. end[i]) (end[-1] = 0).  The
// number of joins that merged two components, or -1 on an open, non-manifold or inconsistent edge.
template <bool Join, bool Note>
int64_t match_edges(const int32_t *end, size_t nv, HalfEdge *he, int32_t *parent, int64_t *adj) {
    int64_t merged = 0;
    Vec<uint64_t> order;  // not std::vector: a std template on this variant's own types (common/isa.hpp)
    for (size_t i = 0, s0 = 0; i < nv; s0 = end[i++]) {
        const size_t s1 = end[i];
        if (s1 - s0 > 24) {  // a high-valence vertex: sorted, so that the matching stays linear
            order.clear();
            for (size_t j = s0; j < s1; ++j)
                order.push_back((uint64_t(std::abs(he[j].upper)) << 32) | uint32_t(j));
            std::sort(order.begin(), order.end());
            for (size_t k = 0; k < order.size(); k += 2) {
                const uint32_t j = uint32_t(order[k]), key = uint32_t(order[k] >> 32);
                if (k + 1 >= order.size() || uint32_t(order[k + 1] >> 32) != key) return -1;  // open
                if (k + 2 < order.size() && uint32_t(order[k + 2] >> 32) == key) return -1;   // non-manifold
                const uint32_t q = uint32_t(order[k + 1]);
                if (he[q].upper != -he[j].upper) return -1;  // both faces run the same way
                merged += join_faces<Join, Note>(parent, adj, he[j].owner, he[q].owner);
            }
            continue;
        }
        for (size_t j = s0; j < s1; j += 2) {  // the entries before j are matched pairs
            const int32_t u = he[j].upper;
            size_t partner = s1;
            for (size_t q = j + 1; q < s1; ++q) {
                if (std::abs(he[q].upper) != std::abs(u)) continue;
                // the same way twice (inconsistent), or a third time (non-manifold)
                if (he[q].upper == u || partner < s1) return -1;
                partner = q;
            }
            if (partner == s1) return -1;  // met once: open
            std::swap(he[j + 1], he[partner]);
            merged += join_faces<Join, Note>(parent, adj, he[j].owner, he[j + 1].owner);
        }
    }
    return merged;
}

}  // namespace detail

// True when faces (F, 3) over vertices (V, 3) form one closed, consistently wound component
// of positive volume, every coordinate finite and within +-limit, every face's area above
// area_rtol x its longest edge squared.  Then out[15] holds the 10 sums of mesh_sums<false>
// about p (out[0] = 6 x the volume), twice the total area at out[10], p = the bounding-box
// center of the used vertices at out[11..14), and out[14] = 1 when the shell is proved
// star-shaped from p (it then cannot cross itself), else 0.  adj (F, 3) or null: when given
// and the shell is not proved star-shaped, adj[t, k] is the face across the edge from corner k
// of face t to corner k + 1.  Every index is checked before use (a bad one answers false).
inline bool clean_solid(const double *v, size_t nv, const int64_t *faces, size_t nf, double area_rtol, double limit,
                        double *out, int64_t *adj) {
    if (nf < 4 || nv < 4 || nv >= (size_t(1) << 31) || 4 * nf >= (size_t(1) << 31)) return false;
    const int64_t n = static_cast<int64_t>(nv);
    // 1. half-edges a -> b are filed under min(a, b): how many under each vertex (at end[min + 1])
    Vec<int32_t> end(nv + 1, 0);
    Vec<uint8_t> used(nv, 0);
    for (size_t t = 0; t < nf; ++t) {
        const int64_t a = faces[3 * t], b = faces[3 * t + 1], c = faces[3 * t + 2];
        if (a < 0 || a >= n || b < 0 || b >= n || c < 0 || c >= n) return false;
        if (a == b || b == c || c == a) return false;
        used[a] = used[b] = used[c] = 1;
        ++end[std::min(a, b) + 1];
        ++end[std::min(b, c) + 1];
        ++end[std::min(c, a) + 1];
    }
    // 2. every vertex finite and within the limit; the bounding box of the used ones
    V3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < nv; ++i) {
        const V3 x = row(v, i);
        if (!(std::fabs(x.x) <= limit && std::fabs(x.y) <= limit && std::fabs(x.z) <= limit)) return false;
        if (used[i]) {
            lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
            hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
        }
    }
    const V3 p = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), 0.5 * (lo.z + hi.z)};
    for (size_t i = 0; i < nv; ++i) end[i + 1] += end[i];  // end[i]: where vertex i's list starts
    // 3. per face: area check, volume sums, star certificate, half-edge filing (end[i] moves to
    // the end of vertex i's list)
    Vec<detail::HalfEdge> he(3 * nf);
    const bool prefetch = nv >= PREFETCH_MIN_ROWS;
    m4 not_star = {}, through = {};  // lanes: some face off or grazed; -(faces the ray leaves through)
    const bool ok = blocked_sum<11>(nf, out, [&](size_t i, size_t m, d4 *t) INERTIA_INLINE {
        const int64_t *f = faces + 3 * i;
        if (prefetch && i + PREFETCH_FACES + 4 <= nf) {  // the rows and the half-edge slots of faces ahead
            const int64_t *g = f + 3 * PREFETCH_FACES;
            prefetch_rows(v, g, 4);
            for (size_t j = 0; j < 12; ++j)
                __builtin_prefetch(&he[end[std::min(g[j], g[j % 3 == 2 ? j - 2 : j + 1])]], 1);
        }
        const V3x4 a = corners(v, f, m, 0, p), b = corners(v, f, m, 1, p), c = corners(v, f, m, 2, p);
        const V3x4 e1 = b - a, e2 = c - a, e3 = e2 - e1;
        const V3x4 nrm = cross(e1, e2);
        const d4 a2 = sqrt4(dot(nrm, nrm)), d = dot(a, nrm);
        const m4 valid = first_lanes(m);
        // zero area relative to the face's own size (longest edge squared), not the mesh's
        const d4 l1 = dot(e1, e1), l2 = dot(e2, e2), l3 = dot(e3, e3);
        const d4 l12 = l1 > l2 ? l1 : l2;
        if (any(~(0.5 * a2 > area_rtol * (l12 > l3 ? l12 : l3)) & valid)) return false;
        const StarLanes star = star_faces(a, e1, e2, nrm, d);
        not_star |= (star.off | star.graze) & valid;
        through += star.hit & valid;
        const int32_t h0 = int32_t(4 * i);
        auto file = [&](size_t j) INERTIA_INLINE {  // half-edge j of the quad: corner j % 3 of face j / 3
            const int32_t x = int32_t(f[j]), y = int32_t(f[j % 3 == 2 ? j - 2 : j + 1]);
            he[end[std::min(x, y)]++] = {x < y ? y + 1 : -(x + 1), h0 + int32_t(j + j / 3)};
        };
        if (m == 4)
            for (size_t j = 0; j < 12; ++j) file(j);
        else
            for (size_t j = 0; j < 3 * m; ++j) file(j);
        add_moments(t, d, a, b, c);
        t[10] += a2;
        return true;
    });
    if (!ok || !(out[0] > 0.0)) return false;
    // 4. match the edges.  Proved star-shaped, the shell is one component: every closed component
    // of faces that all see p strictly inside has winding number >= 1 about p, and a ray leaves
    // it that many times, so one exit means one component.  Otherwise the faces of each edge are
    // joined by union-find: one component when F - 1 joins merged two.
    const bool star_shaped = !any(not_star) && true_count(through) == 1;
    if (star_shaped) {
        if (detail::match_edges<false, false>(end.data(), nv, he.data(), nullptr, nullptr) < 0) return false;
    } else {
        Vec<int32_t> parent(nf);
        for (size_t t = 0; t < nf; ++t) parent[t] = int32_t(t);
        const int64_t merged = adj ? detail::match_edges<true, true>(end.data(), nv, he.data(), parent.data(), adj)
                                   : detail::match_edges<true, false>(end.data(), nv, he.data(), parent.data(), adj);
        if (merged != int64_t(nf) - 1) return false;
    }
    out[11] = p.x;
    out[12] = p.y;
    out[13] = p.z;
    out[14] = star_shaped ? 1.0 : 0.0;
    return true;
}

INERTIA_ISA_END
}  // namespace inertia

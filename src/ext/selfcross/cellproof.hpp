// A proof, cell by cell of a coarse grid, that a closed shell does not cross itself, for the
// shells the star certificate cannot prove (a torus, a bracket), so that the face-pair search
// runs only where the proof fails.
//
// If two faces cross they share a point x, in some cell C; both boxes hold x, so both are among
// the faces whose boxes meet C (the cell's patch).  A patch proves that no two of its faces meet
// but along shared edges and vertices when it is a height field along one of the six axis
// directions d (projecting along an axis drops a coordinate: no rounding):
//   1. every face turns counterclockwise seen along d (the normal's d-component beyond
//      ORIENT_MARGIN times its box diagonal squared; the normal's rounding is below 1e-15);
//   2. the patch's border (edges whose face across is not in the patch) is one closed loop that
//      leaves and enters each vertex at most once, and its projection is a simple polygon.
// Then the number of faces whose projections hold a point y is the winding number of the sum
// of their borders around y; inner edges cancel in pairs (closed, consistently wound shell), the
// simple border loop winds at most once: no two projected faces overlap, and faces meeting at a
// point they do not share would (inside either projection, across an inner side, at an inner
// vertex whose fan covers a neighbourhood once, or where the border would touch itself).
// A patch that fails is cut in 8 (MAX_DEPTH times); the faces of parts still unproved go to the
// search.  Every test rounding could decide is made with a margin, the doubtful side being "not
// proved": the proof is never wrong, at worst it leaves a cell to the search.
#pragma once
#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/buffer.hpp"
#include "selfcross/crossing.hpp"

namespace inertia::selfcross {

constexpr double ORIENT_MARGIN = 1e-12;  // test 1's margin, times the face's box diagonal squared
constexpr double CELL_SLACK = 1e-9;      // cells by which a face's scaled box is widened (rounding < 1e-10)
constexpr double CCW_BOUND = 1e-15;      // rounding bound of a 2-D orientation, relative to |t1| + |t2|
constexpr int MAX_DEPTH = 2;             // a failed patch is cut in 8 up to this many times
constexpr int64_t MIN_CUT = 8;           // a patch of fewer faces is not cut (its faces go to the search)
constexpr double CELL_EDGES = 4.0;       // the grid's cells: this many median longest edges
constexpr int64_t MEDIAN_SAMPLE = 1024;  // the median longest edge is taken over about this many faces
constexpr double PROOF_CELLS_PER_FACE = 4.0;  // cells grow until the grid has at most this many per face

// The faces around each vertex, by a counting sort: vertex v's slots start[v]..start[v + 1];
// slot s holds face fac[s] and in it the corner after v, nxt[s].
// (Faces below 2^31, vertices below 2^31.)
struct VertexSlots {
    std::vector<int64_t> start;
    Vec<int32_t> fac, nxt;
    VertexSlots(const int64_t *F, size_t nf, size_t nv) : start(nv + 1, 0), fac(3 * nf), nxt(3 * nf) {
        for (size_t i = 0; i < 3 * nf; ++i) start[F[i] + 1] += 1;
        for (size_t i = 0; i < nv; ++i) start[i + 1] += start[i];
        Vec<int64_t> fill(nv);
        std::copy(start.begin(), start.end() - 1, fill.data());
        for (size_t t = 0; t < nf; ++t)
            for (int k = 0; k < 3; ++k) {
                const int64_t s = fill[F[3 * t + k]]++;
                nxt[s] = int32_t(F[3 * t + (k + 1) % 3]);
                fac[s] = int32_t(t);
            }
    }
};

// adj[3 t + k]: the face across the edge F[t, k] -> F[t, k + 1] (the one face with that edge
// the other way).  False when an edge has no such face or several: the shell is then not
// closed and consistently wound, and nothing is proved.
inline bool face_twins(const int64_t *F, size_t nf, size_t nv, int64_t *adj) {
    const VertexSlots vs(F, nf, nv);
    for (size_t t = 0; t < nf; ++t)
        for (int k = 0; k < 3; ++k) {
            const int64_t a = F[3 * t + k], b = F[3 * t + (k + 1) % 3];
            int64_t found = -1;
            for (int64_t s = vs.start[b]; s < vs.start[b + 1]; ++s)
                if (vs.nxt[s] == a) {
                    if (found >= 0) return false;
                    found = vs.fac[s];
                }
            if (found < 0) return false;
            adj[3 * t + k] = found;
        }
    return true;
}

// Sign of the 2-D orientation (p, q, r): 1, -1, or 0 when rounding could decide it.
inline int orient_sign(double pu, double pw, double qu, double qw, double ru, double rw) {
    const double t1 = (qu - pu) * (rw - pw), t2 = (qw - pw) * (ru - pu);
    const double det = t1 - t2, bound = CCW_BOUND * (std::abs(t1) + std::abs(t2));
    return det > bound ? 1 : det < -bound ? -1 : 0;
}

// The face's box in scaled coordinates (x - origin) inv; returns its diagonal squared (unscaled).
inline double scaled_box(const double *a, const double *b, const double *c, const double *origin, double inv,
                         double *lo, double *hi) {
    double dd = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double l = std::min({a[k], b[k], c[k]}), h = std::max({a[k], b[k], c[k]});
        lo[k] = (l - origin[k]) * inv;
        hi[k] = (h - origin[k]) * inv;
        dd += (h - l) * (h - l);
    }
    return dd;
}

// The axis directions along which the face turns counterclockwise (bits 1, 2, 4: +x, +y, +z;
// 8, 16, 32: -x, -y, -z): its normal's component beyond ORIENT_MARGIN times dd, the box
// diagonal squared.
inline uint8_t turn_bits(const double *a, const double *b, const double *c, double dd) {
    double n[3];
    face_normal(a, b, c, n);
    const double m = ORIENT_MARGIN * dd;
    uint8_t bits = 0;
    for (int k = 0; k < 3; ++k) bits |= n[k] > m ? uint8_t(1 << k) : n[k] < -m ? uint8_t(8 << k) : 0;
    return bits;
}

// Work arrays of patch_check, reused across patches: a patch is told apart by its mark.
struct PatchWork {
    struct Vertex {
        int64_t stamp;        // the mark of the patch whose border edges out and in these are
        int32_t out, in;
    };
    std::vector<int64_t> fstamp;  // per face: the mark of the patch holding it
    std::vector<Vertex> vwork;
    Vec<int64_t> iwork;        // the border loop, then the edges' order
    Vec<double> fwork;         // projected corners and lowest u of the loop's edges
    int64_t mark = 0;
    PatchWork(size_t nf, size_t nv, size_t biggest)
        : fstamp(nf + 1, -1), vwork(nv, Vertex{-1, -1, -1}), iwork(6 * biggest), fwork(9 * biggest) {}
};

// The closed polygon (pu, pw)[:m] turns counterclockwise about (cu, cw) along every edge
// (proved despite rounding) and goes round it once: then its angle about c increases along it
// by 2 pi in all, so every ray from c meets it once, and it is simple.  Going round once: with
// every edge counterclockwise, the edges that cross the line w = cw upwards are right of c, and
// there is one.  False: not shown.
inline bool star_loop(const double *pu, const double *pw, int64_t m, double cu, double cw) {
    int ups = 0;
    for (int64_t i = 0; i < m; ++i) {
        const int64_t j = i + 1 < m ? i + 1 : 0;
        if (orient_sign(cu, cw, pu[i], pw[i], pu[j], pw[j]) <= 0) return false;
        ups += pw[i] < cw && pw[j] >= cw;
    }
    return ups == 1;
}

// The closed polygon loop[:m] (vertex numbers, projected on iu, iw) is simple: star_loop about
// the mean of its corners (about half the loops), else every pair of edges not neighbours in the
// loop proved apart (a sweep over the edges sorted by lowest u, then number).
inline bool simple_loop(const double *V, int iu, int iw, const int64_t *loop, int64_t m, double *fwork,
                        int64_t *order) {
    double *pu = fwork, *pw = fwork + m, *lo_u = fwork + 2 * m;
    double su = 0.0, sw = 0.0;
    for (int64_t i = 0; i < m; ++i) {
        pu[i] = V[3 * loop[i] + iu];
        pw[i] = V[3 * loop[i] + iw];
        su += pu[i], sw += pw[i];
    }
    if (star_loop(pu, pw, m, su / double(m), sw / double(m))) return true;
    for (int64_t i = 0; i < m; ++i) {
        lo_u[i] = std::min(pu[i], pu[i + 1 < m ? i + 1 : 0]);
        int64_t r = i;  // insertion sort of short loops (stable: the order of the sort below)
        for (; m <= 24 && r > 0 && lo_u[order[r - 1]] > lo_u[i]; --r) order[r] = order[r - 1];
        order[r] = i;
    }
    if (m > 24)
        std::sort(order, order + m, [&](int64_t a, int64_t b) { return lo_u[a] < lo_u[b] || (lo_u[a] == lo_u[b] && a < b); });
    for (int64_t r = 0; r < m; ++r) {
        const int64_t i = order[r], i2 = i + 1 < m ? i + 1 : 0, i0 = i > 0 ? i - 1 : m - 1;
        const double pu1 = pu[i], pw1 = pw[i], pu2 = pu[i2], pw2 = pw[i2];
        const double hu = std::max(pu1, pu2), lw = std::min(pw1, pw2), hw = std::max(pw1, pw2);
        for (int64_t q = r + 1; q < m; ++q) {
            const int64_t j = order[q];
            if (lo_u[j] > hu) break;             // this one and the rest start after edge i ends
            if (j == i2 || j == i0) continue;    // neighbours in the loop meet at their corner
            const int64_t j2 = j + 1 < m ? j + 1 : 0;
            const double qw1 = pw[j], qw2 = pw[j2];
            if (std::min(qw1, qw2) > hw || std::max(qw1, qw2) < lw) continue;
            const double qu1 = pu[j], qu2 = pu[j2];
            const int s1 = orient_sign(pu1, pw1, pu2, pw2, qu1, qw1), s2 = orient_sign(pu1, pw1, pu2, pw2, qu2, qw2);
            if (s1 != 0 && s1 == s2) continue;   // q on one side of p's line
            const int s3 = orient_sign(qu1, qw1, qu2, qw2, pu1, pw1), s4 = orient_sign(qu1, qw1, qu2, qw2, pu2, pw2);
            if (s3 != 0 && s3 == s4) continue;
            return false;
        }
    }
    return true;
}

// 0 when the faces faces[:n] form a height field along one axis (then no two of them meet but
// where they share edges and vertices); else the first test failed: 1 a face not turned along
// the axis, 2 two border edges out of (or into) a vertex, 3 fewer than three border edges,
// 4 more than one border loop, 5 a border loop not simple.  `adj` may name face nf (outside).
inline int patch_check(const double *V, const int64_t *F, const uint8_t *bits_of, const int64_t *adj,
                       const int64_t *faces, int64_t n, PatchWork &w) {
    const int64_t mark = w.mark++;
    if (n < 2) return 0;
    int bits = 63;  // the directions along which every face turns counterclockwise
    for (int64_t i = 0; i < n; ++i) {
        bits &= bits_of[faces[i]];
        if (bits == 0) return 1;
        w.fstamp[faces[i]] = mark;
    }
    int ax = 0;
    while (!(bits & (1 << ax))) ++ax;
    // (u, w, d) right-handed: the faces turn counterclockwise in (u, w) seen along d
    static constexpr int IU[6] = {1, 2, 0, 2, 0, 1}, IW[6] = {2, 0, 1, 1, 2, 0};
    // the border: edges whose face across is not in the patch; per vertex its edge out and in
    PatchWork::Vertex *vw = w.vwork.data();
    int64_t n_border = 0, first = -1;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t t = faces[i];
        for (int k = 0; k < 3; ++k) {
            if (w.fstamp[adj[3 * t + k]] == mark) continue;
            const int64_t v = F[3 * t + k], a = F[3 * t + (k + 1) % 3];
            for (int64_t x : {v, a})
                if (vw[x].stamp != mark) vw[x] = PatchWork::Vertex{mark, -1, -1};
            if (vw[v].out >= 0 || vw[a].in >= 0) return 2;  // two border edges out of v, or into a
            vw[v].out = int32_t(a);
            vw[a].in = int32_t(v);
            ++n_border;
            first = v;
        }
    }
    if (n_border < 3) return 3;
    // one loop: n_border steps along the edges out come back to the first vertex, and not before
    int64_t *loop = w.iwork.data();
    int64_t v = first;
    for (int64_t i = 0; i < n_border; ++i) {
        loop[i] = v;
        v = vw[v].out;
        if (v < 0 || (v == first && i < n_border - 1)) return 4;
    }
    if (v != first) return 4;
    return simple_loop(V, IU[ax], IW[ax], loop, n_border, w.fwork.data(), loop + n_border) ? 0 : 5;
}

// The low and high corners of the vertices the faces use (NaN if one is not finite), and the
// median of the faces' longest edges over at most about MEDIAN_SAMPLE faces evenly spread (a
// cell size, not a measurement).
inline double box_and_median_edge(const double *V, const int64_t *F, size_t nf, double *origin, double *top) {
    const double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};  // locals: the stores would alias V
    bool bad = false;  // a NaN or infinity: x - x is not 0 (an integer or, no floating-point chain)
    for (size_t i = 0; i < 3 * nf; ++i)
        for (int k = 0; k < 3; ++k) {
            const double x = V[3 * F[i] + k];
            lo[k] = std::min(lo[k], x), hi[k] = std::max(hi[k], x), bad |= !(x - x == 0.0);
        }
    const bool finite = !bad;
    for (int k = 0; k < 3; ++k) origin[k] = finite ? lo[k] : NAN, top[k] = finite ? hi[k] : NAN;
    const size_t stride = std::max<size_t>(1, nf / MEDIAN_SAMPLE);
    std::vector<double> longest((nf + stride - 1) / stride);
    for (size_t i = 0; i < longest.size(); ++i) {
        const int64_t *f = F + 3 * i * stride;
        double m = 0.0;
        for (int k = 0; k < 3; ++k) {
            const double *a = V + 3 * f[k], *b = V + 3 * f[(k + 1) % 3];
            const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
            m = std::max(m, dx * dx + dy * dy + dz * dz);
        }
        longest[i] = m;
    }
    const size_t n = longest.size(), half = n / 2;
    if (n == 0) return std::nan("");
    std::nth_element(longest.begin(), longest.begin() + half, longest.end());
    double med = longest[half];
    if (n % 2 == 0) med = (*std::max_element(longest.begin(), longest.begin() + half) + med) / 2;
    return std::sqrt(med);
}

// Sets keep[t] for the faces of the patches patch_check does not prove (each failed cell cut
// in 8 up to MAX_DEPTH times); returns how many.  adj: face_twins; h: the cell.
inline int64_t unproved_faces(const double *V, const int64_t *F, size_t nf, size_t nv, const int64_t *adj,
                              const double *origin, const double *top, double h, uint8_t *keep) {
    if (!(h > 0.0 && h < std::numeric_limits<double>::infinity())) {
        std::fill(keep, keep + nf, uint8_t(1));
        return int64_t(nf);
    }
    int64_t dims[3];
    while (true) {  // at most PROOF_CELLS_PER_FACE cells a face (and 64 more), and 1e5 per axis
        double cells = 1.0;
        for (int c = 0; c < 3; ++c) {
            const double d = std::floor((top[c] - origin[c]) / h + CELL_SLACK) + 1.0;
            cells *= d;
            dims[c] = int64_t(std::min(d, 1e5));
        }
        if (cells <= PROOF_CELLS_PER_FACE * double(nf) + 64 && std::max({dims[0], dims[1], dims[2]}) < 100000) break;
        h *= 2.0;
    }
    const double inv = 1.0 / h;
    const int64_t ncell = dims[0] * dims[1] * dims[2];
    auto corners = [&](int64_t t) { return std::array<const double *, 3>{V + 3 * F[3 * t], V + 3 * F[3 * t + 1], V + 3 * F[3 * t + 2]}; };
    Vec<uint8_t> bits(nf);
    Vec<int32_t> ilo(3 * nf), ihi(3 * nf);  // cells, below 1e5 an axis
    std::vector<int64_t> counts(ncell + 1, 0);
    const int64_t d1 = dims[1], d2 = dims[2];  // locals: stores to the counts would alias dims
    auto each_cell = [&](size_t t, auto &&fn) {
        const int32_t *l = &ilo[3 * t], *u = &ihi[3 * t];  // most faces: one cell
        if (l[0] == u[0] && l[1] == u[1] && l[2] == u[2]) return fn((int64_t(l[0]) * d1 + l[1]) * d2 + l[2]);
        for (int64_t x = ilo[3 * t]; x <= ihi[3 * t]; ++x)
            for (int64_t y = ilo[3 * t + 1]; y <= ihi[3 * t + 1]; ++y)
                for (int64_t z = ilo[3 * t + 2]; z <= ihi[3 * t + 2]; ++z) fn((x * d1 + y) * d2 + z);
    };
    for (size_t t = 0; t < nf; ++t) {
        const auto [a, b, c] = corners(int64_t(t));
        double bl[3], bh[3];
        bits[t] = turn_bits(a, b, c, scaled_box(a, b, c, origin, inv, bl, bh));
        for (int k = 0; k < 3; ++k) {
            ilo[3 * t + k] = int32_t(std::max(int64_t(std::floor(bl[k] - CELL_SLACK)), int64_t(0)));
            ihi[3 * t + k] = int32_t(std::min(int64_t(std::floor(bh[k] + CELL_SLACK)), dims[k] - 1));
        }
        each_cell(t, [&](int64_t i) { counts[i + 1] += 1; });
    }
    for (int64_t i = 0; i < ncell; ++i) counts[i + 1] += counts[i];
    Vec<int64_t> fill(ncell), entries(counts[ncell]);
    std::copy(counts.begin(), counts.end() - 1, fill.data());
    for (size_t t = 0; t < nf; ++t) each_cell(t, [&](int64_t i) { entries[fill[i]++] = int64_t(t); });
    int64_t biggest = 1;
    for (int64_t i = 0; i < ncell; ++i) biggest = std::max(biggest, counts[i + 1] - counts[i]);
    PatchWork work(nf, nv, size_t(biggest));
    // the stack of cut parts: their faces (the parts of a part of m faces take 8 m slots above
    // it), and each part's low corner, size (scaled) and depth
    constexpr int SLOTS = 8 * MAX_DEPTH + 1;
    Vec<int64_t> stack_faces(size_t(biggest) * SLOTS);
    struct Part {
        int64_t start, n;
        double lo[3], size;
        int depth;
    } st[SLOTS];
    int64_t n_keep = 0;
    for (int64_t x = 0; x < dims[0]; ++x)
        for (int64_t y = 0; y < dims[1]; ++y)
            for (int64_t z = 0; z < dims[2]; ++z) {
                const int64_t i = (x * dims[1] + y) * dims[2] + z, c0 = counts[i], n = counts[i + 1] - c0;
                if (n < 2 || patch_check(V, F, bits.data(), adj, &entries[c0], n, work) == 0) continue;
                std::copy(&entries[c0], &entries[c0] + n, stack_faces.data());  // cut it: depth first
                int sp = 1;
                st[0] = Part{0, n, {double(x), double(y), double(z)}, 1.0, 0};
                bool first_pop = true;
                while (sp > 0) {
                    const Part p = st[--sp];
                    if (!first_pop && (p.n < 2 || patch_check(V, F, bits.data(), adj, &stack_faces[p.start], p.n, work) == 0))
                        continue;
                    first_pop = false;
                    if (p.depth >= MAX_DEPTH || p.n < MIN_CUT) {
                        for (int64_t k = 0; k < p.n; ++k) {
                            const int64_t t = stack_faces[p.start + k];
                            n_keep += !keep[t];
                            keep[t] = 1;
                        }
                        continue;
                    }
                    // part q's faces in m slots from base + m q.  A face goes to the parts on the
                    // sides of the three inner planes its box reaches (with the slack): every part it
                    // meets, at worst a few more (sound: a patch of more faces proves more)
                    const double half = 0.5 * p.size, mid[3] = {p.lo[0] + half, p.lo[1] + half, p.lo[2] + half};
                    const int64_t base = p.start + p.n, m = p.n;
                    int64_t cnt[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                    for (int64_t k = 0; k < m; ++k) {
                        const int64_t t = stack_faces[p.start + k];
                        const auto [a, b, c] = corners(t);
                        double bl[3], bh[3];
                        scaled_box(a, b, c, origin, inv, bl, bh);
                        int r0[3], r1[3];
                        for (int k3 = 0; k3 < 3; ++k3) {
                            r0[k3] = bl[k3] <= mid[k3] + CELL_SLACK ? 0 : 1;
                            r1[k3] = bh[k3] >= mid[k3] - CELL_SLACK ? 2 : 1;
                        }
                        for (int zb = r0[2]; zb < r1[2]; ++zb)
                            for (int yb = r0[1]; yb < r1[1]; ++yb)
                                for (int xb = r0[0]; xb < r1[0]; ++xb) {
                                    const int q = xb + 2 * yb + 4 * zb;
                                    stack_faces[base + q * m + cnt[q]++] = t;
                                }
                    }
                    for (int q = 0; q < 8; ++q)
                        st[sp++] = Part{base + q * m, cnt[q],
                                        {p.lo[0] + half * (q & 1), p.lo[1] + half * ((q >> 1) & 1),
                                         p.lo[2] + half * ((q >> 2) & 1)},
                                        half, p.depth + 1};
                }
            }
    return n_keep;
}

}  // namespace inertia::selfcross

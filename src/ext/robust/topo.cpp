// Topology of the chain, vertex by vertex in O(n) from the faces around each vertex (a
// counting sort, no hash table): repeated faces merged with a multiplicity, certified
// vertices, the face across each manifold edge, boundary edges, patches of uncut faces;
// and the weighted sums of signed tetrahedra.
#include "common/union_find.hpp"
#include "robust/kernels.hpp"

namespace inertia::robust {
namespace {

// CSR of faces by their lowest corner, in increasing face order.
void faces_by_lowest(const int64_t* F, size_t nf, size_t nv, std::vector<int64_t>& ptr, std::vector<int64_t>& idx) {
    ptr.assign(nv + 1, 0);
    auto low = [&](size_t f) { return std::min(F[3 * f], std::min(F[3 * f + 1], F[3 * f + 2])); };
    for (size_t f = 0; f < nf; ++f) ptr[low(f) + 1]++;
    for (size_t v = 0; v < nv; ++v) ptr[v + 1] += ptr[v];
    idx.assign(nf, 0);
    std::vector<int64_t> fill(ptr.begin(), ptr.end() - 1);
    for (size_t f = 0; f < nf; ++f) idx[fill[low(f)]++] = int64_t(f);
}

// Parity of the permutation sorting (a, b, c) (distinct): true when odd.
bool odd_perm(int64_t a, int64_t b, int64_t c) {
    bool odd = false;
    if (a > b) std::swap(a, b), odd = !odd;
    if (b > c) std::swap(b, c), odd = !odd;
    if (a > b) odd = !odd;
    return odd;
}

// Faces with distinct corners, equal corner sets merged in order of first appearance, with
// their net multiplicity (copies oriented like the first +1, others -1); cancelled groups
// dropped, a negative group written flipped.
nb::tuple dedupe_faces(Faces faces, size_t n_vertices) {
    const int64_t* F = faces.data();
    const size_t nf = faces.shape(0);
    check_faces(F, nf, n_vertices);
    std::vector<int64_t> out;
    std::vector<double> mult;
    {
        nb::gil_scoped_release unlocked;
        std::vector<int64_t> ptr, idx, leader(nf);
        std::vector<double> net(nf, 0.0);
        faces_by_lowest(F, nf, n_vertices, ptr, idx);
        for (size_t f = 0; f < nf; ++f) leader[f] = int64_t(f);
        for (size_t v = 0; v < n_vertices; ++v)
            for (int64_t i = ptr[v]; i < ptr[v + 1]; ++i) {
                const int64_t f = idx[i];
                if (leader[f] != f) continue;
                const int64_t a = F[3 * f], b = F[3 * f + 1], c = F[3 * f + 2];
                if (a == b || b == c || c == a) {
                    leader[f] = -1;
                    continue;
                }
                net[f] = 1.0;
                const int64_t s = a + b + c, hi = std::max(a, std::max(b, c));
                const bool odd = odd_perm(a, b, c);
                for (int64_t j = i + 1; j < ptr[v + 1]; ++j) {
                    const int64_t g = idx[j];
                    if (leader[g] != g) continue;
                    const int64_t x = F[3 * g], y = F[3 * g + 1], z = F[3 * g + 2];
                    // same lowest corner (v); equal sets iff equal sums and equal highest corners
                    if (x + y + z == s && std::max(x, std::max(y, z)) == hi && x != y && y != z && z != x) {
                        leader[g] = f;
                        net[f] += odd_perm(x, y, z) == odd ? 1.0 : -1.0;
                    }
                }
            }
        for (size_t f = 0; f < nf; ++f) {
            if (leader[f] != int64_t(f) || net[f] == 0.0) continue;
            const double m = net[f];
            out.insert(out.end(), {F[3 * f], m > 0 ? F[3 * f + 1] : F[3 * f + 2], m > 0 ? F[3 * f + 2] : F[3 * f + 1]});
            mult.push_back(std::abs(m));
        }
    }
    const size_t n = mult.size();
    return nb::make_tuple(to_numpy(std::move(out), {n, 3}), to_numpy(std::move(mult), {n}));
}

// A face f around vertex v: the corners after v (a, b), its multiplicity, v's position in it.
struct Corner {
    int64_t f, a, b;
    double m;
    int64_t q;
};

// The corners of the faces around each vertex (CSR, increasing face order), of the faces with
// keep[f] (all if keep is empty).
void vertex_corners(const Mesh& m, const std::vector<char>& keep, std::vector<int64_t>& ptr, std::vector<Corner>& out) {
    ptr.assign(m.nv + 1, 0);
    for (size_t f = 0; f < m.nf; ++f)
        if (keep.empty() || keep[f])
            for (int k = 0; k < 3; ++k) ptr[m.F[3 * f + k] + 1]++;
    for (size_t v = 0; v < m.nv; ++v) ptr[v + 1] += ptr[v];
    out.resize(size_t(ptr[m.nv]));
    std::vector<int64_t> fill(ptr.begin(), ptr.end() - 1);
    for (size_t f = 0; f < m.nf; ++f)
        if (keep.empty() || keep[f])
            for (int q = 0; q < 3; ++q)
                out[fill[m.F[3 * f + q]]++] = {int64_t(f), m.F[3 * f + (q + 1) % 3], m.F[3 * f + (q + 2) % 3], m.M[f],
                                               q};
}

// The faces around one vertex v: corners after v (A, B), the face (W), its multiplicity (Mf),
// v's position in it (Q), and per link edge L = (next, previous, #A==A[t], #B==B[t], #A==B[t],
// #B==A[t]).
struct Star {
    std::vector<int64_t> A, B, W, Q;
    std::vector<double> Mf;
    std::vector<std::array<int64_t, 6>> L;
    std::vector<char> flag;
    std::vector<std::array<double, 9>> C;
    size_t k = 0;
    explicit Star(size_t kmax) : A(kmax), B(kmax), W(kmax), Q(kmax), Mf(kmax), L(kmax), flag(kmax), C(kmax) {}

    void load(const std::vector<int64_t>& ptr, const std::vector<Corner>& corners, int64_t v) {
        k = 0;
        for (int64_t i = ptr[v]; i < ptr[v + 1]; ++i, ++k) {
            const Corner& c = corners[i];
            A[k] = c.a, B[k] = c.b, W[k] = c.f, Q[k] = c.q, Mf[k] = c.m;
        }
    }
    void link() {
        for (size_t t = 0; t < k; ++t) {
            const int64_t a = A[t], b = B[t];
            int64_t nxt = -1, prv = -1, ca = 0, cb = 0, cn = 0, cp = 0;
            for (size_t u = 0; u < k; ++u) {
                ca += A[u] == a;
                cb += B[u] == b;
                if (A[u] == b && cn++ == 0) nxt = int64_t(u);
                if (B[u] == a && cp++ == 0) prv = int64_t(u);
            }
            L[t] = {nxt, prv, ca, cb, cn, cp};
        }
    }
    // (multiplicity v -> x, multiplicity x -> v) of edge {v, x}
    std::pair<double, double> uses(int64_t x) const {
        double m_out = 0.0, m_in = 0.0;
        for (size_t u = 0; u < k; ++u) {
            if (A[u] == x) m_out += Mf[u];
            if (B[u] == x) m_in += Mf[u];
        }
        return {m_out, m_in};
    }
};

// Counts of open, inconsistently wound, non-manifold edges, with edge (m_out, m_in) added.
void count_kind(int64_t* kinds, double m_out, double m_in) {
    const double n = m_out + m_in;
    if (n < 1.5)
        kinds[0]++;
    else if (n < 2.5) {
        if (m_out != m_in) kinds[1]++;
    } else
        kinds[2]++;
}

bool first_in(const std::vector<int64_t>& X, size_t t, int64_t x) {
    for (size_t u = 0; u < t; ++u)
        if (X[u] == x) return false;
    return true;
}

// Pair the faces of v's manifold edges {v, x}, x > v, into nbr; count the edge kinds; returns
// the number of boundary edges (net multiplicity not 0).
int64_t vertex_edges(const Star& s, int64_t v, int64_t* nbr, int64_t* kinds) {
    int64_t n_bnd = 0;
    for (size_t t = 0; t < s.k; ++t) {
        const auto& L = s.L[t];
        int64_t x = s.A[t];  // edge v -> A[t]
        if (x > v) {
            if (L[2] > 1 || L[5] > 1) {
                if (first_in(s.A, t, x)) {
                    auto [m_out, m_in] = s.uses(x);
                    n_bnd += std::abs(m_out - m_in) >= 0.5;
                    count_kind(kinds, m_out, m_in);
                }
            } else {
                const double m_out = s.Mf[t];
                double m_in = 0.0;
                const int64_t u = L[1];
                if (u >= 0) {
                    m_in = s.Mf[u];
                    if (m_out == m_in) {
                        nbr[3 * s.W[t] + s.Q[t]] = s.W[u];
                        nbr[3 * s.W[u] + (s.Q[u] + 2) % 3] = s.W[t];
                    }
                }
                n_bnd += std::abs(m_out - m_in) >= 0.5;
                if (m_out != 1.0 || m_in != 1.0) count_kind(kinds, m_out, m_in);
            }
        }
        x = s.B[t];  // edge B[t] -> v with no face v -> B[t]
        if (x > v && L[4] == 0) {
            if (L[3] > 1) {
                if (first_in(s.B, t, x)) {
                    auto [m_out, m_in] = s.uses(x);
                    n_bnd += std::abs(m_out - m_in) >= 0.5;
                    count_kind(kinds, m_out, m_in);
                }
            } else {
                n_bnd += s.Mf[t] >= 0.5;
                count_kind(kinds, 0.0, s.Mf[t]);
            }
        }
    }
    return n_bnd;
}

// How the link edges connect: 2 one cycle, 1 one path, 0 neither (the tails distinct, the walk
// along `next` from the start reaching all k edges, then stopping or closing).
int fan_kind(Star& s) {
    size_t start = 0, n_starts = 0;
    for (size_t t = 0; t < s.k; ++t) {
        if (s.L[t][2] > 1) return 0;
        if (s.L[t][5] == 0) start = t, n_starts++;
        s.flag[t] = 0;
    }
    if (n_starts > 1) return 0;
    int64_t t = int64_t(start), last = -1;
    size_t count = 0;
    while (t != -1 && !s.flag[t]) {
        s.flag[t] = 1;
        count++;
        last = t;
        t = s.L[t][0];
    }
    if (count != s.k) return 0;
    if (n_starts == 0) return s.L[last][0] == int64_t(start) ? 2 : 0;
    return s.L[last][0] == -1 ? 1 : 0;
}

// The fan around v projects along its mean normal into disjoint sectors: each face positive
// beyond a 1e-9 relative margin, and the sectors cover the circle once (cycle) or less (path).
bool fan_flat(Star& s, const double* V, int64_t v, int kind) {
    const double* p = V + 3 * v;
    auto& C = s.C;
    double n[3] = {0.0, 0.0, 0.0};
    for (size_t t = 0; t < s.k; ++t) sub(V + 3 * s.A[t], p, &C[t][3]);
    for (size_t t = 0; t < s.k; ++t) {
        const int64_t u = s.L[t][0];  // the edge starting at B[t]: its corner vector, already read
        if (u >= 0)
            for (int c = 0; c < 3; ++c) C[t][6 + c] = C[u][3 + c];
        else
            sub(V + 3 * s.B[t], p, &C[t][6]);
        cross(&C[t][3], &C[t][6], &C[t][0]);
        for (int c = 0; c < 3; ++c) n[c] += C[t][c];
    }
    const double ln = norm(n);
    if (!(ln > 0.0)) return false;
    for (double& x : n) x /= ln;
    for (size_t t = 0; t < s.k; ++t) {
        const double cn = dot(&C[t][0], n);  // cn > 1e-9 |c|, squared
        if (!(cn > 0.0 && cn * cn > 1e-18 * dot(&C[t][0], &C[t][0]))) return false;
    }
    if (kind == 1) {
        double total = 0.0;
        for (size_t t = 0; t < s.k; ++t) {
            const double *a = &C[t][3], *b = &C[t][6];
            const double an = dot(a, n), bn = dot(b, n);
            total += std::atan2(dot(&C[t][0], n), dot(a, b) - an * bn);
        }
        return total < TWO_PI - 1e-9;
    }
    // cycle: u = bisector of sector 0; sector t contains u iff a_t . w >= 0 >= b_t . w, w = u x n
    const double *a0 = &C[0][3], *b0 = &C[0][6];
    const double la = norm(a0), lb = norm(b0);
    double u[3], w[3];
    for (int c = 0; c < 3; ++c) u[c] = a0[c] / la + b0[c] / lb;
    cross(u, n, w);
    const double lw = norm(w);
    if (!(lw > 0.0)) return false;
    const double m2 = 1e-18 * lw * lw;
    for (size_t t = 1; t < s.k; ++t) {
        const double *a = &C[t][3], *b = &C[t][6];
        const double aw = dot(a, w), bw = dot(b, w);
        // a . w >= -1e-9 |w| |a| and b . w <= 1e-9 |w| |b|, squared
        if ((aw >= 0.0 || aw * aw <= m2 * dot(a, a)) && (bw <= 0.0 || bw * bw <= m2 * dot(b, b)))
            return false;  // u in (or within the margin of) another sector
    }
    return true;
}

size_t max_valence(const std::vector<int64_t>& ptr) {
    int64_t kmax = 1;
    for (size_t v = 0; v + 1 < ptr.size(); ++v) kmax = std::max(kmax, ptr[v + 1] - ptr[v]);
    return size_t(kmax);
}

// For each vertex v of `verts` (increasing): cert[v] (no two faces around v share a point but
// v and their common edges: one fan, flat in projection), nbr (the face across each manifold,
// consistently wound edge of equal multiplicities that v owns, v < x); returns the counts of
// open, inconsistent, non-manifold edges (3,) and the boundary edges (tail, head) with their
// net multiplicities, by vertex.
nb::tuple vertex_pass(Vertices V, Faces F, In1<double> M, In1<int64_t> verts, Out1<bool> cert, Out2<int64_t> nbr,
                      int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const size_t nvv = verts.shape(0);
    check_range(verts.data(), nvv, 0, int64_t(m.nv), "verts");
    for (size_t j = 1; j < nvv; ++j)
        if (verts(j) <= verts(j - 1)) input_error("verts must be increasing");
    check_length(cert.shape(0), m.nv, "cert");
    check_length(nbr.shape(0), m.nf, "nbr");
    check_length(nbr.shape(1), 3, "nbr's rows");
    std::vector<int64_t> kinds_total(3, 0), edges;
    std::vector<double> emult;
    {
        nb::gil_scoped_release unlocked;
        std::vector<int64_t> ptr, n_bnd(nvv), kinds(3 * nvv, 0);
        std::vector<Corner> corners;
        std::vector<char> keep;  // a few vertices: list only the faces around them
        if (nvv < m.nv / 8) {
            std::vector<char> mark(m.nv, 0);
            for (size_t j = 0; j < nvv; ++j) mark[verts(j)] = 1;
            keep.resize(m.nf);
            for (size_t f = 0; f < m.nf; ++f) keep[f] = mark[m.F[3 * f]] | mark[m.F[3 * f + 1]] | mark[m.F[3 * f + 2]];
        }
        vertex_corners(m, keep, ptr, corners);
        const size_t kmax = max_valence(ptr);
        bool* ok = cert.data();
        int64_t* nb_ = nbr.data();
        const int64_t* vs = verts.data();
        parallel_for(nvv, threads, 2048, [&](size_t j0, size_t j1) {
            Star s(kmax);
            for (size_t j = j0; j < j1; ++j) {
                const int64_t v = vs[j];
                s.load(ptr, corners, v);
                ok[v] = false;
                s.link();
                n_bnd[j] = vertex_edges(s, v, nb_, &kinds[3 * j]);
                if (s.k < 2) continue;
                const int kind = fan_kind(s);
                if (kind != 0) ok[v] = fan_flat(s, m.V, v, kind);
            }
        });
        Star s(kmax);
        for (size_t j = 0; j < nvv; ++j) {
            for (int c = 0; c < 3; ++c) kinds_total[c] += kinds[3 * j + c];
            if (n_bnd[j] == 0) continue;
            const int64_t v = vs[j];
            s.load(ptr, corners, v);
            for (size_t t = 0; t < 2 * s.k; ++t) {
                const int64_t x = t < s.k ? s.A[t] : s.B[t - s.k];
                bool seen = x < v;
                for (size_t u = 0; u < t && !seen; ++u) seen = (u < s.k ? s.A[u] : s.B[u - s.k]) == x;
                if (seen) continue;
                auto [m_out, m_in] = s.uses(x);
                if (std::abs(m_out - m_in) >= 0.5) {
                    edges.insert(edges.end(), {m_out > m_in ? v : x, m_out > m_in ? x : v});
                    emult.push_back(std::abs(m_out - m_in));
                }
            }
        }
    }
    const size_t ne = emult.size();
    return nb::make_tuple(to_numpy(std::move(kinds_total), {3}), to_numpy(std::move(edges), {ne, 2}),
                          to_numpy(std::move(emult), {ne}));
}

// Patches of uncut faces joined across nbr (vertex_pass): labels (F,) in 0..n-1 (cut faces
// alone in theirs), n, and per patch the uncut face of largest area (-1 if none).
nb::tuple patch_reps(Vertices V, Faces F, In2<int64_t> nbr, In1<bool> cut) {
    const Mesh m = mesh_of(V, F);
    const size_t nf = m.nf;
    check_length(nbr.shape(0), nf, "nbr");
    check_length(nbr.shape(1), 3, "nbr's rows");
    check_range(nbr.data(), 3 * nf, -1, int64_t(nf), "nbr");
    check_length(cut.shape(0), nf, "cut");
    std::vector<int64_t> labels(nf), reps;
    {
        nb::gil_scoped_release unlocked;
        const bool* cu = cut.data();
        const int64_t* nb_ = nbr.data();
        std::vector<int64_t> parent(nf);
        for (size_t f = 0; f < nf; ++f) parent[f] = int64_t(f);
        for (size_t f = 0; f < nf; ++f) {
            if (cu[f]) continue;
            for (int e = 0; e < 3; ++e) {
                const int64_t g = nb_[3 * f + e];
                if (g >= 0 && !cu[g]) union_low(parent.data(), int64_t(f), g);
            }
        }
        int64_t n = 0;
        for (size_t f = 0; f < nf; ++f) {
            const int64_t r = find_root(parent.data(), int64_t(f));
            labels[f] = r == int64_t(f) ? n++ : labels[r];
        }
        reps.assign(size_t(n), -1);
        std::vector<double> best(size_t(n), -1.0);
        for (size_t f = 0; f < nf; ++f) {
            if (cu[f]) continue;
            double a[3], b[3], c[3];
            sub(m.at(f, 1), m.at(f, 0), a);
            sub(m.at(f, 2), m.at(f, 0), b);
            cross(a, b, c);
            const double a2 = dot(c, c);
            if (a2 > best[labels[f]]) best[labels[f]] = a2, reps[labels[f]] = int64_t(f);
        }
    }
    const size_t n = reps.size();
    return nb::make_tuple(to_numpy(std::move(labels), {nf}), to_numpy(std::move(reps), {n}));
}

// sum_f w_f of the signed tetrahedron (p, face f) integrals, times 6, 24 (x3), 120 (x6)
// (tetra_add): in blocks of 256 faces (in parallel), then the blocks in order.
nb::ndarray<nb::numpy, double, nb::ndim<1>> weighted_sums(Vertices V, Faces F, In1<double> w, In1<double> p,
                                                          int threads) {
    const Mesh m = mesh_of(V, F);
    check_length(w.shape(0), m.nf, "weights");
    check_length(p.shape(0), 3, "p");
    std::vector<double> out(10, 0.0);
    {
        nb::gil_scoped_release unlocked;
        const size_t nb_ = (m.nf + 255) / 256;
        std::vector<double> blk(10 * nb_, 0.0);
        const double *P = p.data(), *W = w.data();
        parallel_for(nb_, threads, 64, [&](size_t b0, size_t b1) {
            for (size_t b = b0; b < b1; ++b)
                for (size_t f = 256 * b; f < std::min(m.nf, 256 * b + 256); ++f) {
                    if (W[f] == 0.0) continue;
                    double y[3][3];
                    for (int k = 0; k < 3; ++k) sub(m.at(int64_t(f), k), P, y[k]);
                    tetra_add(&blk[10 * b], W[f], y[0], y[1], y[2]);
                }
        });
        for (size_t b = 0; b < nb_; ++b)
            for (int i = 0; i < 10; ++i) out[i] += blk[10 * b + i];
    }
    return to_numpy(std::move(out), {10});
}

// For triangles P (N, 3, 3) about p, each with weight w: the sums (10,) of tetra_add and the
// bounds (13,) of tetra_abs (|w| of each), in order.
nb::tuple piece_sums(In3x3<double> P, In1<double> p, double w) {
    check_length(p.shape(0), 3, "p");
    std::vector<double> sums(10, 0.0), bnd(13, 0.0);
    {
        nb::gil_scoped_release unlocked;
        for (size_t i = 0; i < P.shape(0); ++i) {
            double y[3][3];
            for (int k = 0; k < 3; ++k) sub(P.data() + 9 * i + 3 * k, p.data(), y[k]);
            tetra_add(sums.data(), w, y[0], y[1], y[2]);
            tetra_abs(bnd.data(), std::abs(w), y[0], y[1], y[2]);
        }
    }
    return nb::make_tuple(to_numpy(std::move(sums), {10}), to_numpy(std::move(bnd), {13}));
}

double cross2(const double* P, int64_t a, int64_t b, int64_t c) {
    return (P[2 * b] - P[2 * a]) * (P[2 * c + 1] - P[2 * a + 1]) -
           (P[2 * b + 1] - P[2 * a + 1]) * (P[2 * c] - P[2 * a]);
}

// Closed segments ab and cd share a point (within tiny of the cross products).
bool segments_meet(const double* P, int64_t a, int64_t b, int64_t c, int64_t d, double tiny) {
    const double d1 = cross2(P, a, b, c), d2 = cross2(P, a, b, d), d3 = cross2(P, c, d, a), d4 = cross2(P, c, d, b);
    if ((d1 > tiny && d2 > tiny) || (d1 < -tiny && d2 < -tiny) || (d3 > tiny && d4 > tiny) ||
        (d3 < -tiny && d4 < -tiny))
        return false;
    if (std::abs(d1) <= tiny && std::abs(d2) <= tiny)  // collinear: do the projections overlap?
        for (int k = 0; k < 2; ++k) {
            const double lo1 = std::min(P[2 * a + k], P[2 * b + k]), hi1 = std::max(P[2 * a + k], P[2 * b + k]);
            const double lo2 = std::min(P[2 * c + k], P[2 * d + k]), hi2 = std::max(P[2 * c + k], P[2 * d + k]);
            if (lo1 > hi2 || lo2 > hi1) return false;
        }
    return true;
}

// Ear clipping of the simple polygon P (n, 2): triangles (a, b, c) of vertex indices in P's
// order (n - 2, 3), or None when P is not simple (non-adjacent edges meet, or an edge turns
// back) or no ear is found.  O(n^2); an ear is a convex vertex whose closed triangle holds
// no other remaining vertex.
nb::object ear_clip(In2<double> polygon) {
    check_length(polygon.shape(1), 2, "polygon's rows");
    const int64_t n = int64_t(polygon.shape(0));
    if (n < 3) return nb::none();
    const double* P = polygon.data();
    std::vector<int64_t> out;
    {
        nb::gil_scoped_release unlocked;
        double scale = 0.0, area2 = 0.0;
        for (int64_t i = 0; i < n; ++i) {
            const int64_t j = (i + 1) % n;
            scale = std::max(scale, std::max(std::abs(P[2 * i]), std::abs(P[2 * i + 1])));
            area2 += P[2 * i] * P[2 * j + 1] - P[2 * j] * P[2 * i + 1];
        }
        const double sgn = area2 > 0.0 ? 1.0 : -1.0, tiny = 1e-14 * scale * scale;
        bool simple = area2 != 0.0;
        for (int64_t i = 0; i < n && simple; ++i) {  // no edge turns back
            const int64_t a = (i + n - 1) % n, c = (i + 1) % n;
            const double cr = (P[2 * i] - P[2 * a]) * (P[2 * c + 1] - P[2 * i + 1]) -
                              (P[2 * i + 1] - P[2 * a + 1]) * (P[2 * c] - P[2 * i]);
            const double dt = (P[2 * i] - P[2 * a]) * (P[2 * c] - P[2 * i]) +
                              (P[2 * i + 1] - P[2 * a + 1]) * (P[2 * c + 1] - P[2 * i + 1]);
            simple = !(std::abs(cr) <= tiny && dt < 0.0);
        }
        for (int64_t i = 0; i < n && simple; ++i)  // non-adjacent edges do not meet
            for (int64_t j = i + 2; j < n && simple; ++j)
                if (!(i == 0 && j == n - 1)) simple = !segments_meet(P, i, (i + 1) % n, j, (j + 1) % n, tiny);
        std::vector<int64_t> prv(n), nxt(n);
        for (int64_t i = 0; i < n; ++i) prv[i] = (i + n - 1) % n, nxt[i] = (i + 1) % n;
        auto is_ear = [&](int64_t a, int64_t b, int64_t c) {
            if (sgn * cross2(P, a, b, c) <= tiny) return false;
            for (int64_t q = nxt[c]; q != a; q = nxt[q])
                if (sgn * cross2(P, a, b, q) >= -tiny && sgn * cross2(P, b, c, q) >= -tiny &&
                    sgn * cross2(P, c, a, q) >= -tiny)
                    return false;
            return true;
        };
        int64_t left = n, b = 0, misses = 0;
        while (simple && left > 3) {
            const int64_t a = prv[b], c = nxt[b];
            if (is_ear(a, b, c)) {
                out.insert(out.end(), {a, b, c});
                nxt[a] = c;
                prv[c] = a;
                left--;
                misses = 0;
            } else if (++misses > left) {
                simple = false;
            }
            b = c;
        }
        if (!simple)
            out.clear();
        else
            out.insert(out.end(), {prv[b], b, nxt[b]});
    }
    if (out.empty()) return nb::none();
    const size_t nt = out.size() / 3;
    return nb::cast(to_numpy(std::move(out), {nt, 3}));
}

}  // namespace

void bind_topo(nb::module_& m) {
    m.def("dedupe_faces", &dedupe_faces, "Faces with equal corner sets merged: (faces (n, 3), multiplicities (n,)).");
    m.def("vertex_pass", &vertex_pass,
          "Certified vertices and the faces across manifold edges (in place); (edge kinds (3,), boundary edges "
          "(E, 2), their multiplicities (E,)).");
    m.def("patch_reps", &patch_reps, "Patches of uncut faces: (labels (F,), largest face of each patch (n,)).");
    m.def("weighted_sums", &weighted_sums, "Weighted signed-tetrahedron sums about p (10,), times 6, 24, 120.");
    m.def("piece_sums", &piece_sums,
          "Tetrahedron sums (10,) and absolute bounds (13,) of triangles P (N, 3, 3) about p, weight w.");
    m.def("ear_clip", &ear_clip, "Ear-clipping triangles (n - 2, 3) of a simple polygon, or None.");
}

}  // namespace inertia::robust

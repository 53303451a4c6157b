// Resolving the cut faces.  On a face f the winding just in front of f (w_front) is an integer,
// constant except across the traces other faces leave in f's plane:
//   type 1, a jump segment: a cutter g crossing the plane (or standing on it with an edge, in
//     front of f); w_front changes by J = -m_g sign(nl . n_g) across it towards nl = n_f x (P1 - P0);
//   type 2, coplanar: g in f's plane (all corners within eps of the plane of the better shaped
//     of the two, so that both decide alike) stacks on f; net multiplicity m_f + sum sigma_g m_g,
//     the part counted once, by its lowest face;
//   type 3, ambiguous: grazing the plane, or f of zero area: pieces touching it are not resolved;
//   type 0: no effect (a point contact, standing behind f, or of zero area).
// A piece (a triangle of f) is clipped by the lines of the traces reaching it into convex cells
// of constant w_front and stack; each cell's w_front comes from a walk from f's reference point
// summing the jumps crossed.  A borderline walk, a type-3 trace or too many lines: split again.
#include "robust/kernels.hpp"

namespace inertia::robust {
namespace {

constexpr int LMAX = 16;            // most lines a piece is clipped by (more: split it)
constexpr int CMAX = 160;           // most cells of a clipped piece
constexpr int PMAX = 3 + LMAX + 1;  // most vertices of a cell
constexpr int PSTRIDE = PMAX + 1;   // room for the vertex that overflows it
constexpr size_t BLOCK = 64;        // pieces summed in order per block, blocks in order

struct Traces {
    const int64_t *ptr, *idx, *type;
    const double *P, *J;
    const double* pt(int64_t k, int i) const { return P + 9 * k + 3 * i; }
};

Traces traces_of(const Mesh& m, const In1<int64_t>& cut_ptr, const In1<int64_t>& cut_idx, const In1<int64_t>& tr_type,
                 const In3x3<double>& tr_P, const In1<double>& tr_J) {
    const size_t K = cut_idx.shape(0);
    check_ptr(cut_ptr.data(), cut_ptr.shape(0), m.nf, K, "cut_ptr");
    check_range(cut_idx.data(), K, 0, int64_t(m.nf), "cut_idx");
    check_length(tr_type.shape(0), K, "tr_type");
    check_range(tr_type.data(), K, 0, 4, "tr_type");
    check_length(tr_P.shape(0), K, "tr_P");
    check_length(tr_J.shape(0), K, "tr_J");
    return {cut_ptr.data(), cut_idx.data(), tr_type.data(), tr_P.data(), tr_J.data()};
}

double unit_normal(const Mesh& m, int64_t f, double* n) {
    double u[3], v[3];
    sub(m.at(f, 1), m.at(f, 0), u);
    sub(m.at(f, 2), m.at(f, 0), v);
    cross(u, v, n);
    const double ln = norm(n);
    for (int c = 0; c < 3; ++c) n[c] = ln > 0.0 ? n[c] / ln : 0.0;
    return ln;
}

// Largest coordinate extent of face f from its first corner: the scale of its tolerances.
double face_size(const Mesh& m, int64_t f) {
    double size = 0.0;
    for (int c = 0; c < 3; ++c)
        size =
            std::max(size, std::max(std::abs(m.at(f, 1)[c] - m.at(f, 0)[c]), std::abs(m.at(f, 2)[c] - m.at(f, 0)[c])));
    return size;
}

double edge_squares(const Mesh& m, int64_t f) {
    double s = 0.0;
    for (int e = 0; e < 3; ++e)
        for (int c = 0; c < 3; ++c) {
            const double x = m.at(f, (e + 1) % 3)[c] - m.at(f, e)[c];
            s += x * x;
        }
    return s;
}

// Faces f and g lie in one plane: all six corners within eps of the plane of the better shaped
// of the two (largest |n| / sum of squared edges; ties: lower index).
bool coplanar(const Mesh& m, int64_t f, int64_t g, double lf, double lg, const double* nf, const double* ng,
              double eps) {
    const double qf = lf / edge_squares(m, f), qg = lg / edge_squares(m, g);
    const int64_t h = (qf > qg || (qf == qg && f < g)) ? f : g;
    const double* n = h == f ? nf : ng;
    for (int64_t o : {g, f})
        for (int i = 0; i < 3; ++i) {
            double q[3];
            sub(m.at(o, i), m.at(h, 0), q);
            if (std::abs(dot(n, q)) > eps) return false;
        }
    return true;
}

// The trace of cutter g = cut_idx[k] in the plane of face f (the module comment): type,
// points (type 1: the segment P0, P1; type 2: g's corners counter-clockwise about n_f), jump.
void classify_one(const Mesh& m, int64_t f, int64_t g, double eps, int64_t& type, double* P, double& J) {
    double nf[3], ng[3], dg[3];
    type = 0, J = 0.0;
    const double lf = unit_normal(m, f, nf), lg = unit_normal(m, g, ng);
    if (lg == 0.0) return;  // no area: crossing it changes no winding
    if (lf == 0.0) {
        type = 3;
        return;
    }
    int n_pos = 0, n_neg = 0;
    for (int i = 0; i < 3; ++i) {
        double q[3];
        sub(m.at(g, i), m.at(f, 0), q);
        dg[i] = dot(nf, q);
        n_pos += dg[i] > eps;
        n_neg += dg[i] < -eps;
    }
    if (coplanar(m, f, g, lf, lg, nf, ng, eps)) {
        type = 2;
        const double sig = dot(nf, ng) > 0.0 ? 1.0 : -1.0;
        for (int i = 0; i < 3; ++i) {
            const int src = sig > 0.0 ? i : 2 - i;
            for (int c = 0; c < 3; ++c) P[3 * i + c] = m.at(g, src)[c] - dg[src] * nf[c];
        }
        J = sig * m.M[g];
        return;
    }
    const int n_on = 3 - n_pos - n_neg;
    if (!((n_pos > 0 && n_neg > 0) || (n_on == 2 && n_pos == 1))) return;  // point contact, or behind f
    int n = 0;  // the segment: g's corners on the plane, crossings of g's edges with it
    for (int i = 0; i < 3; ++i)
        if (std::abs(dg[i]) <= eps && n < 2) {
            for (int c = 0; c < 3; ++c) P[3 * n + c] = m.at(g, i)[c] - dg[i] * nf[c];
            n++;
        }
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if (((dg[i] > eps && dg[j] < -eps) || (dg[i] < -eps && dg[j] > eps)) && n < 2) {
            const double s = dg[i] / (dg[i] - dg[j]);
            for (int c = 0; c < 3; ++c) P[3 * n + c] = m.at(g, i)[c] + s * (m.at(g, j)[c] - m.at(g, i)[c]);
            n++;
        }
    }
    if (n != 2) {
        type = 3;
        return;
    }
    double e[3], l[3];
    sub(P + 3, P, e);
    const double le = norm(e);
    if (le <= eps) return;  // a point: no line
    cross(nf, e, l);        // in-plane normal n_f x e; the jump when moving along it
    const double s = dot(l, ng) / le;
    if (std::abs(s) <= 1e-9) {
        type = 3;  // g grazes the plane along the segment
        return;
    }
    type = 1;
    J = s > 0.0 ? -m.M[g] : m.M[g];
}

// Unit in-plane normal of the line P0 -> P1 (n_f x e / |e|); returns |e| (0: a point).
double line_of(const double* P0, const double* P1, const double* nf, double* nl) {
    double e[3];
    sub(P1, P0, e);
    const double le = norm(e);
    if (!(le > 0.0)) {
        nl[0] = nl[1] = nl[2] = 0.0;
        return 0.0;
    }
    cross(nf, e, nl);
    for (int c = 0; c < 3; ++c) nl[c] /= le;
    return le;
}

double point_side(const double* nl, const double* A0, const double* x) {
    double q[3];
    sub(x, A0, q);
    return dot(nl, q);
}

// Where the segment A0 -> A1 (in f's plane) stands with respect to the triangle P: 0 its line
// misses P's interior (beyond tol), 1 it crosses P completely, 2 its line crosses P but the
// segment does not reach it, 3 otherwise (an end in or near P).  nl: the line's unit normal.
int segment_vs_piece(const double* P, const double* A0, const double* A1, const double* nf, double tol, double* nl) {
    const double le = line_of(A0, A1, nf, nl);
    if (le == 0.0) return 3;
    double u[3];
    for (int c = 0; c < 3; ++c) u[c] = (A1[c] - A0[c]) / le;
    bool pos = false, neg = false;
    double tmin = INF, tmax = -INF;
    for (int i = 0; i < 3; ++i) {
        const double d = point_side(nl, A0, P + 3 * i);
        if (d > tol)
            pos = true;
        else if (d < -tol)
            neg = true;
        else {
            const double t = point_side(u, A0, P + 3 * i);
            tmin = std::min(tmin, t), tmax = std::max(tmax, t);
        }
        const int j = (i + 1) % 3;
        const double dj = point_side(nl, A0, P + 3 * j);
        if ((d > tol && dj < -tol) || (d < -tol && dj > tol)) {
            const double s = d / (d - dj);
            double x[3];
            for (int c = 0; c < 3; ++c) x[c] = P[3 * i + c] + s * (P[3 * j + c] - P[3 * i + c]);
            const double t = point_side(u, A0, x);
            tmin = std::min(tmin, t), tmax = std::max(tmax, t);
        }
    }
    if (!(pos && neg)) return 0;  // misses P, or touches it at a corner or along an edge only
    if (tmax < -tol || tmin > le + tol) return 2;
    if (tmin > tol && tmax < le - tol) return 1;
    return 3;
}

// Sum of the jumps of f's type-1 traces crossed going from a to b (both in f); false when a
// crossing is within tol of an end of either segment.
bool walk(const Traces& tr, int64_t f, const double* a, const double* b, const double* nf, double tol, double& jump) {
    jump = 0.0;
    for (int64_t k = tr.ptr[f]; k < tr.ptr[f + 1]; ++k) {
        if (tr.type[k] != 1) continue;
        const double *P0 = tr.pt(k, 0), *P1 = tr.pt(k, 1);
        double nl[3], u[3];
        const double le = line_of(P0, P1, nf, nl);
        const double da = point_side(nl, P0, a), db = point_side(nl, P0, b);
        if ((da > tol && db > tol) || (da < -tol && db < -tol)) continue;
        for (int c = 0; c < 3; ++c) u[c] = (P1[c] - P0[c]) / le;
        if (std::abs(da) <= tol || std::abs(db) <= tol) {
            // an end of the walk on the trace's line: fine only if far from the segment
            const double ta = point_side(u, P0, a), tb = point_side(u, P0, b);
            if ((ta < -tol && tb < -tol) || (ta > le + tol && tb > le + tol)) continue;
            return false;
        }
        const double s = da / (da - db);
        double x[3];
        for (int c = 0; c < 3; ++c) x[c] = a[c] + s * (b[c] - a[c]);
        const double t = point_side(u, P0, x);
        if (t < -tol || t > le + tol) continue;
        if (t <= tol || t >= le - tol) return false;
        jump += db > 0.0 ? tr.J[k] : -tr.J[k];
    }
    return true;
}

// Net multiplicity of the coplanar stack at x on f; false when x is within tol of a coplanar
// cutter's edge.
bool stack_at(const Traces& tr, const Mesh& m, int64_t f, const double* x, const double* nf, double tol, double& net) {
    net = m.M[f];
    for (int64_t k = tr.ptr[f]; k < tr.ptr[f + 1]; ++k) {
        if (tr.type[k] != 2) continue;
        bool inside = true;
        for (int e = 0; e < 3; ++e) {
            double nl[3];
            const double le = line_of(tr.pt(k, e), tr.pt(k, (e + 1) % 3), nf, nl);
            const double d = point_side(nl, tr.pt(k, e), x);
            if (le == 0.0 || std::abs(d) <= tol) return false;
            if (d < 0.0) inside = false;
        }
        if (inside) net += tr.J[k];
    }
    return true;
}

// x lies within tol of the shadow, in f's plane, of a type-3 cutter.
bool near_type3(const Traces& tr, const Mesh& m, int64_t f, const double* x, const double* nf, double tol) {
    for (int64_t k = tr.ptr[f]; k < tr.ptr[f + 1]; ++k) {
        if (tr.type[k] != 3) continue;
        const int64_t g = tr.idx[k];
        bool s_pos = true, s_neg = true;  // inside all three edge lines, either orientation
        for (int e = 0; e < 3; ++e) {
            double nl[3];
            if (line_of(m.at(g, e), m.at(g, (e + 1) % 3), nf, nl) == 0.0) return true;
            const double d = point_side(nl, m.at(g, e), x);
            if (d < -tol) s_pos = false;
            if (d > tol) s_neg = false;
        }
        if (s_pos || s_neg) return true;
    }
    return false;
}

// x is farther than tol from every type-1 segment of f.
bool clear_of_traces(const Traces& tr, int64_t f, const double* x, double tol) {
    for (int64_t k = tr.ptr[f]; k < tr.ptr[f + 1]; ++k) {
        if (tr.type[k] != 1) continue;
        double e[3], q[3], d[3];
        sub(tr.pt(k, 1), tr.pt(k, 0), e);
        sub(x, tr.pt(k, 0), q);
        const double ee = dot(e, e);
        const double t = ee > 0.0 ? std::min(1.0, std::max(0.0, dot(q, e) / ee)) : 0.0;
        for (int c = 0; c < 3; ++c) d[c] = q[c] - t * e[c];
        if (dot(d, d) <= tol * tol) return false;
    }
    return true;
}

// A point of x's face f clear of its traces (its stack decided): the checks of reference_points.
bool clear_point(const Traces& tr, const Mesh& m, int64_t f, const double* x, const double* nf, double tol,
                 double& net) {
    return clear_of_traces(tr, f, x, tol) && !near_type3(tr, m, f, x, nf, tol) && stack_at(tr, m, f, x, nf, tol, net);
}

// ------------------------------------------------------------------------------- one piece
struct Scratch {
    double lines[LMAX][6];  // L0 (3), nl (3)
    std::vector<int64_t> side_fixed, line_of_;
    std::vector<char> flip;
    std::vector<double> cells = std::vector<double>(size_t(CMAX) * PSTRIDE * 3);
    int64_t ncv[CMAX], sides[CMAX];
    double cen[CMAX][3], w_cell[CMAX], areas[CMAX], neg[PSTRIDE][3], tmp_d[PSTRIDE];
    bool known[CMAX], live[CMAX];
    double* cell(int c, int i) { return &cells[(size_t(c) * PSTRIDE + i) * 3]; }
};

// Split every cell by the line (unit normal nl through L0); the + part gets `bit`.  Returns the
// number of cells, -1 when CMAX or PMAX would be exceeded.
int clip(Scratch& s, int n_cells, const double* nl, const double* L0, int64_t bit) {
    int n = n_cells;
    for (int c = 0; c < n_cells; ++c) {
        const int m = int(s.ncv[c]);
        bool has_pos = false, has_neg = false;
        for (int i = 0; i < m; ++i) {
            const double d = point_side(nl, L0, s.cell(c, i));
            s.tmp_d[i] = d;
            if (d > 0.0)
                has_pos = true;
            else if (d < 0.0)
                has_neg = true;
        }
        if (!(has_pos && has_neg)) {
            if (has_pos) s.sides[c] |= bit;
            continue;
        }
        if (n >= CMAX) return -1;
        int npos = 0, nneg = 0;  // the new cell n takes the + part, cell c keeps the - part
        for (int i = 0; i < m; ++i) {
            const int j = (i + 1) % m;
            const double di = s.tmp_d[i], dj = s.tmp_d[j];
            const double *ci = s.cell(c, i), *cj = s.cell(c, j);
            if (di >= 0.0) std::copy(ci, ci + 3, s.cell(n, npos++));
            if (di <= 0.0) std::copy(ci, ci + 3, s.neg[nneg++]);
            if ((di > 0.0 && dj < 0.0) || (di < 0.0 && dj > 0.0)) {
                const double t = di / (di - dj);
                double *x = s.cell(n, npos++), *y = s.neg[nneg++];
                for (int k = 0; k < 3; ++k) x[k] = y[k] = ci[k] + t * (cj[k] - ci[k]);
            }
            if (npos >= PMAX || nneg >= PMAX) return -1;
        }
        for (int i = 0; i < nneg; ++i) std::copy(s.neg[i], s.neg[i] + 3, s.cell(c, i));
        s.ncv[c] = nneg;
        s.ncv[n] = npos;
        s.sides[n] = s.sides[c] | bit;
        n++;
    }
    return n;
}

// Signed area (about nf) and centroid (into out) of the convex polygon cell c.
double cell_area_centroid(Scratch& s, int c, const double* nf, double* out) {
    double cen[3] = {0.0, 0.0, 0.0}, area = 0.0;
    const double* c0 = s.cell(c, 0);
    for (int i = 1; i + 1 < s.ncv[c]; ++i) {
        double u[3], v[3], w[3];
        sub(s.cell(c, i), c0, u);
        sub(s.cell(c, i + 1), c0, v);
        cross(u, v, w);
        const double a = 0.5 * dot(nf, w);
        area += a;
        for (int k = 0; k < 3; ++k) cen[k] += a * (c0[k] + s.cell(c, i)[k] + s.cell(c, i + 1)[k]) / 3.0;
    }
    if (area != 0.0)
        for (int k = 0; k < 3; ++k) out[k] = cen[k] / area;
    return area;
}

// acc (10,) += weight x the tetrahedron sums (apex p) of the fan of cell c; or with `bound`,
// out (13,) += their absolute bounds.
void add_cell(Scratch& s, int c, double weight, const double* p, double* acc, bool bound) {
    for (int i = 1; i + 1 < s.ncv[c]; ++i) {
        double y[3][3];
        sub(s.cell(c, 0), p, y[0]);
        sub(s.cell(c, i), p, y[1]);
        sub(s.cell(c, i + 1), p, y[2]);
        if (bound)
            tetra_abs(acc, 1.0, y[0], y[1], y[2]);
        else
            tetra_add(acc, weight, y[0], y[1], y[2]);
    }
}

// 1 + index of a line among lines[:nlines] equal to the line through x with unit normal nl
// (negative: opposite normal), 0 if none.
int same_line(const Scratch& s, int nlines, const double* nl, const double* x, double tol) {
    for (int li = 0; li < nlines; ++li) {
        const double c = dot(&s.lines[li][3], nl);
        if (std::abs(c) < 1.0 - 1e-12) continue;
        if (std::abs(point_side(&s.lines[li][3], s.lines[li], x)) <= tol) return c > 0.0 ? li + 1 : -(li + 1);
    }
    return 0;
}

// Does the piece come within tol of the shadow of face g in f's plane (no separating axis)?
bool piece_near_type3(const Mesh& m, int64_t g, const double* Pi, const double* nf, double tol) {
    for (int t = 0; t < 2; ++t)
        for (int e = 0; e < 3; ++e) {
            const double *a = t == 0 ? m.at(g, e) : Pi + 3 * e,
                         *b = t == 0 ? m.at(g, (e + 1) % 3) : Pi + 3 * ((e + 1) % 3);
            double nl[3];
            if (line_of(a, b, nf, nl) == 0.0) continue;
            double lo1 = INF, hi1 = -INF, lo2 = INF, hi2 = -INF;
            for (int q = 0; q < 3; ++q) {
                const double d1 = point_side(nl, a, m.at(g, q)), d2 = point_side(nl, a, Pi + 3 * q);
                lo1 = std::min(lo1, d1), hi1 = std::max(hi1, d1), lo2 = std::min(lo2, d2), hi2 = std::max(hi2, d2);
            }
            if (lo1 > hi2 + tol || lo2 > hi1 + tol) return false;
        }
    return true;
}

// One piece Pi of face f (reference point ref, its w_front w_ref): 0 resolved (its cells'
// boundary weights times their tetrahedron sums added to acc (10,), slivers left undecided
// bounded in bnd (13,), windings met in w_seen), 1 to split.  The piece is clipped by the full
// line of every trace reaching it; each cell's w_front comes from a walk from the reference
// point (or from a cell already known).
int resolve_one(Scratch& s, const Mesh& m, const Traces& tr, const double* Pi, int64_t f, const double* ref,
                double w_ref, const double* p, double rel_tol, double* acc, double* bnd, double* w_seen) {
    double nf[3], nl[3];
    unit_normal(m, f, nf);
    const double tol = rel_tol * face_size(m, f);
    const int64_t k0 = tr.ptr[f], n_tr = tr.ptr[f + 1] - k0;
    // 1. the lines reaching the piece
    int nlines = 0;
    s.side_fixed.assign(3 * n_tr, 0);  // a coplanar edge line missing the piece: its side +1 / -1
    s.line_of_.assign(3 * n_tr, -1);
    s.flip.assign(3 * n_tr, 0);
    for (int64_t k = k0; k < k0 + n_tr; ++k) {
        const int64_t t = tr.type[k];
        if (t == 0) continue;
        if (t == 3) {
            if (piece_near_type3(m, tr.idx[k], Pi, nf, tol)) return 1;
            continue;
        }
        for (int e = 0; e < (t == 1 ? 1 : 3); ++e) {
            const double *A = tr.pt(k, t == 2 ? e : 0), *B = tr.pt(k, t == 2 ? (e + 1) % 3 : 1);
            const int r = segment_vs_piece(Pi, A, B, nf, tol, nl);
            const size_t slot = size_t(3 * (k - k0) + e);
            if (t == 1 && (r == 0 || r == 2)) continue;  // the segment misses the piece
            if (t == 2 && r == 0) {
                double d = 0.0;
                for (int q = 0; q < 3; ++q) {
                    const double dq = point_side(nl, A, Pi + 3 * q);
                    if (std::abs(dq) > std::abs(d)) d = dq;
                }
                s.side_fixed[slot] = d > 0.0 ? 1 : -1;
                continue;
            }
            const int same = same_line(s, nlines, nl, A, tol);
            if (same != 0) {  // a line already there (a shared edge): the same bit, maybe reversed
                s.line_of_[slot] = std::abs(same) - 1;
                s.flip[slot] = same < 0;
                continue;
            }
            if (nlines >= LMAX) return 1;
            for (int c = 0; c < 3; ++c) s.lines[nlines][c] = A[c], s.lines[nlines][3 + c] = nl[c];
            s.line_of_[slot] = nlines++;
        }
    }
    // 2. cells
    for (int q = 0; q < 3; ++q) std::copy(Pi + 3 * q, Pi + 3 * q + 3, s.cell(0, q));
    s.ncv[0] = 3;
    s.sides[0] = 0;
    int n_cells = 1;
    for (int li = 0; li < nlines; ++li) {
        n_cells = clip(s, n_cells, &s.lines[li][3], s.lines[li], int64_t(1) << li);
        if (n_cells < 0) return 1;
    }
    // 3. each cell's w_front by a walk (from the reference point, else from a known cell)
    const double tiny = tol * tol;
    double piece_area = 0.0;
    for (int c = 0; c < n_cells; ++c) {
        s.areas[c] = cell_area_centroid(s, c, nf, s.cen[c]);
        s.live[c] = s.areas[c] > tiny;
        s.known[c] = false;
        piece_area += std::abs(s.areas[c]);
        if (!s.live[c] && s.ncv[c] >= 3) add_cell(s, c, 1.0, p, bnd, true);  // a crumb of the clipping: bounded
    }
    for (int c = 0; c < n_cells; ++c) {
        if (!s.live[c]) continue;
        // any point inside will do: the centroid, else points towards its corners (a symmetric
        // mesh may line the centroid up with a trace's end)
        for (int trial = 0; trial <= s.ncv[c]; ++trial) {
            double q[3], jmp;
            for (int k = 0; k < 3; ++k)
                q[k] = trial == 0 ? s.cen[c][k] : 0.7 * s.cen[c][k] + 0.3 * s.cell(c, trial - 1)[k];
            if (walk(tr, f, ref, q, nf, tol, jmp)) {
                s.w_cell[c] = w_ref + jmp;
                s.known[c] = true;
                break;
            }
        }
    }
    for (int c = 0; c < n_cells; ++c) {
        if (!s.live[c] || s.known[c]) continue;
        for (int d = 0; d < n_cells && !s.known[c]; ++d) {
            double jmp;
            if (s.known[d] && walk(tr, f, s.cen[d], s.cen[c], nf, tol, jmp)) {
                s.w_cell[c] = s.w_cell[d] + jmp;
                s.known[c] = true;
            }
        }
        if (!s.known[c]) {
            if (s.areas[c] > 1e-9 * piece_area) return 1;
            // a sliver along a trace: weight in [-1, 1], taken as 0, bounded by its whole sums
            add_cell(s, c, 1.0, p, bnd, true);
            s.live[c] = false;
        }
    }
    // 4. each cell's stack and weight
    for (int c = 0; c < n_cells; ++c) {
        if (!s.live[c]) continue;
        const double w = s.w_cell[c];
        double net = m.M[f];
        bool leader = true;
        for (int64_t k = k0; k < k0 + n_tr; ++k) {
            if (tr.type[k] != 2) continue;
            bool inside = true;
            for (int e = 0; e < 3; ++e) {
                const size_t slot = size_t(3 * (k - k0) + e);
                const int64_t li = s.line_of_[slot];
                inside = inside &&
                         (li >= 0 ? (((s.sides[c] >> li) & 1) == 1) != bool(s.flip[slot]) : s.side_fixed[slot] > 0);
            }
            if (inside) {
                net += tr.J[k];
                if (tr.idx[k] < f) leader = false;
            }
        }
        w_seen[0] = std::min(w_seen[0], w);
        w_seen[1] = std::max(w_seen[1], w + net);
        if (!leader) continue;
        const double weight = (w + net >= 1.0 ? 1.0 : 0.0) - (w >= 1.0 ? 1.0 : 0.0);
        if (weight != 0.0) add_cell(s, c, weight, p, acc, false);
    }
    return 0;
}

// ------------------------------------------------------------------------------- bindings
using Arr1 = nb::ndarray<nb::numpy, double, nb::ndim<1>>;

nb::tuple classify_traces(Vertices V, Faces F, In1<double> M, In1<int64_t> cut_ptr, In1<int64_t> cut_idx, double eps,
                          int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const size_t K = cut_idx.shape(0);
    check_ptr(cut_ptr.data(), cut_ptr.shape(0), m.nf, K, "cut_ptr");
    check_range(cut_idx.data(), K, 0, int64_t(m.nf), "cut_idx");
    std::vector<int64_t> type(K);
    std::vector<double> P(9 * K, 0.0), J(K);
    {
        nb::gil_scoped_release unlocked;
        const int64_t *ptr = cut_ptr.data(), *idx = cut_idx.data();
        parallel_for(m.nf, threads, 4096, [&](size_t f0, size_t f1) {
            for (size_t f = f0; f < f1; ++f)
                for (int64_t k = ptr[f]; k < ptr[f + 1]; ++k)
                    classify_one(m, int64_t(f), idx[k], eps, type[k], &P[9 * k], J[k]);
        });
    }
    return nb::make_tuple(to_numpy(std::move(type), {K}), to_numpy(std::move(P), {K, 3, 3}),
                          to_numpy(std::move(J), {K}));
}

// A point of each face of `faces` away (rel_tol x its size) from every trace: its centroid or
// another fixed barycentric point; (ref (n, 3), net multiplicity of the stack there, found).
nb::tuple reference_points(Vertices V, Faces F, In1<double> M, In1<int64_t> faces, In1<int64_t> cut_ptr,
                           In1<int64_t> cut_idx, In1<int64_t> tr_type, In3x3<double> tr_P, In1<double> tr_J,
                           double rel_tol, int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const Traces tr = traces_of(m, cut_ptr, cut_idx, tr_type, tr_P, tr_J);
    const size_t n = faces.shape(0);
    check_range(faces.data(), n, 0, int64_t(m.nf), "faces");
    std::vector<double> ref(3 * n, 0.0), net(n, 0.0);
    std::vector<char> ok(n, 0);
    {
        nb::gil_scoped_release unlocked;
        parallel_for(n, threads, 256, [&](size_t i0, size_t i1) {
            for (size_t i = i0; i < i1; ++i) {
                const int64_t f = faces.data()[i];
                double nf[3];
                unit_normal(m, f, nf);
                const double tol = rel_tol * face_size(m, f);
                for (int trial = 0; trial < 16 && !ok[i]; ++trial) {
                    // the centroid, then points of an additive recurrence (golden ratios): off the
                    // medians and any rational line a symmetric mesh may draw
                    double w0 = 1.0 / 3.0, w1 = 1.0 / 3.0;
                    if (trial > 0) {
                        double a = std::fmod(0.5 + trial * 0.6180339887498949, 1.0);
                        double b = std::fmod(0.5 + trial * 0.7548776662466927, 1.0);
                        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
                        w0 = 0.05 + 0.9 * a;
                        w1 = 0.05 + 0.9 * b * (1.0 - a);
                    }
                    const double w2 = 1.0 - w0 - w1;
                    double x[3];
                    for (int c = 0; c < 3; ++c) x[c] = w0 * m.at(f, 0)[c] + w1 * m.at(f, 1)[c] + w2 * m.at(f, 2)[c];
                    if (clear_point(tr, m, f, x, nf, tol, net[i])) {
                        std::copy(x, x + 3, &ref[3 * i]);
                        ok[i] = 1;
                    }
                }
                if (!ok[i]) net[i] = 0.0;
            }
        });
    }
    auto okv = new_vector<bool>(n);
    for (size_t i = 0; i < n; ++i) okv.data()[i] = ok[i];
    return nb::make_tuple(to_numpy(std::move(ref), {n, 3}), to_numpy(std::move(net), {n}), okv);
}

// Winding number at pts leaving out face owner[i] and its coplanar (type-2) cutters.
Arr1 winding_excluding(InN3<double> pts, In1<int64_t> owner, Vertices V, Faces F, In1<double> M, In1<int64_t> cut_ptr,
                       In1<int64_t> cut_idx, In1<int64_t> tr_type, int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const size_t K = cut_idx.shape(0), n = pts.shape(0);
    check_ptr(cut_ptr.data(), cut_ptr.shape(0), m.nf, K, "cut_ptr");
    check_range(cut_idx.data(), K, 0, int64_t(m.nf), "cut_idx");
    check_length(tr_type.shape(0), K, "tr_type");
    check_length(owner.shape(0), n, "owner");
    check_range(owner.data(), n, 0, int64_t(m.nf), "owner");
    std::vector<double> out(n);
    {
        nb::gil_scoped_release unlocked;
        const int64_t *ptr = cut_ptr.data(), *idx = cut_idx.data(), *type = tr_type.data();
        parallel_for(n, threads, 1 + 100000 / (m.nf + 1), [&](size_t i0, size_t i1) {
            for (size_t i = i0; i < i1; ++i) {
                const V3 x = row(pts.data(), int64_t(i));
                const int64_t o = owner.data()[i];
                double s = 0.0;
                for (size_t f = 0; f < m.nf; ++f)
                    if (int64_t(f) != o) s += m.M[f] * solid_angle(m, int64_t(f), x);
                for (int64_t k = ptr[o]; k < ptr[o + 1]; ++k)
                    if (type[k] == 2) s -= m.M[idx[k]] * solid_angle(m, idx[k], x);
                out[i] = s / FOUR_PI;
            }
        });
    }
    return to_numpy(std::move(out), {n});
}

// Jumps of w_front from face a's point to face b's point across their common edge (a, b, u, v)
// = pairs[i]: a's point -> edge midpoint on a, midpoint -> b's point on b.  face_slot[f] indexes
// ref (-1: the centroid, for an uncut face).  Not ok when a walk is borderline or the midpoint
// is near a trace of either face, or a coplanar stack covers it, unless a and b lie in one
// plane with stacks of equal net multiplicity there.
nb::tuple walk_pairs(Vertices V, Faces F, In1<double> M, InN4<int64_t> pairs, InN3<double> ref, In1<int64_t> face_slot,
                     In1<int64_t> cut_ptr, In1<int64_t> cut_idx, In1<int64_t> tr_type, In3x3<double> tr_P,
                     In1<double> tr_J, double rel_tol, int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const Traces tr = traces_of(m, cut_ptr, cut_idx, tr_type, tr_P, tr_J);
    const size_t n = pairs.shape(0);
    check_length(face_slot.shape(0), m.nf, "face_slot");
    check_range(face_slot.data(), m.nf, -1, int64_t(ref.shape(0)), "face_slot");
    for (size_t i = 0; i < n; ++i) {
        check_range(pairs.data() + 4 * i, 2, 0, int64_t(m.nf), "pairs (faces)");
        check_range(pairs.data() + 4 * i + 2, 2, 0, int64_t(m.nv), "pairs (vertices)");
    }
    std::vector<double> jump(n, 0.0);
    std::vector<char> ok(n, 0);
    {
        nb::gil_scoped_release unlocked;
        parallel_for(n, threads, 256, [&](size_t i0, size_t i1) {
            for (size_t i = i0; i < i1; ++i) {
                const int64_t* pr = pairs.data() + 4 * i;
                double mid[3], na[3] = {0.0, 0.0, 0.0}, total = 0.0, extra_a = 0.0;
                for (int c = 0; c < 3; ++c) mid[c] = 0.5 * (m.V[3 * pr[2] + c] + m.V[3 * pr[3] + c]);
                bool good = true;
                for (int leg = 0; leg < 2 && good; ++leg) {
                    const int64_t f = pr[leg], s = face_slot.data()[f];
                    double nf[3], x[3], net, j;
                    unit_normal(m, f, nf);
                    const double tol = rel_tol * face_size(m, f);
                    for (int c = 0; c < 3; ++c)
                        x[c] = s >= 0 ? ref.data()[3 * s + c] : (m.at(f, 0)[c] + m.at(f, 1)[c] + m.at(f, 2)[c]) / 3.0;
                    good = clear_point(tr, m, f, mid, nf, tol, net);
                    if (good && leg == 0) {
                        extra_a = net - m.M[f];
                        std::copy(nf, nf + 3, na);
                    } else if (good && (extra_a != 0.0 || net != m.M[f])) {
                        good = dot(nf, na) > 1.0 - 1e-12 && net - m.M[f] == extra_a;
                    }
                    good = good && (leg == 0 ? walk(tr, f, x, mid, nf, tol, j) : walk(tr, f, mid, x, nf, tol, j));
                    if (good) total += j;
                }
                ok[i] = good;
                jump[i] = total;
            }
        });
    }
    auto okv = new_vector<bool>(n);
    for (size_t i = 0; i < n; ++i) okv.data()[i] = ok[i];
    return nb::make_tuple(to_numpy(std::move(jump), {n}), okv);
}

// Resolve pieces P (N, 3, 3) of faces owner (slot: their row of ref / w_ref) about p:
// (status (N,): 0 resolved, 1 to split; the resolved pieces' sums (10,) and sliver bounds (13,),
// summed in order by blocks of 64; the least front and the largest back winding they met).
nb::tuple resolve_pieces(In3x3<double> P, In1<int64_t> owner, In1<int64_t> slot, InN3<double> ref, In1<double> w_ref,
                         Vertices V, Faces F, In1<double> M, In1<int64_t> cut_ptr, In1<int64_t> cut_idx,
                         In1<int64_t> tr_type, In3x3<double> tr_P, In1<double> tr_J, In1<double> p, double rel_tol,
                         int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const Traces tr = traces_of(m, cut_ptr, cut_idx, tr_type, tr_P, tr_J);
    const size_t n = P.shape(0), S = ref.shape(0);
    check_length(owner.shape(0), n, "owner");
    check_range(owner.data(), n, 0, int64_t(m.nf), "owner");
    check_length(slot.shape(0), n, "slot");
    check_range(slot.data(), n, 0, int64_t(S), "slot");
    check_length(w_ref.shape(0), S, "w_ref");
    check_length(p.shape(0), 3, "p");
    std::vector<int64_t> status(n);
    std::vector<double> acc(10, 0.0), bnd(13, 0.0);
    double w_lo = INF, w_hi = -INF;
    {
        nb::gil_scoped_release unlocked;
        const size_t n_blocks = (n + BLOCK - 1) / BLOCK;
        std::vector<double> blk(25 * n_blocks, 0.0);  // per block: acc (10), bnd (13), w_lo, w_hi
        parallel_for(n_blocks, threads, 2, [&](size_t b0, size_t b1) {
            auto s = std::make_unique<Scratch>();
            for (size_t b = b0; b < b1; ++b) {
                double* out = &blk[25 * b];
                out[23] = INF, out[24] = -INF;
                for (size_t i = BLOCK * b; i < std::min(n, BLOCK * b + BLOCK); ++i) {
                    double a[10] = {}, d[13] = {}, w_seen[2] = {INF, -INF};
                    const int64_t r = slot.data()[i];
                    status[i] = resolve_one(*s, m, tr, P.data() + 9 * i, owner.data()[i], ref.data() + 3 * r,
                                            w_ref.data()[r], p.data(), rel_tol, a, d, w_seen);
                    if (status[i] != 0) continue;
                    for (int k = 0; k < 10; ++k) out[k] += a[k];
                    for (int k = 0; k < 13; ++k) out[10 + k] += d[k];
                    out[23] = std::min(out[23], w_seen[0]), out[24] = std::max(out[24], w_seen[1]);
                }
            }
        });
        for (size_t b = 0; b < n_blocks; ++b) {
            for (int k = 0; k < 10; ++k) acc[k] += blk[25 * b + k];
            for (int k = 0; k < 13; ++k) bnd[k] += blk[25 * b + 10 + k];
            w_lo = std::min(w_lo, blk[25 * b + 23]), w_hi = std::max(w_hi, blk[25 * b + 24]);
        }
    }
    return nb::make_tuple(to_numpy(std::move(status), {n}), to_numpy(std::move(acc), {10}),
                          to_numpy(std::move(bnd), {13}), w_lo, w_hi);
}

}  // namespace

void bind_clip(nb::module_& m) {
    m.def("classify_traces", &classify_traces,
          "Trace of each cutter in its face's plane: (type (K,), points (K, 3, 3), jump (K,)).");
    m.def("reference_points", &reference_points,
          "A point of each face clear of its traces: (ref (n, 3), net multiplicity (n,), found (n,)).");
    m.def("winding_excluding", &winding_excluding,
          "Winding numbers at pts without face owner[i] and its coplanar cutters.");
    m.def("walk_pairs", &walk_pairs, "Front-winding jumps across manifold edges: (jump (n,), ok (n,)).");
    m.def("resolve_pieces", &resolve_pieces,
          "Resolve pieces: (status (N,), sums (10,), sliver bounds (13,), least front, largest back winding).");
}

}  // namespace inertia::robust

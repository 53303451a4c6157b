// Which faces of the chain may cut each other: conservative triangle-triangle tests with shared
// corners and edges handled exactly, behind a uniform-grid broad phase; and the winding number
// of the rest of the chain at points on its faces.
#include "robust/kernels.hpp"

namespace inertia::robust {
namespace {

//: Contacts at angles below this (radians) from a triangle's edge count as along the edge.
constexpr double ANGLE_TOL = 1e-12;

using Tri = double[3][3];

// A face's corner ids, corners and (unnormalised) normal (A1 - A0) x (A2 - A0) with its length.
struct FaceGeom {
    int64_t id[3];
    double n[3], ln;
    Tri T;
};

FaceGeom face_geom(const Mesh& m, int64_t f) {
    FaceGeom a;
    m.load(f, a.T);
    for (int c = 0; c < 3; ++c) a.id[c] = m.F[3 * f + c];
    double u[3], v[3];
    sub(a.T[1], a.T[0], u);
    sub(a.T[2], a.T[0], v);
    cross(u, v, a.n);
    a.ln = norm(a.n);
    return a;
}

// Signed distances (times |n_A|) of B's corners to A's plane.
void plane_dist(const FaceGeom& a, const Tri& B, double* d) {
    double q[3];
    for (int k = 0; k < 3; ++k) sub(B[k], a.T[0], q), d[k] = dot(a.n, q);
}

bool one_side(const double* d, double tol) {
    return (d[0] > tol && d[1] > tol && d[2] > tol) || (d[0] < -tol && d[1] < -tol && d[2] < -tol);
}

// 2-D separating-axis test of two coplanar triangles (axes: in-plane edge normals, n A's normal).
bool coplanar_overlap(const Tri& A, const Tri& B, const double* n, double eps) {
    for (int t = 0; t < 2; ++t) {
        const Tri& T = t == 0 ? A : B;
        for (int e = 0; e < 3; ++e) {
            double d[3], ax[3];
            sub(T[(e + 1) % 3], T[e], d);
            cross(n, d, ax);
            const double la = norm(ax);
            if (la == 0.0) continue;
            double lo1 = dot(A[0], ax), hi1 = lo1, lo2 = dot(B[0], ax), hi2 = lo2;
            for (int k = 1; k < 3; ++k) {
                const double q1 = dot(A[k], ax), q2 = dot(B[k], ax);
                lo1 = std::min(lo1, q1), hi1 = std::max(hi1, q1), lo2 = std::min(lo2, q2), hi2 = std::max(hi2, q2);
            }
            const double tol = eps * la;
            if (lo1 > hi2 + tol || lo2 > hi1 + tol) return false;
        }
    }
    return true;
}

// Interval of T (meeting the other plane, distances d) along the direction D.
void line_interval(const Tri& T, const double* d, double tol, const double* D, double& lo, double& hi) {
    lo = INF, hi = -INF;
    for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) <= tol) {
            const double q = dot(T[k], D);
            lo = std::min(lo, q), hi = std::max(hi, q);
        }
        const int j = (k + 1) % 3;
        if ((d[k] > tol && d[j] < -tol) || (d[k] < -tol && d[j] > tol)) {
            const double s = d[k] / (d[k] - d[j]);
            double x[3];
            for (int c = 0; c < 3; ++c) x[c] = T[k][c] + s * (T[j][c] - T[k][c]);
            const double q = dot(x, D);
            lo = std::min(lo, q), hi = std::max(hi, q);
        }
    }
}

// May triangles a and b share a point (closed sets, within eps)?  Separating planes first
// (Moeller 1997), coplanar pairs by separating axes, else the intervals both cut from the
// line of the two planes overlap.
bool tris_cut(const FaceGeom& a, const FaceGeom& b, double eps) {
    double dB[3], dA[3];
    plane_dist(a, b.T, dB);
    const double tolA = eps * a.ln;
    if (one_side(dB, tolA)) return false;
    plane_dist(b, a.T, dA);
    const double tolB = eps * b.ln;
    if (one_side(dA, tolB)) return false;
    if (a.ln == 0.0 || b.ln == 0.0) return true;  // degenerate triangle touching the other's plane
    if (std::abs(dB[0]) <= tolA && std::abs(dB[1]) <= tolA && std::abs(dB[2]) <= tolA)
        return coplanar_overlap(a.T, b.T, a.n, eps);
    double D[3];  // direction of the planes' line (unnormalised; intervals scale alike)
    cross(a.n, b.n, D);
    const double lD = norm(D);
    if (lD == 0.0) return true;
    double a0, a1, b0, b1;
    line_interval(a.T, dA, tolB, D, a0, a1);
    line_interval(b.T, dB, tolA, D, b0, b1);
    const double tol = 2.0 * eps * lD;
    return a0 <= b1 + tol && b0 <= a1 + tol;
}
// Direction d in T's sector at corner s (normal n): in the closed sector, strictly inside
// (angles below ANGLE_TOL count as on the sector's edge).
void sector_flags(const Tri& T, int s, const double* d, const double* n, bool& closed, bool& strict) {
    double e1[3], e2[3], c[3];
    sub(T[(s + 1) % 3], T[s], e1);
    sub(T[(s + 2) % 3], T[s], e2);
    cross(e1, d, c);
    const double c1 = dot(c, n);
    cross(d, e2, c);
    const double c2 = dot(c, n);
    const double ln = norm(n), ld = norm(d);
    const double t1 = ANGLE_TOL * ln * ld * norm(e1), t2 = ANGLE_TOL * ln * ld * norm(e2);
    closed = c1 >= -t1 && c2 >= -t2;
    strict = c1 > t1 && c2 > t2;
}

// Direction d strictly (beyond ANGLE_TOL) inside T's sector at corner s (n: the common plane's normal).
bool strictly_inside(const Tri& T, int s, const double* d, const double* n) {
    double e1[3], e2[3], c[3];
    sub(T[(s + 1) % 3], T[s], e1);
    sub(T[(s + 2) % 3], T[s], e2);
    cross(e1, e2, c);
    const double o = dot(c, n);  // orientation of the sector relative to n
    cross(e1, d, c);
    double c1 = dot(c, n);
    cross(d, e2, c);
    double c2 = dot(c, n);
    const double ln = norm(n), ld = norm(d), l1 = norm(e1), l2 = norm(e2);
    if (o < 0.0) c1 = -c1, c2 = -c2;
    return c1 > ANGLE_TOL * ln * ld * l1 && c2 > ANGLE_TOL * ln * ld * l2;
}

// Coplanar triangles sharing corner v: their sectors at v overlap (beyond ANGLE_TOL) iff an
// edge direction or the bisector of one lies strictly inside the other.
bool sectors_overlap(const Tri& A, int sa, const Tri& B, int sb, const double* n) {
    for (int t = 0; t < 2; ++t) {
        const Tri &T = t == 0 ? A : B, &U = t == 0 ? B : A;
        const int s = t == 0 ? sa : sb, su = t == 0 ? sb : sa;
        for (int k = 0; k < 3; ++k) {
            double d[3];
            for (int c = 0; c < 3; ++c)
                d[c] = k < 2 ? U[(su + 1 + k) % 3][c] - U[su][c]
                             : 0.5 * (U[(su + 1) % 3][c] + U[(su + 2) % 3][c]) - U[su][c];
            if (strictly_inside(T, s, d, n)) return true;
        }
    }
    return false;
}

// In-plane side of point q relative to the edge from A[i0] along e (sign of a dot with A's normal).
double side(const Tri& A, const double* n, int i0, const double* e, const double* q) {
    double r[3], c[3];
    sub(q, A[i0], r);
    cross(e, r, c);
    return dot(c, n);
}

// Does face g cut the interior of face f (or vice versa)?  3 shared corners: yes; a shared
// edge: only a fold (coplanar, opposite corners on the same side); a shared corner: the
// planes' line through it meets both triangles in segments pointing the same way; no shared
// corner: tris_cut.
bool faces_cut(const FaceGeom& a, const FaceGeom& b, double eps) {
    const Tri &A = a.T, &B = b.T;
    int ns = 0, sa = -1, sb = -1, sum_a = 0, sum_b = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a.id[i] == b.id[j]) ns++, sa = i, sb = j, sum_a += i, sum_b += j;
    if (ns == 0) return tris_cut(a, b, eps);
    if (ns == 3) return true;
    double dB[3], dA[3];
    plane_dist(a, B, dB);
    plane_dist(b, A, dA);
    if (a.ln == 0.0 || b.ln == 0.0) return true;
    const double tolA = eps * a.ln, tolB = eps * b.ln;
    if (ns == 2) {
        const int oa = 3 - sum_a, ob = 3 - sum_b;   // corners off the shared edge
        if (std::abs(dB[ob]) > tolA) return false;  // not coplanar: they meet along the edge only
        // coplanar: a fold when the opposite corners are on the same side of the edge
        const int i0 = (oa + 1) % 3, i1 = (oa + 2) % 3;
        double e[3];
        sub(A[i1], A[i0], e);
        return side(A, a.n, i0, e, A[oa]) * side(A, a.n, i0, e, B[ob]) >= 0.0;
    }
    dB[sb] = 0.0, dA[sa] = 0.0;  // one shared corner: sa in A, sb in B
    const int b1 = (sb + 1) % 3, b2 = (sb + 2) % 3, a1 = (sa + 1) % 3, a2 = (sa + 2) % 3;
    if ((dB[b1] > tolA && dB[b2] > tolA) || (dB[b1] < -tolA && dB[b2] < -tolA)) return false;
    if ((dA[a1] > tolB && dA[a2] > tolB) || (dA[a1] < -tolB && dA[a2] < -tolB)) return false;
    if (std::abs(dB[b1]) <= tolA && std::abs(dB[b2]) <= tolA) return sectors_overlap(A, sa, B, sb, a.n);
    // the planes' line through v meets each triangle in a segment from v along +-D (or only
    // in v): they cut iff some direction lies in both closed sectors and strictly inside one
    double u[3], w[3], na[3], nb[3], D[3];
    sub(A[a1], A[sa], u), sub(A[a2], A[sa], w), cross(u, w, na);
    sub(B[b1], B[sb], u), sub(B[b2], B[sb], w), cross(u, w, nb);
    cross(na, nb, D);
    if (D[0] == 0.0 && D[1] == 0.0 && D[2] == 0.0) return true;
    for (double sgn : {-1.0, 1.0}) {
        const double d[3] = {sgn * D[0], sgn * D[1], sgn * D[2]};
        bool ca, sa_, cb, sb_;
        sector_flags(A, sa, d, na, ca, sa_);
        sector_flags(B, sb, d, nb, cb, sb_);
        if (ca && cb && (sa_ || sb_)) return true;
    }
    return false;
}

inline uint64_t cell_hash(int64_t i, int64_t j, int64_t k) {
    return (uint64_t(i) * 73856093u) ^ (uint64_t(j) * 19349663u) ^ (uint64_t(k) * 83492791u);
}

// One uniform grid of cubes of side `cell`, bucketed by a counting sort of hashed cell keys.
// Mode 0 registers the faces with small[f] and reports pairs among them; mode 1 registers
// every face and reports the pairs with a face not small.  A pair is examined in the bucket of
// the cell holding the low corner of the intersection of the two boxes only.  An entry keeps a
// copy of its face's corners, low cell and box (float32, relative to the origin, widened so
// that it holds the box), so that a bucket is read in sequence.
struct Entry {
    float box[6];
    int32_t corner[3], face, low[3];
};

struct Grid {
    const Mesh& m;
    const double* box;  // (F, 6): lo, hi
    const bool *small, *cert;
    int mode;
    double eps;
    size_t T = 16;
    std::vector<int32_t> ilo, ihi;
    std::vector<int64_t> start;
    std::vector<Entry> entry;

    Grid(const Mesh& m_, const double* box_, const bool* small_, const bool* cert_, int mode_, const double* origin,
         double cell, double eps_)
        : m(m_), box(box_), small(small_), cert(cert_), mode(mode_), eps(eps_), ilo(3 * m.nf), ihi(3 * m.nf) {
        size_t n_entries = 0;
        for (size_t f = 0; f < m.nf; ++f) {
            if (mode == 0 && !small[f]) continue;
            size_t span = 1;
            for (int c = 0; c < 3; ++c) {
                ilo[3 * f + c] = int32_t(std::floor((box[6 * f + c] - eps - origin[c]) / cell));
                ihi[3 * f + c] = int32_t(std::floor((box[6 * f + 3 + c] + eps - origin[c]) / cell));
                span *= size_t(ihi[3 * f + c] - ilo[3 * f + c] + 1);
            }
            n_entries += span;
        }
        while (T < n_entries) T *= 2;
        const uint64_t mask = T - 1;
        start.assign(T + 1, 0);
        auto cells = [&](size_t f, auto&& visit) {
            for (int64_t i = ilo[3 * f]; i <= ihi[3 * f]; ++i)
                for (int64_t j = ilo[3 * f + 1]; j <= ihi[3 * f + 1]; ++j)
                    for (int64_t k = ilo[3 * f + 2]; k <= ihi[3 * f + 2]; ++k) visit(cell_hash(i, j, k) & mask);
        };
        for (size_t f = 0; f < m.nf; ++f)
            if (mode == 1 || small[f]) cells(f, [&](uint64_t b) { start[b + 1]++; });
        for (size_t b = 0; b < T; ++b) start[b + 1] += start[b];
        std::vector<int64_t> fill(start.begin(), start.end() - 1);
        entry.resize(n_entries);
        const float grow = 2.4e-7f;  // float32 rounds to nearest: widen so the copy holds the box
        for (size_t f = 0; f < m.nf; ++f) {
            if (mode == 0 && !small[f]) continue;
            Entry e;
            for (int c = 0; c < 3; ++c) {
                e.box[c] = float(box[6 * f + c] - eps - origin[c]);
                e.box[3 + c] = float(box[6 * f + 3 + c] + eps - origin[c]);
                e.box[c] -= std::abs(e.box[c]) * grow, e.box[3 + c] += std::abs(e.box[3 + c]) * grow;
                e.corner[c] = int32_t(m.F[3 * f + c]), e.low[c] = ilo[3 * f + c];
            }
            e.face = int32_t(f);
            cells(f, [&](uint64_t b) { entry[fill[b]++] = e; });
        }
    }

    bool boxes_apart(int64_t f, int64_t g) const {
        for (int c = 0; c < 3; ++c)
            if (box[6 * g + c] > box[6 * f + 3 + c] + eps || box[6 * f + c] > box[6 * g + 3 + c] + eps) return true;
        return false;
    }

    // Cutting pairs (f < g) found in buckets b0..b1-1.  The box test and the certified-corner
    // test are branch-free; their survivors go on to the low-corner bucket, then faces_cut.
    void scan(size_t b0, size_t b1, std::vector<int64_t>& hits, std::vector<std::pair<int64_t, int64_t>>& out) const {
        const uint64_t mask = T - 1;
        for (size_t b = b0; b < b1; ++b) {
            const int64_t e1 = start[b + 1];
            for (int64_t ea = start[b]; ea < e1; ++ea) {
                const Entry& a = entry[ea];
                const int64_t f = a.face;
                if (mode == 1 && small[f]) continue;  // mode 1: pairs with a big face, scanned from that face
                const float* bf = a.box;
                const int32_t c0 = a.corner[0], c1 = a.corner[1], c2 = a.corner[2];
                const bool k0 = cert[c0], k1 = cert[c1], k2 = cert[c2];
                size_t nh = 0;
                for (int64_t eb = mode == 1 ? start[b] : ea + 1; eb < e1; ++eb) {
                    const float* bg = entry[eb].box;
                    const int32_t g0 = entry[eb].corner[0], g1 = entry[eb].corner[1], g2 = entry[eb].corner[2];
                    hits[nh] = eb;
                    nh += (bg[0] <= bf[3]) & (bg[3] >= bf[0]) & (bg[1] <= bf[4]) & (bg[4] >= bf[1]) & (bg[2] <= bf[5]) &
                          (bg[5] >= bf[2]) &
                          !((k0 & ((c0 == g0) | (c0 == g1) | (c0 == g2))) |
                            (k1 & ((c1 == g0) | (c1 == g1) | (c1 == g2))) |
                            (k2 & ((c2 == g0) | (c2 == g1) | (c2 == g2))));
                }
                for (size_t h = 0; h < nh; ++h) {
                    const Entry& e = entry[hits[h]];
                    const int64_t g = e.face;
                    if (g == f || (mode == 1 && !small[g] && g < f)) continue;
                    const int64_t i = std::max(a.low[0], e.low[0]), j = std::max(a.low[1], e.low[1]),
                                  k = std::max(a.low[2], e.low[2]);
                    if ((cell_hash(i, j, k) & mask) != b) continue;
                    if (boxes_apart(f, g) || !faces_cut(face_geom(m, f), face_geom(m, g), eps)) continue;
                    out.emplace_back(std::min(f, g), std::max(f, g));
                }
            }
        }
    }
};

// The faces each face may cut, as CSR (cut_ptr (F + 1,), cut_idx), each list increasing and
// each pair in both lists.  Two grids: a fine one (cell twice the median face box) for the
// faces spanning at most 4 cells per axis, a coarse one for the pairs with the rest.  Faces
// sharing a certified vertex (vertex_pass) cannot cut each other and are not tested.
nb::tuple cut_lists(Vertices V, Faces F, In1<bool> cert, double eps, int threads) {
    const Mesh m = mesh_of(V, F);
    check_length(cert.shape(0), m.nv, "cert");
    if (!(eps >= 0.0)) input_error("eps must be a non-negative length");
    const size_t nf = m.nf;
    if (nf >= size_t(INT32_MAX) || m.nv >= size_t(INT32_MAX))
        input_error("cut_lists takes fewer than 2^31 faces and vertices");
    std::vector<int64_t> ptr(nf + 1, 0), idx;
    {
        nb::gil_scoped_release unlocked;
        std::vector<double> box(6 * nf), ext(nf);  // per face: lo, hi
        double origin[3] = {INF, INF, INF}, top[3] = {-INF, -INF, -INF};
        for (size_t f = 0; f < nf; ++f) {
            double *lo = &box[6 * f], *hi = lo + 3;
            for (int c = 0; c < 3; ++c) {
                const double a = m.at(f, 0)[c], b = m.at(f, 1)[c], d = m.at(f, 2)[c];
                lo[c] = std::min(a, std::min(b, d)), hi[c] = std::max(a, std::max(b, d));
                if (!std::isfinite(lo[c]) || !std::isfinite(hi[c]))
                    input_error("face " + std::to_string(f) + " has a corner that is not finite");
                origin[c] = std::min(origin[c], lo[c]), top[c] = std::max(top[c], hi[c]);
            }
            ext[f] = std::max(std::max(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
        }
        double span_all = 0.0;
        for (int c = 0; c < 3; ++c) span_all = std::max(span_all, top[c] - origin[c]);
        if (span_all == 0.0 || nf == 0) span_all = 1.0;
        if (eps > span_all) input_error("eps exceeds the extent of the faces (the grid's cells would not fit)");
        std::vector<double> sorted(ext);  // the median, as NumPy takes it (mean of the middle two)
        double median = 0.0;
        if (nf) {
            const size_t h = nf / 2;
            std::nth_element(sorted.begin(), sorted.begin() + h, sorted.end());
            median = sorted[h];
            if (nf % 2 == 0) median = (*std::max_element(sorted.begin(), sorted.begin() + h) + median) / 2.0;
        }
        const double cell = std::max(std::max(2.0 * median, span_all / 1e6), 1e-300);
        for (double& o : origin) o -= 2.0 * eps;
        std::vector<char> small_c(nf);
        double big = -INF;
        for (size_t f = 0; f < nf; ++f) {
            small_c[f] = ext[f] <= 4.0 * cell;
            if (!small_c[f]) big = std::max(big, ext[f]);
        }
        const bool* small = reinterpret_cast<const bool*>(small_c.data());
        std::vector<std::pair<int64_t, int64_t>> pairs;
        for (int mode = 0; mode < (big > -INF ? 2 : 1); ++mode) {
            const Grid grid(m, box.data(), small, cert.data(), mode, origin,
                            mode == 0 ? cell : std::max(big / 4.0, span_all / 1e6), eps);
            int64_t kmax = 1;
            for (size_t b = 0; b < grid.T; ++b) kmax = std::max(kmax, grid.start[b + 1] - grid.start[b]);
            const size_t n_chunks = 64;
            std::vector<std::vector<std::pair<int64_t, int64_t>>> found(n_chunks);
            // threads for a large grid only (a chunk of a small one costs less than starting one)
            parallel_for(n_chunks, grid.entry.size() < 65536 ? 1 : threads, 8, [&](size_t c0, size_t c1) {
                std::vector<int64_t> hits(size_t(kmax) + 1);
                for (size_t ch = c0; ch < c1; ++ch)
                    grid.scan(grid.T * ch / n_chunks, grid.T * (ch + 1) / n_chunks, hits, found[ch]);
            });
            for (auto& v : found) pairs.insert(pairs.end(), v.begin(), v.end());
        }
        std::sort(pairs.begin(), pairs.end());
        pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
        for (auto [f, g] : pairs) ptr[f + 1]++, ptr[g + 1]++;
        for (size_t f = 0; f < nf; ++f) ptr[f + 1] += ptr[f];
        idx.resize(size_t(ptr[nf]));
        std::vector<int64_t> fill(ptr.begin(), ptr.end() - 1);
        for (auto [f, g] : pairs) idx[fill[f]++] = g, idx[fill[g]++] = f;
        for (size_t f = 0; f < nf; ++f) std::sort(idx.begin() + ptr[f], idx.begin() + ptr[f + 1]);
    }
    const size_t n = idx.size();
    return nb::make_tuple(to_numpy(std::move(ptr), {nf + 1}), to_numpy(std::move(idx), {n}));
}

// Generalised winding number at pts (P, 3), leaving out face owner[i] for point i:
// w(p) = sum_f M_f Omega_f(p) / 4 pi.
nb::ndarray<nb::numpy, double, nb::ndim<1>> winding_rest(InN3<double> pts, In1<int64_t> owner, Vertices V, Faces F,
                                                         In1<double> M, int threads) {
    const Mesh m = mesh_of(V, F, &M);
    const size_t n = pts.shape(0);
    check_length(owner.shape(0), n, "owner");
    std::vector<double> out(n);
    {
        nb::gil_scoped_release unlocked;
        const double* P = pts.data();
        const int64_t* o = owner.data();
        parallel_for(n, threads, 1 + 100000 / (m.nf + 1), [&](size_t i0, size_t i1) {
            for (size_t i = i0; i < i1; ++i) {
                const V3 x = row(P, int64_t(i));
                double s = 0.0;
                for (size_t f = 0; f < m.nf; ++f)
                    if (int64_t(f) != o[i]) s += m.M[f] * solid_angle(m, int64_t(f), x);
                out[i] = s / FOUR_PI;
            }
        });
    }
    return to_numpy(std::move(out), {n});
}

}  // namespace

void bind_cuts(nb::module_& m) {
    m.def("cut_lists", &cut_lists,
          "Faces that may cut each face: CSR (cut_ptr (F + 1,), cut_idx), both ways, increasing.");
    m.def("winding_rest", &winding_rest, "Winding numbers at pts of every face but owner[i].");
}

}  // namespace inertia::robust

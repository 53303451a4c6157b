// Winding numbers of a closed, consistently wound shell at many points.  Off the surface the
// generalized winding number (the sum of the faces' solid angles / 4 pi) is an integer: the
// signed number of times a ray from the point crosses the shell.  The faces are filed in a 2-D
// grid of their projections along the ray (one counting sort), so a point's ray meets only the
// faces of its grid cell.  Where that count could be wrong (a point within NEAR_RTOL of a face,
// a ray within rounding of an edge, a shell whose edges do not pair up) the solid angles are
// summed over every face instead (Van Oosterom & Strackee 1983).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/solid_angle.hpp"
#include "common/star.hpp"
#include "selfcross/crossing.hpp"
#include "topology/weld.hpp"

namespace inertia::selfcross {

// a point nearer than this times the shell's box diagonal to a face takes the solid-angle sum
constexpr double NEAR_RTOL = 1e-9;

// Every directed edge a -> b met as often as b -> a (a hash table of signed counts): the shell
// is closed as a chain.  Vertex numbers of 32 bits and more: not told (false).
inline bool edges_pair_up(const int64_t *F, size_t nf) {
    size_t cap = 16;
    while (cap < 6 * nf) cap *= 2;
    std::vector<uint64_t> key(cap, 0);
    std::vector<int32_t> count(cap, 0);
    for (size_t i = 0; i < 3 * nf; ++i) {
        const int64_t a = F[i], b = F[i % 3 == 2 ? i - 2 : i + 1];
        if (std::max(a, b) >= (int64_t(1) << 32) - 1) return false;
        const uint64_t k = (uint64_t(std::min(a, b)) << 32 | uint64_t(std::max(a, b))) + 1;
        size_t h = size_t((k * 0x9E3779B97F4A7C15ull) >> 20) & (cap - 1);
        while (key[h] != 0 && key[h] != k) h = (h + 1) & (cap - 1);
        key[h] = k;
        count[h] += a < b ? 1 : -1;
    }
    return std::all_of(count.begin(), count.end(), [](int32_t c) { return c == 0; });
}

// The corners of a triangle soup (T, 3, 3) as vertices (returned) and faces F (T, 3), corners
// with equal coordinates (bit for bit) one vertex (topology's weld).
inline Vec<double> weld_corners(const double *tri, size_t nt, Vec<int64_t> &F) {
    topology::Groups<int64_t> g = topology::weld_rows<true>(tri, 3 * nt);
    Vec<double> V(3 * size_t(g.count));
    for (size_t j = 0; j < size_t(g.count); ++j) std::copy(tri + 3 * g.first[j], tri + 3 * g.first[j] + 3, &V[3 * j]);
    F = std::move(g.group);
    return V;
}

class ShellWinding {
  public:
    ShellWinding(const double *V, const int64_t *F, size_t nf) : V_(V), F_(F), nf_(nf) {
        if (nf == 0 || !edges_pair_up(F, nf)) return;
        // the faces' projected boxes (x, y along E1, E2, widened by near_) and 3-D diagonal
        std::vector<double> pb(4 * nf);
        double lo3[3] = {INFINITY, INFINITY, INFINITY}, hi3[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < 3 * nf; ++i)
            for (int k = 0; k < 3; ++k) {
                const double x = V[3 * F[i] + k];
                if (!std::isfinite(x)) return;  // no grid: the solid angles are summed
                lo3[k] = std::min(lo3[k], x), hi3[k] = std::max(hi3[k], x);
            }
        near_ = NEAR_RTOL * std::sqrt((hi3[0] - lo3[0]) * (hi3[0] - lo3[0]) + (hi3[1] - lo3[1]) * (hi3[1] - lo3[1]) +
                                      (hi3[2] - lo3[2]) * (hi3[2] - lo3[2]));
        if (!std::isfinite(near_)) return;
        x0_ = y0_ = INFINITY;
        double x1 = -INFINITY, y1 = -INFINITY;
        std::vector<double> extent(nf);
        for (size_t t = 0; t < nf; ++t) {
            double *b = &pb[4 * t];
            b[0] = b[1] = INFINITY, b[2] = b[3] = -INFINITY;
            for (int k = 0; k < 3; ++k) {
                double xy[2];
                project(corner(t, k), xy);
                b[0] = std::min(b[0], xy[0]), b[1] = std::min(b[1], xy[1]);
                b[2] = std::max(b[2], xy[0]), b[3] = std::max(b[3], xy[1]);
            }
            b[0] -= 2 * near_, b[1] -= 2 * near_, b[2] += 2 * near_, b[3] += 2 * near_;
            extent[t] = std::max(b[2] - b[0], b[3] - b[1]);
            x0_ = std::min(x0_, b[0]), y0_ = std::min(y0_, b[1]), x1 = std::max(x1, b[2]), y1 = std::max(y1, b[3]);
        }
        // cells about as long as the median face, coarser while the faces fill more than 8 cells each
        std::nth_element(extent.begin(), extent.begin() + nf / 2, extent.end());
        h_ = std::max(extent[nf / 2], 1e-300);
        auto cells = [&](size_t t, int64_t *c) {
            const double *b = &pb[4 * t];
            c[0] = int64_t((b[0] - x0_) / h_), c[1] = int64_t((b[1] - y0_) / h_);
            c[2] = int64_t((b[2] - x0_) / h_), c[3] = int64_t((b[3] - y0_) / h_);
        };
        while (true) {
            const double dx = (x1 - x0_) / h_ + 1.0, dy = (y1 - y0_) / h_ + 1.0;
            double reg = 0.0;
            if (dx * dy <= 4.0 * double(nf) + 16) {
                nx_ = int64_t(dx), ny_ = int64_t(dy);
                for (size_t t = 0; t < nf && reg <= 8.0 * double(nf); ++t) {
                    int64_t c[4];
                    cells(t, c);
                    reg += double(c[2] - c[0] + 1) * double(c[3] - c[1] + 1);
                }
                if (reg <= 8.0 * double(nf)) break;
            }
            h_ *= 2.0;
        }
        start_.assign(size_t(nx_ * ny_) + 1, 0);
        for (int pass = 0; pass < 2; ++pass) {  // count, then file (a counting sort)
            std::vector<int64_t> fill(start_.begin(), start_.end() - 1);
            for (size_t t = 0; t < nf; ++t) {
                int64_t c[4];
                cells(t, c);
                for (int64_t x = c[0]; x <= c[2]; ++x)
                    for (int64_t y = c[1]; y <= c[3]; ++y) {
                        if (pass == 0) start_[x * ny_ + y + 1] += 1;
                        else faces_[fill[x * ny_ + y]++] = int64_t(t);
                    }
            }
            if (pass == 0) {
                for (size_t i = 0; i + 1 < start_.size(); ++i) start_[i + 1] += start_[i];
                faces_.resize(start_.back());
            }
        }
        counted_ = true;
    }

    double at(const double *p) const {
        if (nf_ == 0) return 0.0;
        if (counted_) {
            const int64_t n = crossings(p);
            if (n != NO_COUNT) return double(n);
        }
        double sum = 0.0;
        for (size_t t = 0; t < nf_; ++t) sum += solid_angle(corner(t, 0), corner(t, 1), corner(t, 2), row(p));
        return sum / (4.0 * M_PI);
    }

  private:
    static constexpr int64_t NO_COUNT = INT64_MIN;
    // the ray's direction U and two unit vectors E1, E2 with (E1, E2, U) right-handed
    static constexpr const double *U = STAR_RAYS[0];
    static constexpr double E1[3] = {0.8944271909999159, -0.4472135954999579, 0.0};
    static constexpr double E2[3] = {0.35856858280031806, 0.7171371656006361, -0.5976143046671968};
    const double *V_;
    const int64_t *F_;
    size_t nf_;
    bool counted_ = false;  // the grid is built: the shell's edges pair up
    double near_ = 0.0, x0_ = 0.0, y0_ = 0.0, h_ = 1.0;
    int64_t nx_ = 0, ny_ = 0;
    std::vector<int64_t> start_, faces_;  // per cell, its faces: faces_[start_[c]:start_[c + 1]]

    const double *corner(size_t t, int k) const { return V_ + 3 * F_[3 * t + k]; }
    static void project(const double *p, double *xy) {
        xy[0] = E1[0] * p[0] + E1[1] * p[1] + E1[2] * p[2];
        xy[1] = E2[0] * p[0] + E2[1] * p[1] + E2[2] * p[2];
    }

    // p within d of the triangle (a, b, c): of its plane, and of the inner side of each edge's line
    // in it (conservative near the corners).
    static bool near(const double *p, const double *a, const double *b, const double *c, double d) {
        double n[3];
        face_normal(a, b, c, n);
        const double ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(std::abs(n[0] * (p[0] - a[0]) + n[1] * (p[1] - a[1]) + n[2] * (p[2] - a[2])) <= d * ln)) return false;
        const double *q[4] = {a, b, c, a};
        for (int k = 0; k < 3; ++k) {  // m = n x (edge): the edge's inward normal in the plane
            const double e[3] = {q[k + 1][0] - q[k][0], q[k + 1][1] - q[k][1], q[k + 1][2] - q[k][2]};
            const double m[3] = {n[1] * e[2] - n[2] * e[1], n[2] * e[0] - n[0] * e[2], n[0] * e[1] - n[1] * e[0]};
            const double lm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            if ((p[0] - q[k][0]) * m[0] + (p[1] - q[k][1]) * m[1] + (p[2] - q[k][2]) * m[2] < -d * lm) return false;
        }
        return true;
    }

    // Signed crossings of the ray from p along U (+1 leaving through a face's outer side), or
    // NO_COUNT when p is within near_ of a face or the ray within rounding of an edge.
    int64_t crossings(const double *p) const {
        if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) return NO_COUNT;
        double xy[2];
        project(p, xy);
        const double fx = (xy[0] - x0_) / h_, fy = (xy[1] - y0_) / h_;
        if (!(fx >= 0.0 && fy >= 0.0 && fx < double(nx_) && fy < double(ny_))) return 0;  // no face covers it
        const int64_t c = int64_t(fx) * ny_ + int64_t(fy);
        const double rtol = STAR_EDGE_RTOL, d = near_;
        int64_t count = 0;
        for (int64_t e = start_[c]; e < start_[c + 1]; ++e) {
            const size_t t = size_t(faces_[e]);
            const double *a = corner(t, 0), *b = corner(t, 1), *cc = corner(t, 2);
            const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
            const double s0[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
            if (near(p, a, b, cc, d)) return NO_COUNT;
            // Moller-Trumbore
            const double pv[3] = {U[1] * e2[2] - U[2] * e2[1], U[2] * e2[0] - U[0] * e2[2], U[0] * e2[1] - U[1] * e2[0]};
            const double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
            const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
            const double l2 = std::sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
            const double s = (s0[0] * pv[0] + s0[1] * pv[1] + s0[2] * pv[2]) / det;
            const double q[3] = {s0[1] * e1[2] - s0[2] * e1[1], s0[2] * e1[0] - s0[0] * e1[2], s0[0] * e1[1] - s0[1] * e1[0]};
            const double w = (U[0] * q[0] + U[1] * q[1] + U[2] * q[2]) / det;
            const bool apart = s < -rtol || w < -rtol || s + w > 1.0 + rtol;
            if (!(std::abs(det) > rtol * l1 * l2)) {  // the ray nearly along the face
                if (!(std::isfinite(s) && std::isfinite(w)) || !apart) return NO_COUNT;
                continue;
            }
            if (apart || (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det <= 0.0) continue;
            if (s < rtol || w < rtol || s + w > 1.0 - rtol) return NO_COUNT;  // through an edge, to rounding
            count += det < 0.0 ? 1 : -1;  // det = -U . n: leaving through the outer side when negative
        }
        return count;
    }
};

// Does the surface of B run both strictly inside and strictly outside the closed shell A?
// B's sample points are each face's centroid and a point near each corner (barycentric weights
// 0.8, 0.1, 0.1: a centroid alone misses a corner poking in); those strictly inside A's box lo..hi
// are thinned evenly to n_max (as numpy.linspace would pick them) and A's winding number found at
// each.  Returns the first point with |w| > 3/4 when B also has a point outside A's box or one
// with |w| < 1/4; else false.
inline bool runs_inside(const ShellWinding &A, const double *lo, const double *hi, const double *V, const int64_t *Fb,
                        size_t nb, size_t n_max, double *point) {
    static constexpr double W[4][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.8, 0.1, 0.1}, {0.1, 0.8, 0.1}, {0.1, 0.1, 0.8}};
    auto sample = [&](size_t i, double *x) {  // sample point i: face i / 4, weights i % 4
        const int64_t *f = Fb + 3 * (i / 4);
        for (int k = 0; k < 3; ++k)
            x[k] = W[i % 4][0] * V[3 * f[0] + k] + W[i % 4][1] * V[3 * f[1] + k] + W[i % 4][2] * V[3 * f[2] + k];
    };
    std::vector<size_t> in;
    for (size_t t = 0; t < nb; ++t) {
        const int64_t *f = Fb + 3 * t;
        bool apart = false;  // a face whose box misses the open box holds no sample point inside it
        for (int k = 0; k < 3 && !apart; ++k)
            apart = std::max({V[3 * f[0] + k], V[3 * f[1] + k], V[3 * f[2] + k]}) <= lo[k] ||
                    std::min({V[3 * f[0] + k], V[3 * f[1] + k], V[3 * f[2] + k]}) >= hi[k];
        for (size_t i = 4 * t; i < 4 * t + 4 && !apart; ++i) {
            double x[3];
            sample(i, x);
            if (x[0] > lo[0] && x[0] < hi[0] && x[1] > lo[1] && x[1] < hi[1] && x[2] > lo[2] && x[2] < hi[2]) in.push_back(i);
        }
    }
    const size_t n_in = in.size(), m = std::min(n_in, n_max);
    bool outside = n_in < 4 * nb, found = false;
    const double step = m > 1 ? double(n_in - 1) / double(m - 1) : 0.0;
    for (size_t r = 0; r < m && !(found && outside); ++r) {
        double x[3];
        sample(in[n_in <= n_max ? r : m > 1 && r + 1 == m ? n_in - 1 : size_t(double(r) * step)], x);
        const double w = std::abs(A.at(x));
        if (w > 0.75 && !found) {
            found = true;
            std::copy(x, x + 3, point);
        }
        outside = outside || w < 0.25;
    }
    return found && outside;
}

}  // namespace inertia::selfcross

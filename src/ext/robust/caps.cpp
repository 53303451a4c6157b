// The cap-region octree's cells for the set D = {x : |w_cap(x)| >= thr} (w_cap the winding
// number of the caps closing the mesh boundary):
//   status 0, free: no cap crosses the cell and |w_cap(c)| + rho |grad w_cap| < thr (c the
//     centre, rho the half diagonal; |grad w| <= sum_e m_e len_e / (4 pi d_e^2), Biot-Savart
//     over each cap's loop);
//   status 1, near one flat cap (thr = 1/2 only): cap k a flat polygon covered once, the others
//     neither crossing the cell nor reaching it with a loop edge, adding at most
//     Delta = |w_rest(c)| + rho |grad w_rest| < 1/10 on it; D then meets the cell only where
//     |w_k| >= 1/2 - Delta, a thin layer whose volume flat_cap_volume bounds in closed form;
//   status 2: refine (or count the cell whole at the last level).
#include <nanobind/stl/array.h>

#include "robust/kernels.hpp"

namespace inertia::robust {
namespace {

// (h_in, r_max, h_max) of flat_cap_volume, 0 <= delta < 1/4.
std::array<double, 3> flat_cap_heights(double delta, double diameter) {
    if (delta <= 0.0) return {0.0, 0.0, 0.0};
    const double b = 2.0 * delta / std::sqrt(1.0 - 4.0 * delta * delta);
    const double a = (1.0 - 2.0 * delta) / (2.0 * std::sqrt(delta * (1.0 - delta)));
    const double r_max = b * diameter / (a - b);
    return {b * diameter, r_max, b * (r_max + diameter)};
}

// Bound of the volume where |w_k| >= 1/2 - delta for a flat polygon k (area, perimeter,
// diameter; flat within flat_tol), 0 <= delta < 1/10, over `shadow` of its plane (inf: all).
// With b = 2 delta / sqrt(1 - 4 delta^2), a point at height h over foot q:
//  q in the polygon: the plane beyond `diameter` of q lies outside it, so its solid angle
//    misses at least 2 pi h / sqrt(h^2 + diameter^2): |h| <= h_in = b diameter;
//  q outside at distance r: the polygon lies between the circles of radii r and r + diameter,
//    so |w_k| <= h / (2 sqrt(h^2 + r^2)) and <= 1/2 - h / (2 sqrt(h^2 + (r + diameter)^2)); both
//    reach 1/2 - delta only for r <= r_max = b diameter / (a - b),
//    a = (1 - 2 delta) / (2 sqrt(delta (1 - delta))), and |h| <= h_max = b (r_max + diameter).
// So the set lies in a layer over the polygon and a band around it, each thickened by flat_tol.
double flat_cap_volume(double delta, double area, double perimeter, double diameter, double flat_tol, double shadow) {
    const auto [h_in, r_max, h_max] = flat_cap_heights(delta, diameter);
    return 2.0 * std::min(area, shadow) * (h_in + flat_tol) +
           2.0 * std::min(perimeter * r_max + PI * r_max * r_max, shadow) * (h_max + flat_tol);
}

double box_distance(const double* x, const double* lo, const double* hi) {
    double s = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double d = std::max(0.0, std::max(lo[c] - x[c], x[c] - hi[c]));
        s += d * d;
    }
    return std::sqrt(s);
}

double segment_distance(const double* x, const double* E0, const double* E1) {
    double d[3], q[3], r[3];
    sub(E1, E0, d);
    sub(x, E0, q);
    const double dd = dot(d, d);
    const double t = dd > 0.0 ? std::min(1.0, std::max(0.0, dot(q, d) / dd)) : 0.0;
    for (int c = 0; c < 3; ++c) r[c] = q[c] - t * d[c];
    return norm(r);
}

struct CapArrays {
    const double *CV, *CM, *face_lo, *face_hi, *E0, *E1, *EM, *area, *perimeter, *diameter, *normal, *apex, *flat_dev;
    const int64_t *CF, *face_ptr, *edge_ptr;
    const bool* flat;
    size_t K;
    double eps;

    // Biot-Savart bound of |grad w| over the cell (x, rho) from loop edges e0..e1-1 (inf if one reaches it).
    double loop_gradient(const double* x, double rho, int64_t e0, int64_t e1) const {
        double g = 0.0;
        for (int64_t e = e0; e < e1; ++e) {
            const double d = segment_distance(x, E0 + 3 * e, E1 + 3 * e) - rho;
            if (d <= 0.0) return INF;
            double l[3];
            sub(E1 + 3 * e, E0 + 3 * e, l);
            g += EM[e] * norm(l) / (FOUR_PI * d * d);
        }
        return g;
    }

    // One cell (centre x, half side `half`); writes status, which, delta, w_rest, contrib.
    void classify(const double* x, double half, double thr, int64_t& status, int64_t& which, double& delta,
                  double& w_rest, double& contrib) const {
        const double rho = half * std::sqrt(3.0);
        double w_all = 0.0, g_fin = 0.0, best = -1.0, w_k = 0.0, g_k = 0.0;
        int n_inf = 0, n_cross = 0;
        int64_t nk = -1;
        bool cross_k = false;
        for (size_t j = 0; j < K; ++j) {
            double w = 0.0;
            bool crossed = false;
            for (int64_t f = face_ptr[j]; f < face_ptr[j + 1]; ++f) {
                if (box_distance(x, face_lo + 3 * f, face_hi + 3 * f) <= rho) crossed = true;
                w += CM[f] * solid_angle(CV + 3 * CF[3 * f], CV + 3 * CF[3 * f + 1], CV + 3 * CF[3 * f + 2], row(x));
            }
            w /= FOUR_PI;
            const double g = loop_gradient(x, rho, edge_ptr[j], edge_ptr[j + 1]);
            w_all += w;
            n_cross += crossed;
            if (g == INF)
                n_inf++;
            else
                g_fin += g;
            const double score = (crossed || g == INF) ? INF : std::abs(w) + rho * g;
            if (score > best || nk < 0) best = score, nk = int64_t(j), w_k = w, g_k = g, cross_k = crossed;
        }
        status = 2, which = -1, delta = 0.0, w_rest = 0.0, contrib = 0.0;
        if (n_cross == 0 && n_inf == 0 && std::abs(w_all) + rho * g_fin < thr) {
            status = 0;
            return;
        }
        if (nk < 0 || thr != 0.5 || !flat[nk]) return;
        // the other caps: no crossing, no loop edge within the cell, and small
        if (n_cross - cross_k > 0 || n_inf - (g_k == INF) > 0) return;
        double d = std::abs(w_all - w_k) + rho * (g_fin - (g_k < INF ? g_k : 0.0));
        if (flat_dev[nk] > 0.0)
            d += flat_dev[nk] * loop_gradient(x, rho + flat_dev[nk], edge_ptr[nk], edge_ptr[nk + 1]);
        if (!(d < 0.1)) return;
        const double* n = normal + 3 * nk;
        double q[3];
        sub(x, apex + 3 * nk, q);
        const double height = dot(q, n);
        const auto [h_in, r_max, h_max] = flat_cap_heights(d, diameter[nk]);
        (void)r_max;
        if (std::abs(height) > rho + std::max(h_in, h_max) + flat_dev[nk] + eps) {
            status = 0;
            return;
        }
        status = 1, which = nk, delta = d, w_rest = std::abs(w_all - w_k);
        const double side = 2.0 * half, shadow = side * side * (std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
        contrib = std::min(side * side * side,
                           flat_cap_volume(d, area[nk], perimeter[nk], diameter[nk], flat_dev[nk] + eps, shadow));
    }
};

// Classify cubic cells (centres (N, 3), half side `half`).  Caps, in groups j: faces CF (over
// CV, multiplicities CM, boxes face_lo/hi) face_ptr[j]:face_ptr[j + 1], loop edges E0 -> E1
// (EM) edge_ptr[j]:edge_ptr[j + 1]; flat[j], area, perimeter, diameter as in flat_cap_volume,
// unit normal and apex (a point of its plane), flat_dev (0: flat within eps).  Status 1 cells
// get which = k, delta, w_rest = |w_rest(c)| and contrib, the layer's volume over the cell's
// shadow on k's plane (at most the cell's volume).
nb::tuple cap_cells(InN3<double> centers, double half, double thr, InN3<double> CV, Faces CF, In1<double> CM,
                    In1<int64_t> face_ptr, InN3<double> face_lo, InN3<double> face_hi, InN3<double> E0, InN3<double> E1,
                    In1<double> EM, In1<int64_t> edge_ptr, In1<bool> flat, In1<double> area, In1<double> perimeter,
                    In1<double> diameter, InN3<double> normal, InN3<double> apex, In1<double> flat_dev, double eps,
                    int threads) {
    const size_t nc = CF.shape(0), ne = E0.shape(0), K = face_ptr.shape(0) ? face_ptr.shape(0) - 1 : 0;
    check_at_least(face_ptr.shape(0), 1, "face_ptr");
    check_faces(CF.data(), nc, CV.shape(0), "cap faces");
    check_length(CM.shape(0), nc, "CM");
    check_ptr(face_ptr.data(), face_ptr.shape(0), K, nc, "face_ptr");
    check_length(face_lo.shape(0), nc, "face_lo");
    check_length(face_hi.shape(0), nc, "face_hi");
    check_length(E1.shape(0), ne, "E1");
    check_length(EM.shape(0), ne, "EM");
    check_ptr(edge_ptr.data(), edge_ptr.shape(0), K, ne, "edge_ptr");
    for (auto* a : {&flat_dev, &area, &perimeter, &diameter}) check_length(a->shape(0), K, "cap group values");
    check_length(flat.shape(0), K, "flat");
    check_length(normal.shape(0), K, "normal");
    check_length(apex.shape(0), K, "apex");
    const CapArrays caps{CV.data(),
                         CM.data(),
                         face_lo.data(),
                         face_hi.data(),
                         E0.data(),
                         E1.data(),
                         EM.data(),
                         area.data(),
                         perimeter.data(),
                         diameter.data(),
                         normal.data(),
                         apex.data(),
                         flat_dev.data(),
                         CF.data(),
                         face_ptr.data(),
                         edge_ptr.data(),
                         flat.data(),
                         K,
                         eps};
    const size_t n = centers.shape(0);
    std::vector<int64_t> status(n), which(n);
    std::vector<double> delta(n), w_rest(n), contrib(n);
    {
        nb::gil_scoped_release unlocked;
        parallel_for(n, threads, 1 + 20000 / (nc + ne + 1), [&](size_t i0, size_t i1) {
            for (size_t i = i0; i < i1; ++i)
                caps.classify(centers.data() + 3 * i, half, thr, status[i], which[i], delta[i], w_rest[i], contrib[i]);
        });
    }
    return nb::make_tuple(to_numpy(std::move(status), {n}), to_numpy(std::move(which), {n}),
                          to_numpy(std::move(delta), {n}), to_numpy(std::move(w_rest), {n}),
                          to_numpy(std::move(contrib), {n}));
}

}  // namespace

void bind_caps(nb::module_& m) {
    m.def("cap_cells", &cap_cells,
          "Octree cells against the cap region: (status, which, delta, w_rest, contrib), each (N,).");
    m.def("flat_cap_volume", &flat_cap_volume,
          "Bound of the volume where |w_k| >= 1/2 - delta near a flat polygon, over `shadow` of its plane.");
    m.def("flat_cap_heights", &flat_cap_heights, "(h_in, r_max, h_max) of flat_cap_volume.");
}

}  // namespace inertia::robust

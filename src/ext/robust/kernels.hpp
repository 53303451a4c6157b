// Shared pieces of the robust family (inertia._ext.robust): the mesh view, solid angles and
// tetrahedron sums, the CSR check.
// Conventions: triangles are index triples into V (N, 3); `eps` is a length; every
// intersection test is conservative (true = "may cut" within eps), so that false is safe.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/arrays.hpp"
#include "common/parallel.hpp"
#include "common/solid_angle.hpp"
#include "common/vec3.hpp"

namespace inertia::robust {

constexpr double PI = 3.141592653589793;
constexpr double FOUR_PI = 4.0 * PI;
constexpr double TWO_PI = 2.0 * PI;
constexpr double INF = INFINITY;

template <class T>
using InN4 = nb::ndarray<const T, nb::shape<-1, 4>, nb::c_contig, nb::device::cpu>;

// A CSR pointer of `rows` rows over `items` entries: starts at 0, never decreases, ends at items.
inline void check_ptr(const int64_t* ptr, size_t len, size_t rows, size_t items, const char* what) {
    check_length(len, rows + 1, what);
    if (ptr[0] != 0 || ptr[rows] != int64_t(items))
        input_error(std::string(what) + " must run from 0 to " + std::to_string(items));
    for (size_t i = 0; i < rows; ++i)
        if (ptr[i + 1] < ptr[i]) input_error(std::string(what) + " decreases at " + std::to_string(i));
}

// The closed chain: vertices, faces (checked), multiplicities.
struct Mesh {
    const double* V;
    const int64_t* F;
    const double* M;
    size_t nv, nf;
    const double* at(int64_t f, int k) const { return V + 3 * F[3 * f + k]; }
    void load(int64_t f, double T[3][3]) const {
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) T[k][c] = at(f, k)[c];
    }
};

inline Mesh mesh_of(const Vertices& V, const Faces& F, const In1<double>* M = nullptr) {
    check_faces(F.data(), F.shape(0), V.shape(0));
    if (M) check_length(M->shape(0), F.shape(0), "multiplicities");
    return {V.data(), F.data(), M ? M->data() : nullptr, V.shape(0), F.shape(0)};
}

inline double solid_angle(const Mesh& m, int64_t f, const V3& p) {
    return solid_angle(m.at(f, 0), m.at(f, 1), m.at(f, 2), p);
}

// acc (10,) += weight x the signed tetrahedron (0, a, b, c) integrals times 6, 24 (x3), 120 (x6):
// volume, int y (3), int y y^T (xx, yy, zz, xy, xz, yz).
inline void tetra_add(double* acc, double weight, const double* a, const double* b, const double* c) {
    const double det = weight * (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                                 a[2] * (b[0] * c[1] - b[1] * c[0]));
    const double s[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
    acc[0] += det;
    for (int i = 0; i < 3; ++i) acc[1 + i] += det * s[i];
    static constexpr int P[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    for (int k = 0; k < 6; ++k) {
        const int i = P[k][0], j = P[k][1];
        acc[4 + k] += det * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
}

// out (13,) += bounds of the tetrahedron (0, a, b, c) integrals of |1|, |y_j|, |y_j y_k|:
// |V|, |V| max|y_j|, |V| max|y_j| max|y_k| (the largest |y_j| is at a corner).
inline void tetra_abs(double* out, double weight, const double* a, const double* b, const double* c) {
    const double vol = std::abs(a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                                a[2] * (b[0] * c[1] - b[1] * c[0])) /
                       6.0 * weight;
    double m[3];
    for (int j = 0; j < 3; ++j) m[j] = std::max(std::abs(a[j]), std::max(std::abs(b[j]), std::abs(c[j])));
    out[0] += vol;
    for (int j = 0; j < 3; ++j) out[1 + j] += vol * m[j];
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) out[4 + 3 * j + k] += vol * m[j] * m[k];
}

}  // namespace inertia::robust

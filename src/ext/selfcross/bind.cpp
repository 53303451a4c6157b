// Bindings of the selfcross family (inertia._ext.selfcross): the star certificate, the
// self-crossing search of a closed shell with its cell proof, and the triangle crossing tests.
#include <nanobind/stl/optional.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/vector.h>

#include <array>
#include <optional>
#include <utility>

#include "common/arrays.hpp"
#include "common/star.hpp"
#include "selfcross/search.hpp"
#include "selfcross/winding.hpp"

using namespace inertia;
using namespace inertia::selfcross;
using namespace nb::literals;
using Pair = std::optional<std::pair<int64_t, int64_t>>;

namespace {

// The faces' vertex numbers, and the sizes the kernels' 32-bit face and vertex numbers hold.
void checked_faces(const Faces &F, size_t n_vertices, const char *what = "faces", bool renumbered = false) {
    check_faces(F.data(), F.shape(0), n_vertices, what);
    if (F.shape(0) >= (size_t(1) << 29) || (n_vertices >= (size_t(1) << 31) && !renumbered))
        input_error(std::string(what) + ": at most 2^29 faces and 2^31 - 1 vertices");
}

// twins: no rows, or one per face with every entry a face number below `limit`.
const int64_t *checked_twins(const InN3<int64_t> &twins, size_t nf, size_t limit) {
    if (twins.shape(0) == 0) return nullptr;
    check_length(twins.shape(0), nf, "twins");
    check_index_rows(twins.data(), nf, limit, "twins", "face", nf);
    return twins.data();
}

template <class A>
auto bool_out(size_t n, A &&fill) {
    auto out = new_vector<bool>(n);
    std::vector<uint8_t> work(n, 0);
    {
        nb::gil_scoped_release release;
        fill(work.data());
    }
    std::copy(work.begin(), work.end(), out.data());
    return out;
}

}  // namespace

void bind_selfcross(nb::module_ &m) {
    m.attr("STAR_RTOL") = STAR_RTOL;
    m.attr("CROSS_RTOL") = CROSS_RTOL;
    m.attr("CELL_EDGES") = CELL_EDGES;
    m.attr("HEIGHTFIELD_MIN_FACES") = HEIGHTFIELD_MIN_FACES;

    m.def("star_certificate", [](Vertices V, Faces F, In1<double> center) {
        checked_faces(F, V.shape(0));
        check_length(center.shape(0), 3, "center");
        nb::gil_scoped_release release;
        return star_certificate(V.data(), F.data(), F.shape(0), center.data());
    }, "vertices"_a, "faces"_a, "center"_a,
          "True when the closed, outward shell is star-shaped from center with a one-to-one radial projection.");

    m.def("find_crossing", [](Vertices V, Faces F, InN3<int64_t> twins, bool prove_cells) -> Pair {
        const size_t nf = F.shape(0), nv = V.shape(0);
        checked_faces(F, nv, "faces", nv > 4 * nf + 1024);  // (then renumbered to at most 3 nf vertices)
        const int64_t *adj = checked_twins(twins, nf, nf);
        int64_t out[2];
        nb::gil_scoped_release release;
        if (!find_crossing(V.data(), F.data(), nf, nv, adj, prove_cells, out)) return std::nullopt;
        return std::make_pair(out[0], out[1]);
    }, "vertices"_a, "faces"_a, "twins"_a, "prove_cells"_a = true,
          "A pair (i < j) of faces of the closed shell that cross, or None.  twins: the face across each edge\n"
          "(face_twins), or no rows.  prove_cells=False: every face pair searched, no cell proof.");

    m.def("triangles_cross", [](In3x3<double> T1, In3x3<double> T2) {
        const size_t n = T1.shape(0);
        check_length(T2.shape(0), n, "T2");
        return bool_out(n, [&](uint8_t *hit) {
            for (size_t i = 0; i < n; ++i) {
                const double *a = T1.data() + 9 * i, *b = T2.data() + 9 * i;
                hit[i] = tris_cross(make_tri(a, a + 3, a + 6), make_tri(b, b + 3, b + 6), CROSS_RTOL);
            }
        });
    }, "T1"_a, "T2"_a, "(N,) bool: triangles T1[i] and T2[i] (N, 3, 3) cross (an edge of one through the other).");

    m.def("crossing_between", [](Vertices V, Faces A, Faces B, In1<double> lo, In1<double> hi, size_t max_faces) -> Pair {
        checked_faces(A, V.shape(0), "faces_a");
        checked_faces(B, V.shape(0), "faces_b");
        check_length(lo.shape(0), 3, "lo");
        check_length(hi.shape(0), 3, "hi");
        int64_t out[2];
        nb::gil_scoped_release release;
        if (!crossing_between(V.data(), A.data(), A.shape(0), B.data(), B.shape(0), lo.data(), hi.data(), max_faces, out))
            return std::nullopt;
        return std::make_pair(out[0], out[1]);
    }, "vertices"_a, "faces_a"_a, "faces_b"_a, "lo"_a, "hi"_a, "max_faces"_a,
          "The first (i, j), lowest i then j, with faces_a[i] and faces_b[j] crossing among the faces whose boxes\n"
          "meet lo..hi; None when none does or more than max_faces faces meet that box.");

    m.def("face_twins", [](Faces F, size_t n_vertices) -> std::optional<nb::ndarray<nb::numpy, int64_t, nb::ndim<2>>> {
        const size_t nf = F.shape(0);
        checked_faces(F, n_vertices);
        auto adj = new_array<int64_t, 2>({nf, 3});
        bool closed;
        {
            nb::gil_scoped_release release;
            closed = face_twins(F.data(), nf, n_vertices, adj.data());
        }
        if (!closed) return std::nullopt;
        return adj;
    }, "faces"_a, "n_vertices"_a,
          "(F, 3): the face across the edge from corner k to k + 1 of each face; None when an edge has\n"
          "not exactly one face the other way.");

    m.def("certified_fans", [](Vertices V, Faces F, In1<bool> wanted, InN3<int64_t> twins) {
        const size_t nf = F.shape(0), nv = V.shape(0);
        checked_faces(F, nv);
        check_length(wanted.shape(0), nv, "wanted");
        const int64_t *adj = checked_twins(twins, nf, nf);
        std::vector<uint8_t> want(wanted.data(), wanted.data() + nv);
        return bool_out(nv, [&](uint8_t *cert) {
            const auto c = certified_fans(V.data(), F.data(), nf, nv, Frames(V.data(), F.data(), nf).n.data(),
                                          want.data(), adj);
            std::copy(c.begin(), c.end(), cert);
        });
    }, "vertices"_a, "faces"_a, "wanted"_a, "twins"_a,
          "Per vertex: its fan of faces is certified flat (no two of its faces can cross); the wanted only.\n"
          "With twins (rows), each fan is walked across its edges; without, faces are sorted by vertex.");

    m.def("patch_check", [](Vertices V, Faces F, InN3<int64_t> twins, In1<int64_t> patch) {
        const size_t nf = F.shape(0), nv = V.shape(0), n = patch.shape(0);
        checked_faces(F, nv);
        check_length(twins.shape(0), nf, "twins");
        checked_twins(twins, nf, nf + 1);
        check_range(patch.data(), n, 0, int64_t(nf), "patch");
        nb::gil_scoped_release release;
        std::vector<uint8_t> bits(nf);
        for (size_t t = 0; t < nf; ++t) {
            const double *a = V.data() + 3 * F.data()[3 * t], *b = V.data() + 3 * F.data()[3 * t + 1],
                         *c = V.data() + 3 * F.data()[3 * t + 2];
            double lo[3], hi[3];
            bits[t] = turn_bits(a, b, c, scaled_box(a, b, c, std::array<double, 3>{}.data(), 1.0, lo, hi));
        }
        PatchWork work(nf, nv, n);
        return patch_check(V.data(), F.data(), bits.data(), twins.data(), patch.data(), int64_t(n), work);
    }, "vertices"_a, "faces"_a, "twins"_a, "patch"_a,
          "0 when the faces `patch` form a height field along an axis (none crosses another); else the\n"
          "test that failed (1 orientation, 2 border vertex, 3 short border, 4 several loops, 5 loop not\n"
          "simple).  twins as face_twins; an entry equal to the number of faces means outside.");

    m.def("unproved_faces", [](Vertices V, Faces F, InN3<int64_t> twins, double cell) {
        const size_t nf = F.shape(0), nv = V.shape(0);
        checked_faces(F, nv);
        check_length(twins.shape(0), nf, "twins");
        const int64_t *adj = checked_twins(twins, nf, nf);
        return bool_out(nf, [&](uint8_t *keep) {
            double origin[3], top[3];
            box_and_median_edge(V.data(), F.data(), nf, origin, top);
            bool finite = true;
            for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(top[k] - origin[k]);
            if (finite) unproved_faces(V.data(), F.data(), nf, nv, adj, origin, top, cell, keep);
            else std::fill(keep, keep + nf, uint8_t(1));  // no proof of what is not finite
        });
    }, "vertices"_a, "faces"_a, "twins"_a, "cell"_a,
          "(F,) bool: the faces the cell proof (cells `cell` long from the low corner) leaves to the search.");

    m.def("winding_numbers", [](InN3<double> points, In3x3<double> tri) {
        const size_t n = points.shape(0);
        auto out = new_vector<double>(n);
        nb::gil_scoped_release release;
        Vec<int64_t> F;
        const Vec<double> V = weld_corners(tri.data(), tri.shape(0), F);
        const ShellWinding shell(V.data(), F.data(), tri.shape(0));
        for (size_t i = 0; i < n; ++i) out.data()[i] = shell.at(points.data() + 3 * i);
        return out;
    }, "points"_a, "tri"_a,
          "(P,) generalized winding numbers of the triangles tri (T, 3, 3) at points (P, 3): where the triangles\n"
          "form a closed surface (equal corners joined), the signed ray crossings off it; else the solid angles.");

    m.def("runs_inside", [](Vertices V, Faces A, In1<double> lo, In1<double> hi, std::vector<Faces> partners,
                            size_t n_max) {
        checked_faces(A, V.shape(0), "faces_a");
        for (const Faces &B : partners) checked_faces(B, V.shape(0), "partner faces");
        check_length(lo.shape(0), 3, "lo");
        check_length(hi.shape(0), 3, "hi");
        std::vector<std::optional<std::array<double, 3>>> out(partners.size());
        nb::gil_scoped_release release;
        const ShellWinding shell(V.data(), A.data(), A.shape(0));
        for (size_t i = 0; i < partners.size(); ++i) {
            std::array<double, 3> p;
            if (runs_inside(shell, lo.data(), hi.data(), V.data(), partners[i].data(), partners[i].shape(0), n_max, p.data()))
                out[i] = p;
        }
        return out;
    }, "vertices"_a, "faces_a"_a, "lo"_a, "hi"_a, "partners"_a, "n_max"_a,
          "Per partner shell B: a point of B's surface strictly inside the closed shell A (faces_a, box lo..hi)\n"
          "while B also runs strictly outside A, or None (at most n_max of B's sample points in A's box tried).");
}

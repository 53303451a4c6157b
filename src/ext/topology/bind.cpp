// Bindings of the topology family (inertia._ext.topology).  Each kernel runs without the GIL;
// its results are handed to NumPy (no copy) once the GIL is held again.
#include <nanobind/stl/tuple.h>

#include <limits>
#include <string>
#include <utility>

#include "common/arrays.hpp"
#include "topology/components.hpp"
#include "topology/merge.hpp"
#include "topology/weld.hpp"

using namespace inertia;
using namespace inertia::topology;

namespace {

using MeshArrays = std::tuple<NpArray<double, 2>, NpArray<int64_t, 2>>;

MeshArrays arrays(Mesh &&m) {
    const size_t nv = m.n_vertices(), nf = m.n_faces();
    return {to_numpy(std::move(m.v), {nv, 3}), to_numpy(std::move(m.f), {nf, 3})};
}

template <class F>
auto released(F &&job) {
    nb::gil_scoped_release unlocked;
    return job();
}

}  // namespace

void bind_topology(nb::module_ &m) {
    m.def("weld_map", [](Vertices v) {
        const size_t n = v.shape(0);
        return to_numpy(released([&] { return weld_map(v.data(), n); }), {n});
    }, "rep[i]: the lowest index of a row equal to row i (-0.0 == 0.0; a row with NaN or inf maps to itself).");

    m.def("weld_compact", [](Vertices v, Faces f) {
        check_faces(f.data(), f.shape(0), v.shape(0));
        return arrays(released([&] { return weld_compact(v.data(), v.shape(0), f.data(), f.shape(0)); }));
    }, "compact(v, f with each index replaced by weld_map(v)): welded, unreferenced rows dropped.");

    m.def("compact", [](Vertices v, Faces f) {
        check_faces(f.data(), f.shape(0), v.shape(0));
        return arrays(released([&] {
            return compact_groups<int64_t>(v.data(), f.data(), f.shape(0), nullptr, v.shape(0), nullptr);
        }));
    }, "Unreferenced vertices dropped, faces renumbered, the vertices' order kept.");

    m.def("near_merge_map", [](Vertices v, double tol) {
        if (!(tol > 0.0)) input_error("near_merge_map: tol must be positive, got " + std::to_string(tol));
        Vec<int64_t> rep = released([&] { return near_merge_map(v.data(), v.shape(0), tol); });
        const size_t n = rep.size();
        return to_numpy(std::move(rep), {n});
    }, "rep[i]: the lowest index of i's group of rows joined by distances <= tol; empty when the grid "
       "cannot number the cells.");

    m.def("float32_apart", [](Vertices v, double tol, double maxabs) {
        return released([&] { return float32_apart(v.data(), v.shape(0), tol, maxabs); });
    }, "True when no two rows (float32 values) are within tol in every coordinate; False when not shown.");

    m.def("weld_and_merge", [](Vertices v, Faces f, double rtol) {
        check_faces(f.data(), f.shape(0), v.shape(0));
        double pending = 0.0;
        MeshArrays out = arrays(released([&] {
            Mesh mesh = weld_compact(v.data(), v.shape(0), f.data(), f.shape(0));
            pending = merge_near(mesh, rtol, false);
            return mesh;
        }));
        return std::make_tuple(std::get<0>(out), std::get<1>(out), pending);
    }, "(v, f, pending): welded, then merged within rtol of the mesh size; pending > 0 is the tolerance "
       "still to merge within when the grid cannot number the cells.");

    m.def("stl_weld_and_merge", [](In1<uint8_t> data, size_t n, double rtol) {
        if (n > (data.shape(0) < 84 ? 0 : (data.shape(0) - 84) / 50))
            input_error("binary STL of " + std::to_string(data.shape(0)) + " bytes cannot hold " +
                        std::to_string(n) + " triangles");
        const uint8_t *records = data.data() + 84;
        double pending = 0.0;
        MeshArrays out = arrays(released([&] {
            return 3 * n < size_t(std::numeric_limits<int32_t>::max())
                       ? stl_weld_and_merge<int32_t>(records, n, rtol, pending)
                       : stl_weld_and_merge<int64_t>(records, n, rtol, pending);
        }));
        return std::make_tuple(std::get<0>(out), std::get<1>(out), pending);
    }, "weld_and_merge of a binary STL's triangles read from its bytes (`data`: the whole file).");

    m.def("connected_components", [](size_t n, In1<int64_t> a, In1<int64_t> b) {
        check_length(b.shape(0), a.shape(0), "b");
        for (size_t e = 0; e < a.shape(0); ++e)
            if (a(e) < 0 || b(e) < 0 || size_t(a(e)) >= n || size_t(b(e)) >= n)
                input_error("edge " + std::to_string(e) + " = (" + std::to_string(a(e)) + ", " +
                            std::to_string(b(e)) + ") names a node outside 0.." + std::to_string(n) + "-1");
        Vec<int64_t> labels(n);
        const int64_t count = released([&] {
            return connected_components(n, a.data(), b.data(), a.shape(0), labels.data());
        });
        return std::make_tuple(count, to_numpy(std::move(labels), {n}));
    }, "(count, labels): components of the graph on nodes 0..n-1 with edges a[e] - b[e], numbered in order "
       "of their lowest node.");
}

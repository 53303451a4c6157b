// Bindings of the text family (inertia._ext.text): ASCII STL and OBJ readers over a file's bytes.
#include <algorithm>

#include "common/arrays.hpp"
#include "text/ascii_stl.hpp"
#include "text/obj.hpp"

using namespace nb::literals;
using inertia::text::Mesh;

namespace {

// (vertices, faces, None), or (None, None, error) with error (kind, line number, line start, line end, token start,
// token end, count) with offsets into the text.
nb::tuple result(Mesh &&m, const uint8_t *d, size_t n) {
    if (const auto &e = m.error; e.kind != inertia::text::OK) {
        const size_t line = 1 + size_t(std::count(d, d + e.line, '\n'));
        const size_t end = size_t(std::find(d + e.line, d + n, '\n') - d);
        return nb::make_tuple(nb::none(), nb::none(), nb::make_tuple(e.kind, line, e.line, end, e.token, e.token_end,
                                                                     e.count));
    }
    const size_t nv = m.vertices.size() / 3, nf = m.faces.size() / 3;
    return nb::make_tuple(inertia::to_numpy(std::move(m.vertices), {nv, 3}), inertia::to_numpy(std::move(m.faces), {nf, 3}),
                          nb::none());
}

template <class Read>
nb::tuple read(inertia::In1<uint8_t> data, Read read) {
    Mesh m;
    {
        nb::gil_scoped_release nogil;
        m = read(data.data(), data.shape(0));
    }
    return result(std::move(m), data.data(), data.shape(0));
}

}  // namespace

void bind_text(nb::module_ &m) {
    m.def(
        "read_ascii_stl", [](inertia::In1<uint8_t> data) { return read(data, inertia::text::read_ascii_stl); },
        "data"_a,
        "(vertices (V, 3) float64, faces (F, 3) int64, None) of ASCII STL bytes, or (None, None, error); "
        "vertices[faces] are the file's corners (a repeated corner stored once).");
    m.def(
        "read_obj",
        [](inertia::In1<uint8_t> data, int polygons) {
            if (polygons < inertia::text::FAN || polygons > inertia::text::MUJOCO)
                throw nb::value_error("read_obj: polygons must be 0 (fan), 1 (shorter) or 2 (mujoco)");
            const auto how = inertia::text::Polygons(polygons);
            return read(data, [how](const uint8_t *d, size_t n) { return inertia::text::read_obj(d, n, how); });
        },
        "data"_a, "polygons"_a = 0,
        "(vertices (V, 3) float64, triangles (F, 3) int64, None) of OBJ bytes, or (None, None, error); polygons "
        "fanned from their first vertex (0), quadrilaterals split along their shorter diagonal (1), or as MuJoCo "
        "reads them (2: see src/ext/text/obj.hpp).");
}

// inertia._ext: the compiled core.  One submodule per kernel family, each bound in its own
// folder's bind.cpp; the layer that owns a family is the only one that imports it
// (geometry: integrals, topology, selfcross, text, robust; massprops: principal; dynamics: dynamics).
#include <nanobind/nanobind.h>

#include <exception>

#include "common/errors.hpp"

namespace nb = nanobind;

void bind_integrals(nb::module_ &m);
void bind_topology(nb::module_ &m);
void bind_selfcross(nb::module_ &m);
void bind_text(nb::module_ &m);
void bind_robust(nb::module_ &m);
void bind_dynamics(nb::module_ &m);
void bind_principal(nb::module_ &m);
void bind_isa(nb::module_ &m);

namespace {

// inertia::Error -> the Python class it names in inertia._core.errors, with its code.
void translate(const std::exception_ptr &p, void *) {
    try {
        std::rethrow_exception(p);
    } catch (const inertia::Error &e) {
        nb::gil_scoped_acquire gil;
        nb::object errors = nb::module_::import_("inertia._core.errors");
        nb::object cls = errors.attr(e.kind.c_str());
        nb::object exc = cls(nb::str(e.what()), nb::arg("code") = nb::str(e.code.c_str()));
        PyErr_SetObject(cls.ptr(), exc.ptr());
    }
}

void add(nb::module_ &parent, const char *name, const char *doc, void (*bind)(nb::module_ &)) {
    nb::module_ sub = parent.def_submodule(name, doc);
    bind(sub);
    // importable by its dotted name too: from inertia._ext import dynamics
    nb::module_::import_("sys").attr("modules")[(std::string("inertia._ext.") + name).c_str()] = sub;
}

}  // namespace

NB_MODULE(_ext, m) {
    m.doc() = "The compiled kernels of inertia (C++; built when the package is installed).";
    nb::register_exception_translator(translate);
    add(m, "integrals", "Volume and surface integrals of triangle meshes; the clean-solid pass.", bind_integrals);
    add(m, "topology", "Welding, merging and compaction of mesh vertices; edge topology.", bind_topology);
    add(m, "selfcross", "Self-crossing search of closed shells and the cell proof.", bind_selfcross);
    add(m, "text", "ASCII STL and OBJ readers.", bind_text);
    add(m, "robust", "Robust solids of imperfect meshes: winding numbers, cuts, pieces, caps.", bind_robust);
    add(m, "dynamics", "Free rigid-body integrators and rollouts.", bind_dynamics);
    add(m, "principal", "Principal moments and axes in canonical form.", bind_principal);
    bind_isa(m);  // the private hooks of dispatch.cpp: _isa, _isas, _force_isa
    // one kernel of winding numbers (selfcross's), reachable from integrals until its wrapper goes
    m.attr("integrals").attr("winding_numbers") = m.attr("selfcross").attr("winding_numbers");
}

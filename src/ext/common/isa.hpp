// Kernels compiled once per instruction set.  CMakeLists.txt compiles the hot translation units
// (dynamics/rollout_kernels.cpp, integrals/kernels.cpp) several times, each with its own -march
// and -DINERTIA_ISA=<tag>; every header those units include that defines code opens
// INERTIA_ISA_BEGIN inside its namespace, so each compilation's functions (and the std templates
// instantiated on its types) carry their own names, inertia::isa_<tag>::..., and the linker never
// merges an AVX-512 copy with the baseline one.  Without INERTIA_ISA (every other unit) the
// macros are empty.  The units so compiled include no nanobind and no errors.hpp: they report
// bad input by a return value, and the caller, compiled once, raises.
//
// dispatch.cpp picks one table of entry points by the CPU's features (never by timing) at the
// first call; every variant gives the same bits (-ffp-contract=off everywhere).
#pragma once

#define INERTIA_CAT_(a, b) a##b
#define INERTIA_CAT(a, b) INERTIA_CAT_(a, b)

#if defined(INERTIA_ISA)
#define INERTIA_ISA_BEGIN inline namespace INERTIA_CAT(isa_, INERTIA_ISA) {
#define INERTIA_ISA_END }
#else
#define INERTIA_ISA_BEGIN
#define INERTIA_ISA_END
#endif

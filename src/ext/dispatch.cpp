// The choice among the variants of the hot kernels (common/isa.hpp): CMake lists the variants
// this build compiled as INERTIA_VARIANTS, X(tag) for each, lowest first (x86_64, x86_64_v3,
// x86_64_v4 in a portable x86-64 build; native, INERTIA_ARCH's, or generic alone otherwise).
// At the first call of a kernel the highest variant the CPU runs is taken, by its features alone
// (cpuid through __builtin_cpu_supports, which also checks that the OS saves the AVX registers),
// never by timing; every variant gives the same bits.  This choice is the one piece of mutable
// global state of the module.
//
// Private test hooks, on inertia._ext: _isa() the variant in use, _isas() every variant of the
// build and whether this CPU runs it, _force_isa(name) to run another (tests/test_isa.py).
#include <nanobind/nanobind.h>
#include <nanobind/stl/string.h>

#include <atomic>
#include <stdexcept>
#include <string>

#include "common/isa.hpp"
#include "dynamics/rollout.hpp"
#include "integrals/kernels.hpp"

namespace nb = nanobind;

#ifndef INERTIA_VARIANTS
#error "CMakeLists.txt defines INERTIA_VARIANTS"
#endif

// each variant's tables, defined in its compilation of integrals/kernels.cpp and dynamics/rollout_kernels.cpp
#define X(tag)                                                             \
    namespace inertia {                                                    \
    extern const IntegralKernels integral_kernels_##tag;                   \
    namespace dynamics {                                                   \
    extern const RolloutKernels rollout_kernels_##tag;                     \
    }                                                                      \
    }
INERTIA_VARIANTS
#undef X

namespace inertia {

namespace {

struct Variant {
    const char *tag;  // its name is the tag with '-' for '_': x86-64-v3, the -march it was built for
    const IntegralKernels *integrals;
    const dynamics::RolloutKernels *rollout;
};

#define X(tag) {#tag, &integral_kernels_##tag, &dynamics::rollout_kernels_##tag},
constexpr Variant VARIANTS[] = {INERTIA_VARIANTS};
#undef X
constexpr size_t N_VARIANTS = sizeof(VARIANTS) / sizeof(VARIANTS[0]);

std::string name_of(const Variant &v) {
    std::string s = v.tag;
    for (char &c : s)
        if (c == '_') c = '-';
    return s;
}

// The features -march=x86-64-vN may use (GCC's and Clang's lists of the psABI levels).
#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
bool cpu_has(const char *f) {
    __builtin_cpu_init();
    const std::string s = f;
    if (s == "v2")
        return __builtin_cpu_supports("popcnt") && __builtin_cpu_supports("sse3") &&
               __builtin_cpu_supports("ssse3") && __builtin_cpu_supports("sse4.1") &&
               __builtin_cpu_supports("sse4.2");
    if (s == "v3")
        return cpu_has("v2") && __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2") &&
               __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("fma");
    if (s == "v4")
        return cpu_has("v3") && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512vl");
    return true;
}
#else
bool cpu_has(const char *) { return true; }
#endif

// Whether this CPU runs variant v: x86_64_vN needs level N; the others need what the module does.
bool runs(const Variant &v) {
    const std::string tag = v.tag;
    for (const char *level : {"v2", "v3", "v4"})
        if (tag == std::string("x86_64_") + level) return cpu_has(level);
    return true;
}

std::atomic<const Variant *> chosen{nullptr};

const Variant &current() {
    const Variant *v = chosen.load(std::memory_order_acquire);
    if (v) return *v;
    const Variant *best = &VARIANTS[0];
    for (size_t i = 1; i < N_VARIANTS; ++i)
        if (runs(VARIANTS[i])) best = &VARIANTS[i];
    chosen.compare_exchange_strong(v, best, std::memory_order_acq_rel);  // a racing first call chose the same
    return *chosen.load(std::memory_order_acquire);
}

}  // namespace

const IntegralKernels &integral_kernels() { return *current().integrals; }

namespace dynamics {
const RolloutKernels &rollout_kernels() { return *current().rollout; }
}  // namespace dynamics

}  // namespace inertia

void bind_isa(nb::module_ &m) {
    using namespace inertia;
    m.def("_isa", [] { return name_of(current()); },
          "Private (tests): the variant of the hot kernels in use, e.g. 'x86-64-v4', or 'native' in a build "
          "tuned for its machine.");
    m.def("_isas", [] {
        nb::dict out;
        for (const Variant &v : VARIANTS) out[nb::str(name_of(v).c_str())] = runs(v);
        return out;
    }, "Private (tests): every variant of the hot kernels this build holds, lowest first, and whether this CPU "
       "runs it.");
    m.def("_force_isa", [](const std::string &name) {
        for (const Variant &v : VARIANTS) {
            if (name_of(v) != name) continue;
            if (!runs(v)) {
                std::string ok;
                for (const Variant &w : VARIANTS)
                    if (runs(w)) ok += (ok.empty() ? "" : ", ") + name_of(w);
                throw std::runtime_error("this CPU lacks the instructions of the " + name +
                                         " kernels (cpuid); it runs " + ok);
            }
            const std::string before = name_of(current());
            chosen.store(&v, std::memory_order_release);
            return before;
        }
        std::string held;
        for (const Variant &v : VARIANTS) held += (held.empty() ? "" : ", ") + name_of(v);
        throw nb::value_error(("no kernels named '" + name + "' in this build; it holds: " + held).c_str());
    }, nb::arg("name"),
       "Private (tests): run the hot kernels of variant `name` from now on (every thread); returns the name of "
       "the variant used before.  ValueError when the build holds no such variant, RuntimeError when this CPU "
       "lacks its instructions.");
}

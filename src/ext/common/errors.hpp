// Errors of the compiled core.  A kernel throws inertia::Error; the module's translator
// (module.cpp) raises it in Python as the class of inertia._core.errors that `kind` names,
// with its stable `code`, so a caller sees InputError("...", code="invalid_input") and never
// a C++ exception.
#pragma once
#include <stdexcept>
#include <string>

namespace inertia {

struct Error : std::runtime_error {
    std::string kind;  // class name in inertia._core.errors: InputError, MeshFileError, ...
    std::string code;  // stable code, e.g. "invalid_input", "malformed"
    Error(std::string kind_, std::string code_, const std::string &message)
        : std::runtime_error(message), kind(std::move(kind_)), code(std::move(code_)) {}
};

// A bad argument: wrong length, index out of range, count that does not fit.
[[noreturn]] inline void input_error(const std::string &message) {
    throw Error("InputError", "invalid_input", message);
}

}  // namespace inertia

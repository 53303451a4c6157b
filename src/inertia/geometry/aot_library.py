"""The kernels compiled ahead of time (:mod:`inertia._core.aot`), with the argument types
they are compiled for, and the build.  The table holds every kernel the mesh-file path calls from
Python (reading, welding, checks, winding numbers, the self-crossing search): the whole of a
row of ``inertia batch`` or ``inertia props``.  Any other kernel, or a call with other
types, runs on numba as before (compiled then if numba's cache is cold).  Importing
this module does not import numba (the build does).

Types in numba's notation: ``f8[:,::1]`` a C-contiguous 2-D float64 array, ``u4[:,:,:]`` a
3-D uint32 array of any strides, ``i8`` an int64 scalar; ``!`` marks an array the kernel
writes (a call with a read-only one goes to numba, which refuses it as before).
"""

from __future__ import annotations

import os

from .._core import aot
from .._core.errors import InertiaError

EXPORTS = {
    "inertia.geometry._topology_numba": {
        "stl_weld_and_merge": "u4[:,:,:], f8",
        "weld_and_merge": "f8[:,::1], i8[:,::1], f8",
        "weld_map": "f8[:,::1]",
        "weld_compact": "f8[:,::1], i8[:,::1]",
        "clean_solid": "f8[:,::1], i8[:,::1], f8, f8, f8[::1]!, i8[:,::1]!",
        "winding_numbers": "f8[:,::1], f8[:,:,::1]",
    },
    "inertia.geometry._text_numba": {
        "read_ascii_stl": "u1[::1], f8[:,::1]!, i8[:,::1]!, i8",
        "read_obj": "u1[::1], i8",
        "gather_tokens": "u1[::1], i8[:,::1]",
    },
}


def build(exports: dict | None = None) -> str:
    """Compile the kernels of ``exports`` (default :data:`EXPORTS`; ``{module: {function:
    argument types}}``) with ``numba.pycc`` into the library of :mod:`inertia._core.aot`
    (about a minute); returns its path.  Built in a temporary folder beside it, then moved in
    place.  On failure the error is raised, and noted so that it is not retried for the same
    sources.

    The compilation runs in a child process whose numba cache is an empty folder (inside the
    temporary one).  Numba's on-disk cache is keyed by each function's own source file: a
    cached kernel keeps the code of the kernels it calls from other modules as they were when
    it was compiled, so a library built from the cache could hold an earlier version of a
    kernel whose module changed since (an edited checkout, a checkout of another commit).
    Compiled afresh, the library holds the sources its digest names."""
    import shutil
    import tempfile

    exports = EXPORTS if exports is None else exports
    folder = os.path.dirname(aot.library_path())
    os.makedirs(folder, exist_ok=True)
    sources = aot.library_sources()          # the kernels, what they import, this table
    stats = aot.source_stats(sources)
    digest = aot.sources_hash(sources)
    _remove_stale_builds(folder)
    tmp = tempfile.mkdtemp(prefix=".build-", dir=folder)
    try:
        _compile_in_child(exports, tmp)
        built = [n for n in os.listdir(tmp) if n.startswith(aot.library_name()) and not n.endswith((".o", ".c"))]
        if len(built) != 1:
            raise InertiaError(f"numba.pycc left {built!r} in {tmp}, not one library", code="internal_error")
        return aot.install(os.path.join(tmp, built[0]), exports, stats, digest)
    except Exception as exc:          # not an interrupt: a Ctrl-C is no reason to give up
        aot.note_failure(digest, exc)
        raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _compile_in_child(exports: dict, folder: str) -> None:
    """Run :func:`compile_into` in a new interpreter (this one's, importing this package)
    with ``NUMBA_CACHE_DIR`` an empty folder in ``folder``; its error, if any, is raised here."""
    import json
    import subprocess
    import sys

    package_parent = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    path = os.environ.get("PYTHONPATH")
    env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(folder, "numba-cache"),
               PYTHONPATH=package_parent + (os.pathsep + path if path else ""))
    code = "import sys, json; from inertia.geometry.aot_library import compile_into; " \
           "compile_into(json.loads(sys.stdin.read()), sys.argv[1], sys.argv[2])"
    done = subprocess.run([sys.executable, "-c", code, folder, aot.build_target()], input=json.dumps(exports),
                          text=True, capture_output=True, env=env)
    if done.returncode != 0:
        lines = [line for line in done.stderr.strip().splitlines() if line.strip()]
        raise InertiaError(f"compiling the ahead-of-time library failed (exit {done.returncode}): "
                           f"{lines[-1] if lines else 'no message'}", code="internal_error")


def compile_into(exports: dict, folder: str, target: str = "") -> None:
    """Compile the kernels of ``exports`` with ``numba.pycc`` into a library in ``folder``
    (this process: :func:`build` calls it in a child with an empty numba cache), for the CPU
    ``target`` (:func:`inertia._core.aot.build_target`: "" the architecture's generic CPU,
    ``host`` this one with the features numba's own compiler uses here, or a CPU name)."""
    import importlib
    import warnings

    from numba.core.sigutils import _parse_signature_string

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # pycc's deprecation notice
        from numba.pycc import CC

        cc = CC(aot.library_name())
        cc.output_dir = folder
        cc.verbose = False
        cc.target_cpu = target if target != "host" or _use_host_features() else ""
        for module_name, functions in exports.items():
            module = importlib.import_module(module_name)
            for name, spec in functions.items():
                dispatcher = getattr(module, name)
                args = tuple(_parse_signature_string(f"({spec.replace('!', '')},)"))
                dispatcher.compile(args)         # numba infers the return type
                sig = dispatcher.overloads[args].signature
                cc.export(aot.exported_name(module_name, name), sig)(dispatcher.py_func)
        cc.compile()


def _use_host_features() -> bool:
    """Make pycc compile with this CPU's features as numba detects them for its own code (pycc
    alone names the CPU model, whose features a virtual machine may not all offer); False
    when this numba lacks the hooks: the caller then compiles for the generic CPU (slower
    code, never an instruction this CPU lacks)."""
    try:
        from numba.core import codegen

        features = codegen.get_host_cpu_features()
        if not isinstance(features, str) or not hasattr(codegen.AOTCPUCodegen, "_customize_tm_features"):
            return False
        codegen.AOTCPUCodegen._customize_tm_features = lambda self: features
    except Exception:  # noqa: BLE001 - an internal API changed
        return False
    return True


def _remove_stale_builds(folder: str, age_s: float = 3600.0) -> None:
    """Remove the temporary folders of builds that were killed (older than ``age_s``)."""
    import shutil
    import time

    for name in os.listdir(folder):
        path = os.path.join(folder, name)
        try:
            if name.startswith(".build-") and time.time() - os.path.getmtime(path) > age_s:
                shutil.rmtree(path, ignore_errors=True)
        except OSError:
            pass

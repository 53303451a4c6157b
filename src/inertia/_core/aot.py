"""Kernels compiled ahead of time into one shared library: a process that uses them never
imports numba.

A command-line process that reads a mesh pays 0.3-0.4 s before its first kernel runs when the
kernels come from numba: importing numba (0.12 s) and loading the cached machine code (numba
initialises its whole compiler target on the first load, 0.25 s).  For ``inertia batch``,
whose work on 500 small meshes takes about a second, that is a third of the run.  The same
kernels compiled ahead of time by ``numba.pycc`` load in under a millisecond and run at the
same speed (measured on the self-crossing search: 1.86 vs 1.84 ms a 5.5k-face mesh).

* :func:`inertia.geometry.aot_library.build` compiles the kernels its table names into the
  user's cache folder (:func:`cache_dir`), for this machine's CPU with the features numba's
  own compiler uses here (where Linux names the CPU; elsewhere, or with
  ``NUMBA_CPU_NAME=generic``, for the architecture's generic CPU).  The library's name holds
  a hash of the CPU's model and feature flags (:func:`cpu_key`), so machines of other CPUs
  that share a home folder each build and load their own.  :func:`install` puts it in place
  with a manifest: the argument types, and the size, time and a hash of every module of
  the layers the kernels live in and import (:data:`SOURCE_FOLDERS`).  The build runs in
  the background warm-up (``python -m inertia.cli.warmup``) and in
  ``inertia warm-up``; it needs a C compiler and setuptools, and when it fails it leaves a
  note (:func:`note_failure`) so that it is not retried for the same sources.
* :func:`kernels` gives, for a kernel module, an object whose functions are those of the
  library: valid only while every source it was built from is unchanged, for the same NumPy,
  and while numba is installed (a call the library cannot take goes to numba).
  A pycc function does not check its arguments (an int32 array where int64 is compiled is
  read as garbage, a read-only output is written), so each call checks them against the
  manifest first (about 1 us; an output is marked ``!`` and must be writeable), and a
  call that does not match, or a function the library lacks, goes to the numba kernel
  (importing numba then).  The library's functions hold the GIL: a caller that runs kernels
  in threads asks for numba's (``kernels(..., ahead_of_time=False)`` in :mod:`.compiled`).
  Its numbers equal numba's to rounding.  Compiled for the generic x86-64 CPU, the integrals
  pass (``clean_solid``) ran 20-30 % slower than numba's code, the weld 6 % (no vector
  instructions beyond SSE2, no fused multiply-adds): hence the host build.

``INERTIA_COMPILED=always`` or ``never`` bypass the library (:mod:`.compiled`).
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import json
import os
import sys
import zlib

from .atomic import write_text_atomic
from .errors import InertiaError

_DTYPES = {"f8": "float64", "f4": "float32", "i8": "int64", "i4": "int32", "u4": "uint32", "u1": "uint8",
           "b1": "bool"}
_state: dict = {}            # "library": (module, manifest) or None once looked for


def cache_dir() -> str:
    """``INERTIA_CACHE_DIR``, else the platform's user cache folder + ``inertia``."""
    env = os.environ.get("INERTIA_CACHE_DIR")
    if env:
        return os.path.abspath(os.path.expanduser(env))
    if sys.platform == "win32":
        base = os.environ.get("LOCALAPPDATA") or os.path.expanduser("~")
        return os.path.join(base, "inertia", "cache")
    if sys.platform == "darwin":
        return os.path.join(os.path.expanduser("~"), "Library", "Caches", "inertia")
    return os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
                        "inertia")


def _package_dir() -> str:
    return os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def library_name() -> str:
    """The library's module name: one per installation (its folder) and CPU (:func:`cpu_key`),
    so installs do not clash, nor machines of other CPUs that share the cache folder."""
    name = f"inertia_kernels_{zlib.crc32(_package_dir().encode()):08x}"
    key = cpu_key()
    return name if key == "generic" else f"{name}_{zlib.crc32(key.encode()):08x}"


def build_target() -> str:
    """The CPU the library is compiled for: numba's ``NUMBA_CPU_NAME`` when set (``generic``
    for a build any CPU of the architecture runs), else ``host`` where :func:`cpu_key` can tell
    this CPU from others (Linux), else the architecture's generic CPU ("")."""
    key = cpu_key()
    if key == "generic":
        return ""
    return key.split(":")[1] if key.startswith("numba:") else "host"


def cpu_key() -> str:
    """What a library compiled for this machine runs on: ``generic`` (any CPU of the
    architecture), or a text naming this CPU (``NUMBA_CPU_NAME`` and ``NUMBA_CPU_FEATURES``, or
    the model and feature flags Linux reports for the first processor).  Read once."""
    key = _state.get("cpu_key")
    if key is None:
        key = _state["cpu_key"] = _cpu_key()
    return key


def _cpu_key(cpuinfo: str = "/proc/cpuinfo") -> str:
    name = os.environ.get("NUMBA_CPU_NAME", "").strip()
    if name:
        return "generic" if name == "generic" else f"numba:{name}:{os.environ.get('NUMBA_CPU_FEATURES', '')}"
    if not sys.platform.startswith("linux"):
        return "generic"
    model = flags = None
    try:
        with open(cpuinfo, encoding="utf-8", errors="replace") as fh:
            for line in fh:                       # the first processor's block
                field, _, value = line.partition(":")
                field = field.strip()
                if field in ("model name", "cpu model", "CPU part") and model is None:
                    model = value.strip()
                elif field in ("flags", "Features") and flags is None:
                    flags = " ".join(sorted(value.split()))
                elif not line.strip() and (model or flags):
                    break
    except OSError:
        return "generic"
    if not flags:
        return "generic"
    return f"{os.uname().machine}:{model or ''}:{flags}"


def library_path() -> str:
    return os.path.join(cache_dir(), "aot", library_name() + importlib.machinery.EXTENSION_SUFFIXES[0])


def _manifest_path() -> str:
    return library_path() + ".json"


def _failed_path() -> str:
    return library_path() + ".failed"


def _digest(path: str) -> str:
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def sources_hash(files) -> str:
    """One hash of the contents of the named source files (relative to the package), in order."""
    h = hashlib.sha256()
    for rel in files:
        h.update(rel.encode() + b"\0" + _digest(os.path.join(_package_dir(), rel)).encode() + b"\0")
    return h.hexdigest()


#: the folders whose modules the kernels are (or import: constants of the reference readers,
#: tolerances), with the table and this loader: a library built from other versions of any
#: of them is stale
SOURCE_FOLDERS = ("_core", "geometry")


def library_sources() -> list[str]:
    """The sources a library depends on (see :data:`SOURCE_FOLDERS`), relative, sorted."""
    root = _package_dir()
    found = []
    for sub in SOURCE_FOLDERS:
        folder = os.path.join(root, sub)
        for name in os.listdir(folder):
            if name.endswith(".py"):
                found.append(f"{sub}/{name}")
    return sorted(found)


def source_stats(files) -> dict:
    """``{file: [size, mtime_ns]}``: the quick check that files are as they were."""
    out = {}
    for rel in files:
        st = os.stat(os.path.join(_package_dir(), rel))
        out[rel] = [st.st_size, st.st_mtime_ns]
    return out


def parse_types(spec: str) -> list[tuple]:
    """``"f8[:,::1], i8[::1]!, i8"`` -> ``[("array", "float64", 2, True, False), ("array",
    "int64", 1, True, True), ("scalar", "int64")]``: each argument an array (dtype,
    dimensions, C-contiguous required, written by the kernel: marked ``!``) or a scalar."""
    out = []
    for item in _split(spec):
        written = item.endswith("!")
        code, _, dims = item.rstrip("!").partition("[")
        dtype = _DTYPES[code.strip()]
        if not dims:
            out.append(("scalar", dtype))
            continue
        axes = dims.rstrip("]").split(",")
        out.append(("array", dtype, len(axes), axes[-1].strip() == "::1", written))
    return out


def _split(spec: str) -> list[str]:
    items, depth, cur = [], 0, ""
    for ch in spec:
        if ch == "," and depth == 0:
            items.append(cur.strip())
            cur = ""
            continue
        depth += (ch == "[") - (ch == "]")
        cur += ch
    if cur.strip():
        items.append(cur.strip())
    return items


def _checker(kind):
    """A one-argument test for ``kind`` (a :func:`parse_types` item): the argument is exactly
    what the compiled function reads (see the module docstring).  The dtype is made once, so
    a guarded call costs a few hundred ns an argument."""
    import numpy as np

    if kind[0] == "scalar":
        if kind[1] == "bool":
            return lambda arg: isinstance(arg, (bool, np.bool_))
        if kind[1] == "float64":
            return lambda arg: isinstance(arg, (int, float, np.integer, np.floating)) and not isinstance(
                arg, (bool, np.bool_))
        if kind[1] == "int64":
            return lambda arg: (isinstance(arg, (int, np.integer)) and not isinstance(arg, (bool, np.bool_))
                                and -2**63 <= arg < 2**63)
        return lambda arg: False
    dtype, ndim, contiguous, writeable = np.dtype(kind[1]), kind[2], kind[3], kind[4]
    ndarray = np.ndarray

    def accepts(arg) -> bool:
        if not isinstance(arg, ndarray) or arg.dtype != dtype or arg.ndim != ndim or not arg.dtype.isnative:
            return False
        if contiguous or writeable:
            flags = arg.flags
            return (not contiguous or flags.c_contiguous) and (not writeable or flags.writeable)
        return True
    return accepts


class _Kernels:
    """The library's functions of one kernel module (see the module docstring).  They hold
    the GIL (pycc does not release it): a caller that runs kernels in threads asks for the
    numba module instead (``holds_gil``)."""

    holds_gil = True

    def __init__(self, module_name: str, library, functions: dict):
        self._module_name = module_name
        for name, spec in functions.items():
            fast = getattr(library, exported_name(module_name, name))
            setattr(self, name, self._guarded(name, fast, parse_types(spec)))

    def _guarded(self, name, fast, kinds):
        checks = tuple(_checker(k) for k in kinds)
        n = len(checks)

        def call(*args):
            if len(args) == n:
                for check, arg in zip(checks, args):
                    if not check(arg):
                        break
                else:
                    return fast(*args)
            return getattr(self._numba(), name)(*args)
        call.__name__ = name
        call.__doc__ = f"{self._module_name}.{name}, compiled ahead of time (see inertia._core.aot)"
        return call

    def _numba(self):
        import importlib

        return importlib.import_module(self._module_name)

    def __getattr__(self, name):      # a function (or constant) the library does not hold
        if name.startswith("__") or name == "holds_gil":
            raise AttributeError(name)
        return getattr(self._numba(), name)


def exported_name(module_name: str, function: str) -> str:
    return module_name.rsplit(".", 1)[-1].strip("_") + "__" + function


def load():
    """``(library module, manifest)``, or None (absent, stale, built for another NumPy, or
    not loadable); looked for once per process."""
    if "library" in _state:
        return _state["library"]
    _state["library"] = None
    try:
        with open(_manifest_path(), encoding="utf-8") as fh:
            manifest = json.load(fh)
        import numpy as np

        if (manifest.get("numpy") != np.__version__ or manifest.get("library") != os.path.basename(library_path())
                or manifest.get("cpu", "generic") != cpu_key()):
            return None
        # the same sources (a new or removed one makes it stale), each unchanged: as it was
        # (size and time, like a .pyc), or else of the same contents (a reinstall)
        files = library_sources()
        if sorted(manifest["sources"]) != files:
            return None
        if source_stats(files) != manifest["sources"] and sources_hash(files) != manifest.get("hash"):
            return None
        spec = importlib.util.spec_from_file_location(library_name(), library_path())
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    except Exception:  # noqa: BLE001 - absent, unreadable or broken: the numba kernels serve
        return None
    _state["library"] = (module, manifest)
    return _state["library"]


def kernels(module_name: str):
    """The library's functions of ``module_name`` (an object with the module's function
    names), or None when the library is absent, stale, or holds nothing of that module."""
    cached = _state.get(("kernels", module_name))
    if cached is not None or ("kernels", module_name) in _state:
        return cached
    lib = load()
    result = None
    if lib is not None and module_name in lib[1]["exports"]:
        try:
            result = _Kernels(module_name, lib[0], lib[1]["exports"][module_name])
        except AttributeError:        # a manifest naming a function the library lacks
            result = None
    _state[("kernels", module_name)] = result
    return result


def wanted() -> bool:
    """No usable library yet, none has failed to build for these sources, and the cache
    folder can be written: the warm-up should build one."""
    if load() is not None or not _writable(os.path.dirname(library_path())):
        return False
    try:
        with open(_failed_path(), encoding="utf-8") as fh:
            return fh.readline().strip() != sources_hash(library_sources())
    except OSError:
        return True


def _writable(folder: str) -> bool:
    """``folder`` exists and can be written, or could be made (its nearest existing parent
    can be written)."""
    while folder and not os.path.exists(folder):
        parent = os.path.dirname(folder)
        if parent == folder:
            return False
        folder = parent
    return os.path.isdir(folder) and os.access(folder, os.W_OK | os.X_OK)


def install(built: str, exports: dict, sources: dict, digest: str) -> str:
    """Move the library file ``built`` (compiled for ``exports`` from ``sources``, as
    :func:`source_stats` gives them, whose contents hash to ``digest``) into place with its
    manifest, the manifest last: a library without its manifest is never loaded.  Returns
    the library's path."""
    import numpy as np

    target = library_path()
    manifest = {"library": os.path.basename(target), "numpy": np.__version__, "cpu": cpu_key(),
                "target": build_target(), "sources": sources, "hash": digest, "exports": exports}
    if os.path.exists(_manifest_path()):
        os.unlink(_manifest_path())
    os.replace(built, target)
    write_text_atomic(_manifest_path(), json.dumps(manifest, indent=1))
    if os.path.exists(_failed_path()):
        os.unlink(_failed_path())
    _state.clear()
    return target


def note_failure(sources_hash: str, error: BaseException) -> None:
    """Remember that a build failed for these sources (:func:`wanted` then says no)."""
    try:
        write_text_atomic(_failed_path(), sources_hash + "\n" + f"{type(error).__name__}: {error}\n")
    except (OSError, InertiaError):    # an unwritable cache folder: wanted() says no anyway
        pass

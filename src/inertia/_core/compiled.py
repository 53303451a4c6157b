"""When to run the compiled (numba) kernels, and when the NumPy path instead.

Every compiled kernel has a NumPy twin that gives the same answers (tests compare them), so the
choice is only about time.  Three costs decide it:

* importing numba and loading a cached kernel: about 0.2-0.4 s, once per process;
* compiling a kernel whose cache is cold (a fresh install): 5-30 s;
* the NumPy path: about 0.6 us per face of a mesh (measured at 1k-1.3M faces).

The rule (``INERTIA_COMPILED=auto``, the default):

1. A process that has not imported numba yet runs small jobs on the NumPy path: a one-shot
   ``inertia props part.stl`` never pays for numba.  Once the process has spent
   :data:`IMPORT_SECONDS` of CPU time since its first NumPy-path job (about what the import
   and the kernels' loading cost), or one job is larger than :data:`IMPORT_WORK`, numba is
   imported.
2. A kernel whose machine code is not in numba's cache is not compiled in the caller's time:
   the NumPy path runs, and a background process (``python -m inertia.cli.warmup``, detached, at
   low priority, one at a time) compiles every kernel into the cache.  Later calls, in this
   process or the next, find the cache warm.
3. Otherwise the compiled kernel runs.

Before all three, kernels compiled ahead of time (:mod:`.aot`: one shared library in the
user's cache folder, built by the background warm-up) serve whatever they hold: they load in
a millisecond, without numba.

``INERTIA_COMPILED=always`` compiles on first use and waits (the behaviour before this rule);
``never`` keeps every call on the NumPy path.  Either way the numbers are the same.
"""

from __future__ import annotations

import importlib
import os
import sys
import time

from . import aot

#: one job this large (faces, or body-steps; callers scale it by their NumPy cost) goes
#: compiled at once: the NumPy path costs ~0.6 us a face, numba's import and a load ~0.25 s
IMPORT_WORK = 400_000
#: CPU seconds a process spends after its first NumPy-path job before it imports numba: about
#: twice what the import and loading the mesh kernels from the cache cost (0.2 + ~0.3 s), since
#: the process clock also counts work that is not NumPy-path (reading XML, Python); the
#: ski-rental rule then stays within ~3x the better choice in hindsight.  Checking Menagerie's
#: tiago (34 meshes): 0.71 s all-NumPy, 0.94-1.13 s switching after 0.3-0.5 s.
IMPORT_SECONDS = 1.0

_MODES = ("auto", "always", "never")
_numpy_since = None        # process CPU time at the first NumPy-path job (numba not imported)
_expect_much = False       # the caller has announced more work than the import costs (prefer_compiled)
_checked: dict = {}        # module name -> (time of the last cache check, module or None)
_RECHECK_S = 5.0           # a cold cache is looked at again after this long (the warm-up may be done)
_warmup_started = False
_library_checked = False
_numba_found = None        # numba_available(), once looked for


def mode() -> str:
    """``INERTIA_COMPILED`` (auto, always or never); anything else is read as auto."""
    m = os.environ.get("INERTIA_COMPILED", "auto").strip().lower()
    return m if m in _MODES else "auto"


def prefer_compiled() -> None:
    """Announce that this process has much work ahead (a batch of thousands of meshes): the
    rule then imports numba at the first job instead of waiting for the NumPy paths to pay
    for it (with ``auto``; ``never`` still means never)."""
    global _expect_much
    _expect_much = True


def numba_available() -> bool:
    """numba can be imported (checked without importing it when possible; once per process)."""
    global _numba_found
    if "numba" in sys.modules:
        return sys.modules["numba"] is not None
    if _numba_found is None:
        import importlib.util

        try:
            _numba_found = importlib.util.find_spec("numba") is not None
        except (ImportError, ValueError):
            _numba_found = False
    return _numba_found


def kernels(module_name: str, *, work: int = 0, ahead_of_time: bool = True):
    """The compiled kernel module ``module_name``, or None when the NumPy path should run.

    ``work`` is the size of the job (faces, body-steps); the kernels the module's
    ``WARM_PROBE`` names show whether it is warm.  See the module docstring for the rule.
    ``ahead_of_time=False``: numba's kernels even where the library has them (they release
    the GIL, for callers that run them in threads).
    """
    global _numpy_since
    m = mode()
    if m == "never":
        return None
    if ahead_of_time:
        ready = _library_kernels(module_name, m)
        if ready is not None:
            return ready
    if m == "auto" and "numba" not in sys.modules and not _expect_much:
        now = time.process_time()
        if _numpy_since is None:
            _numpy_since = now
        if work < IMPORT_WORK and now - _numpy_since < IMPORT_SECONDS:
            return None
    seen = _checked.get(module_name)
    if seen is not None and seen[1] is not None:
        return seen[1]             # warm, seen before: the common case, a few hundred ns
    try:
        module = importlib.import_module(module_name)
    except ImportError:            # numba missing or broken: the NumPy path
        return None
    if m == "always":
        return module
    now = time.monotonic()
    if seen is not None and now - seen[0] < _RECHECK_S:
        return seen[1]
    warm = _is_cached(module)
    _checked[module_name] = (now, module if warm else None)
    if not warm or _library_wanted():
        start_warmup()
    return module if warm else None


def _library_wanted() -> bool:
    """The ahead-of-time library (:mod:`.aot`) is missing or stale and may be built (checked
    once per process): the background warm-up then builds it."""
    global _library_checked
    if _library_checked or _warmup_started:
        return False
    _library_checked = True
    return aot.wanted()


def ahead_of_time_kernels(module_name: str):
    """The kernels of ``module_name`` from the ahead-of-time library (:mod:`.aot`) when
    :func:`kernels` takes them (``auto``, numba installed: a call the library cannot take
    goes to it), else None."""
    return _library_kernels(module_name, mode())


def _library_kernels(module_name: str, m: str):
    """:func:`ahead_of_time_kernels` in the mode ``m`` already read."""
    if m != "auto" or not numba_available():
        return None
    return aot.kernels(module_name)   # no numba to import or load


def is_cached(dispatcher, *, unknown: bool = True) -> bool:
    """A numba kernel is ready without compiling: compiled in this process already, or its
    machine code is in numba's on-disk cache for the current source (read through numba's
    private cache index; ``unknown`` is the answer when that API is not there)."""
    try:
        if dispatcher.signatures:
            return True
        return bool(dispatcher._cache._cache_file._load_index())
    except Exception:  # noqa: BLE001 - a numba without these internals, or not a dispatcher
        return unknown


def _is_cached(module) -> bool:
    """Every kernel ``module.WARM_PROBE`` names is ready (see :func:`is_cached`); a numba
    without the cache internals behaves as before: compile on first use."""
    return all(is_cached(getattr(module, name)) for name in getattr(module, "WARM_PROBE", ()))


def start_warmup() -> bool:
    """Start the background compilation of every kernel (once per process, one at a time
    per installation); True if one was started."""
    global _warmup_started
    if _warmup_started or os.environ.get("INERTIA_WARMUP_CHILD"):
        return False
    _warmup_started = True
    import subprocess
    import tempfile
    import zlib

    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    lock = os.path.join(tempfile.gettempdir(), f"inertia-warmup-{zlib.crc32(here.encode()):08x}.lock")
    try:
        if time.time() - os.path.getmtime(lock) < 600:
            return False             # another process is compiling (a lock older than 10 min is stale)
    except OSError:
        pass
    try:
        with open(lock, "w") as fh:
            fh.write(str(os.getpid()))
        env = dict(os.environ, INERTIA_WARMUP_CHILD="1", INERTIA_WARMUP_LOCK=lock)
        subprocess.Popen([sys.executable, "-m", "inertia.cli.warmup"], env=env, stdin=subprocess.DEVNULL,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    except OSError:
        return False
    return True

"""The kernels compiled ahead of time (inertia._core.aot): built once here into a temporary
cache folder, they give the numba kernels' answers (a second compilation of the same source)
to rounding, refuse arguments of other types by handing them to numba (never reading them
as garbage), serve a fresh process without importing numba, and a stale or broken library is
never loaded."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("numba")

from inertia._ext import integrals as _ext  # noqa: E402

from inertia._core import aot  # noqa: E402
from inertia.geometry import aot_library  # noqa: E402

_NO_TWINS = np.empty((0, 3), dtype=np.int64)         # find_crossing finds the edges' twins itself


def _torus(nu=40, nv=16, r=0.35):
    u, w = np.meshgrid(np.linspace(0, 2 * np.pi, nu, endpoint=False), np.linspace(0, 2 * np.pi, nv, endpoint=False),
                       indexing="ij")
    v = np.stack([(1 + r * np.cos(w)) * np.cos(u), (1 + r * np.cos(w)) * np.sin(u), r * np.sin(w)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a, b = i * nv + j, ((i + 1) % nu) * nv + j
    c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return np.ascontiguousarray(v), np.ascontiguousarray(f, dtype=np.int64)


def _stl_bytes(v, f) -> bytes:
    rec = np.zeros(len(f), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = v[f]
    return b"aot test".ljust(80) + len(f).to_bytes(4, "little") + rec.tobytes()


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """The library built into a fresh cache folder (INERTIA_CACHE_DIR) for this module."""
    import importlib.util

    if not (os.environ.get("CC") or any(shutil.which(c) for c in ("cc", "gcc", "clang"))):
        pytest.skip("no C compiler: the ahead-of-time library cannot be built here (numba serves)")
    if importlib.util.find_spec("setuptools") is None:
        pytest.skip("no setuptools: numba.pycc cannot build the ahead-of-time library (numba serves)")
    folder = tmp_path_factory.mktemp("inertia-cache")
    old = os.environ.get("INERTIA_CACHE_DIR")
    os.environ["INERTIA_CACHE_DIR"] = str(folder)
    aot._state.clear()
    try:
        path = aot_library.build()
        yield folder, path
    finally:
        aot._state.clear()
        if old is None:
            os.environ.pop("INERTIA_CACHE_DIR", None)
        else:
            os.environ["INERTIA_CACHE_DIR"] = old


def _both(module_name):
    import importlib

    fast = aot.kernels(module_name)
    assert fast is not None, aot.load()
    return fast, importlib.import_module(module_name)


def _close(a, b):
    if isinstance(a, tuple):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            _close(x, y)
    elif isinstance(a, np.ndarray):
        assert a.shape == b.shape and a.dtype == b.dtype
        if a.dtype.kind == "f":
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-300)
        else:
            np.testing.assert_array_equal(a, b)
    else:
        assert a == b


def test_the_library_gives_the_numba_kernels_answers(library):
    sc_fast, sc_nb = _both("inertia.geometry._selfcross_numba")
    topo_fast, topo_nb = _both("inertia.geometry._topology_numba")
    v, f = _torus()
    crossed = v.copy()
    crossed[0] += np.array([0.0, 0.0, 0.5])          # one vertex pulled through the tube: crossings
    for verts, expect in ((v, 0), (crossed, 1)):
        outs = [np.zeros(2, np.int64), np.zeros(2, np.int64)]
        found = [k.find_crossing(verts, f, _NO_TWINS, 64, 1e-9, o) for k, o in zip((sc_fast, sc_nb), outs)]
        assert found == [expect, expect]
        np.testing.assert_array_equal(outs[0], outs[1])
        assert sc_fast.star_certificate(verts, f, np.zeros(3)) == sc_nb.star_certificate(verts, f, np.zeros(3))
        # the search given the edges' twins answers as when it finds them itself
        twins = np.full((len(f), 3), -1)
        assert _ext.clean_solid(verts, f, 1e-12, 1e60, adj=twins) is not None and (twins >= 0).all()
        assert sc_fast.find_crossing(verts, f, twins, 64, 1e-9, outs[0]) == expect
    soup = np.ascontiguousarray(v[f].reshape(-1, 3))
    soup_f = np.arange(len(soup), dtype=np.int64).reshape(-1, 3)
    _close(topo_fast.weld_and_merge(soup, soup_f, 1e-9), topo_nb.weld_and_merge(soup, soup_f, 1e-9))
    raw = np.frombuffer(_stl_bytes(v, f), dtype=np.uint8)
    corners = raw[84:].reshape(-1, 50)[:, 12:48].copy().view("<u4").reshape(-1, 3, 3)
    strided = np.frombuffer(_stl_bytes(v, f)[84:], dtype=[("n", "<u4", 3), ("c", "<u4", (3, 3)), ("a", "<u2")])["c"]
    for arg in (corners, strided):
        _close(topo_fast.stl_weld_and_merge(arg, 1e-9), topo_nb.stl_weld_and_merge(arg, 1e-9))


def test_the_text_readers_from_the_library_read_what_numba_reads(library):
    fast, nb = _both("inertia.geometry._text_numba")
    v, f = _torus(12, 6)
    v = np.round(v, 6)
    obj = ("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in v) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f))
    raw = np.frombuffer(obj.encode(), dtype=np.uint8)
    got, ref = fast.read_obj(raw, -1), nb.read_obj(raw, -1)
    _close(got, ref)
    assert len(got[2]) == 0                           # no number left to the slow path
    np.testing.assert_allclose(got[0], v, rtol=1e-15, atol=1e-15)   # both read the numbers written
    np.testing.assert_array_equal(got[1], f)


def test_other_argument_types_go_to_numba_not_to_the_library(library):
    fast, nb = _both("inertia.geometry._selfcross_numba")
    v, f = _torus()
    crossed = v.copy()
    crossed[0] += np.array([0.0, 0.0, 0.5])
    out = np.zeros(2, np.int64)
    # int32 faces, Fortran-ordered vertices, a float where an int is compiled: read as garbage
    # (or a crash) by a pycc function; the guard sends them to numba, which gives the answer
    assert fast.find_crossing(crossed, f.astype(np.int32), _NO_TWINS, 64, 1e-9, out) == 1
    assert fast.find_crossing(np.asfortranarray(crossed), f, _NO_TWINS, 64, 1e-9, out) == 1
    assert fast.find_crossing(v, f, _NO_TWINS, 64.0, 1e-9, out) == 0
    # a read-only output: the library would write it; numba refuses it, as it always did
    frozen = np.zeros(2, np.int64)
    frozen.flags.writeable = False
    with pytest.raises(Exception) as theirs:
        nb.find_crossing(crossed, f, _NO_TWINS, 64, 1e-9, frozen)
    with pytest.raises(type(theirs.value)):
        fast.find_crossing(crossed, f, _NO_TWINS, 64, 1e-9, frozen)
    assert not frozen.any()
    assert "numba" in sys.modules
    assert fast.WARM_PROBE == nb.WARM_PROBE          # what the library lacks comes from the module


def _fresh(code: str, cache, **env):
    full = {**os.environ, "INERTIA_COMPILED": "auto", "INERTIA_CACHE_DIR": str(cache), **env}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=full, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_a_fresh_process_reads_a_mesh_file_without_numba(library, tmp_path):
    import inertia
    from tests._make import write_ascii_stl, write_obj

    v, f = _torus(60, 24)
    paths = [tmp_path / "torus.stl", tmp_path / "torus.obj", tmp_path / "torus_ascii.stl"]
    paths[0].write_bytes(_stl_bytes(v, f))
    write_obj(paths[1], v, f)
    write_ascii_stl(paths[2], v[f])
    for path in paths:
        code = ("import json, sys\nimport inertia\nfrom inertia._core import compiled\n"
                "compiled.start_warmup = lambda: False\n"
                f"p = inertia.mesh_file_properties({str(path)!r}, density=1000.0)\n"
                "print(json.dumps({'numba': 'numba' in sys.modules, 'mass': p.mass, 'I': p.inertia_com.tolist(),\n"
                "                  'used': sorted(getattr(sys.modules.get('inertia.geometry._text_readers'), '_compiled_used', ()))}))\n")
        got = _fresh(code, library[0])
        assert not got["numba"], path.name
        # a text file small as this one is read by the compiled reader: the library costs nothing to load
        assert got["used"] == {"torus.stl": [], "torus.obj": ["obj"], "torus_ascii.stl": ["ascii_stl"]}[path.name]
        ref = inertia.mesh_file_properties(path, density=1000.0)     # numba (the suite runs with always)
        assert got["mass"] == pytest.approx(ref.mass, rel=1e-12)
        np.testing.assert_allclose(got["I"], ref.inertia_com, rtol=1e-12, atol=1e-12 * np.abs(ref.inertia_com).max())
        # the torus's volume in closed form, as a sanity: 2 pi^2 R r^2, to the faceting
        assert got["mass"] == pytest.approx(1000.0 * 2 * np.pi ** 2 * 0.35 ** 2, rel=0.02)


def test_a_stale_or_broken_library_is_never_loaded(library, tmp_path):
    folder, path = library
    code = ("import json, sys\nfrom inertia._core import aot\n"
            "print(json.dumps({'loaded': aot.load() is not None, 'wanted': aot.wanted()}))\n")
    assert _fresh(code, folder) == {"loaded": True, "wanted": False}
    copy = tmp_path / "cache"
    shutil.copytree(folder, copy)
    manifest = copy / "aot" / os.path.basename(aot._manifest_path())
    good = json.loads(manifest.read_text())
    assert "geometry/aot_library.py" in good["sources"]     # the table too: a change to it rebuilds
    assert "geometry/_text_reference.py" in good["sources"]  # and what the kernels import
    meta = json.loads(manifest.read_text())
    meta["sources"]["geometry/_selfcross_numba.py"][1] += 1   # a source touched since ...
    manifest.write_text(json.dumps(meta))
    assert _fresh(code, copy) == {"loaded": True, "wanted": False}   # ... with the same contents
    meta["hash"] = "0" * 64                                    # ... with other contents
    manifest.write_text(json.dumps(meta))
    assert _fresh(code, copy) == {"loaded": False, "wanted": True}
    meta = json.loads(json.dumps(good))
    del meta["sources"]["geometry/_selfcross_numba.py"]       # built before a source existed
    manifest.write_text(json.dumps(meta))
    assert _fresh(code, copy) == {"loaded": False, "wanted": True}
    manifest.write_text(json.dumps(good))
    (copy / "aot" / os.path.basename(path)).write_bytes(b"\x7fELF not a library")
    assert _fresh(code, copy)["loaded"] is False     # unloadable: numba serves, nothing crashes
    # a build that failed for these sources is not retried; for other sources it is
    (copy / "aot" / os.path.basename(path)).unlink()
    failed = copy / "aot" / os.path.basename(aot._failed_path())
    failed.write_text(aot.sources_hash(aot.library_sources()) + "\nOSError: no compiler\n")
    assert _fresh(code, copy) == {"loaded": False, "wanted": False}
    failed.write_text("1" * 64 + "\nOSError: no compiler\n")
    assert _fresh(code, copy) == {"loaded": False, "wanted": True}
    # a cache folder that cannot be written: no build is attempted (it would fail every run)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    assert _fresh(code, blocker / "cache") == {"loaded": False, "wanted": False}


def test_parse_types():
    assert aot.parse_types("f8[:,::1], i8[::1]!, u4[:,:,:], i8, f8") == [
        ("array", "float64", 2, True, False), ("array", "int64", 1, True, True),
        ("array", "uint32", 3, False, False), ("scalar", "int64"), ("scalar", "float64")]


def test_an_interrupted_build_is_not_noted_as_failed(tmp_path, monkeypatch):
    """Ctrl-C during a build: the build stops, and is tried again later (no failure note)."""
    monkeypatch.setenv("INERTIA_CACHE_DIR", str(tmp_path / "cache"))
    aot._state.clear()

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(aot_library, "_compile_in_child", interrupted)
    try:
        with pytest.raises(KeyboardInterrupt):
            aot_library.build({"inertia.geometry._topology_numba": {"weld_map": "f8[:,::1]"}})
        assert not os.path.exists(aot._failed_path()) and aot.wanted()
        assert not [n for n in os.listdir(tmp_path / "cache" / "aot") if n.startswith(".build-")]
    finally:
        aot._state.clear()


def test_threaded_callers_and_a_missing_numba_do_not_take_the_library(library, tmp_path, monkeypatch):
    from inertia._core import compiled

    monkeypatch.setenv("INERTIA_COMPILED", "auto")
    name = "inertia.geometry._text_numba"
    assert getattr(compiled.kernels(name), "holds_gil", False)            # the library's, holding the GIL
    assert not getattr(compiled.kernels(name, ahead_of_time=False), "holds_gil", False)   # numba's
    # numba gone after the build: the library is not used (a call it cannot take would need
    # numba), the NumPy path answers, as without the library
    v, f = _torus()
    np.save(tmp_path / "soup.npy", v[f].reshape(-1, 3))
    code = ("import json, sys\nsys.modules['numba'] = None\nimport numpy as np\nimport inertia\n"
            "from inertia._core import compiled\ncompiled.start_warmup = lambda: False\n"
            f"soup = np.load({str(tmp_path / 'soup.npy')!r})\n"
            "p = inertia.mesh_properties(soup, np.arange(len(soup)).reshape(-1, 3), density=1.0)\n"
            "print(json.dumps({'mass': p.mass, 'lib': compiled.kernels('inertia.geometry._topology_numba') is not None}))\n")
    got = _fresh(code, library[0])
    import inertia

    assert not got["lib"]
    assert got["mass"] == pytest.approx(inertia.mesh_properties(v, f, density=1.0).mass, rel=1e-12)


def test_the_library_holds_a_callee_changed_since_numba_cached_its_caller(library, tmp_path, monkeypatch):
    """Numba's cache keys a kernel by its own file: a cached kernel keeps the code of a callee
    from another module as it was (an exported f calls h of its module, which calls g of
    another; g changes).  The build compiles afresh (an empty numba cache in a child process),
    so the library holds g as its source is now; built from the cache it held the old g."""
    import subprocess
    import sys

    package = tmp_path / "stalepkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "callee.py").write_text("import numba\n\n@numba.njit(cache=True)\ndef g(x):\n    return x + 1\n")
    (package / "caller.py").write_text("import numba\nfrom .callee import g\n\n"
                                       "@numba.njit(cache=True)\ndef h(x):\n    return g(x) * 10\n\n"
                                       "@numba.njit(cache=True)\ndef f(x):\n    return h(x)\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    probe = [sys.executable, "-c", "from stalepkg.caller import f; print(f(1))"]
    assert subprocess.run(probe, env=env, capture_output=True, text=True, check=True).stdout.strip() == "20"
    source = (package / "callee.py").read_text().replace("x + 1", "x + 2")
    (package / "callee.py").write_text(source)                  # caller.py untouched: its cache is "valid"
    stale = subprocess.run(probe, env=env, capture_output=True, text=True, check=True).stdout.strip()
    assert stale in ("20", "30")                                # numba's own answer: 20 while it misses the change
    monkeypatch.setenv("PYTHONPATH", env["PYTHONPATH"])
    monkeypatch.setenv("INERTIA_CACHE_DIR", str(tmp_path / "cache"))
    aot._state.clear()
    try:
        path = aot_library.build({"stalepkg.caller": {"f": "i8"}})
        fast = aot.kernels("stalepkg.caller")
        assert fast is not None and os.path.exists(path)
        assert fast.f(1) == 30, f"the library holds the old callee (numba's cached caller gives {stale})"
    finally:
        aot._state.clear()
        sys.modules.pop("stalepkg.caller", None)
        sys.modules.pop("stalepkg.callee", None)
        sys.modules.pop("stalepkg", None)


def test_the_library_is_built_for_this_cpu_and_never_loaded_on_another(library, tmp_path):
    folder, path = library
    manifest = json.loads(open(path + ".json", encoding="utf-8").read())
    assert manifest["cpu"] == aot.cpu_key()
    if aot.cpu_key() != "generic":       # Linux: compiled for this CPU, named by it
        assert manifest["target"] == "host"
        assert os.path.basename(path).startswith(aot.library_name()) and aot.library_name().count("_") == 3
    code = ("import json, sys\nfrom inertia._core import aot\n"
            "print(json.dumps({'loaded': aot.load() is not None, 'name': aot.library_name()}))\n")
    here = _fresh(code, folder)
    assert here["loaded"]
    # another CPU sharing the cache folder (NUMBA_CPU_NAME makes this one count as another):
    # it looks for a library of its own name, and a manifest naming another CPU is never loaded
    other = _fresh(code, folder, NUMBA_CPU_NAME="generic")
    assert other["name"] != here["name"] and not other["loaded"]
    copy = tmp_path / "cache"
    shutil.copytree(folder, copy)
    meta = dict(manifest, cpu=manifest["cpu"] + " avx9000")
    (copy / "aot" / (os.path.basename(path) + ".json")).write_text(json.dumps(meta))
    assert _fresh(code, copy)["loaded"] is False


def test_the_cpu_key_names_the_model_and_flags_of_the_first_processor(tmp_path, monkeypatch):
    monkeypatch.delenv("NUMBA_CPU_NAME", raising=False)
    if not sys.platform.startswith("linux"):
        assert aot._cpu_key() == "generic"
        return
    block = "processor\t: {n}\nmodel name\t: {model}\nflags\t\t: {flags}\n\n"

    def key(*cpus):
        info = tmp_path / "cpuinfo"
        info.write_text("".join(block.format(n=n, model=m, flags=f) for n, (m, f) in enumerate(cpus)))
        return aot._cpu_key(str(info))

    a = key(("EPYC", "fpu sse2 avx2"), ("EPYC", "fpu"))
    assert a == key(("EPYC", "avx2 fpu sse2"))               # the first processor, flags in any order
    assert a != key(("EPYC", "fpu sse2 avx2 avx512f"))      # one more feature: another CPU
    assert a != key(("Xeon", "fpu sse2 avx2"))
    assert key(("EPYC", "")) == "generic"                    # nothing to tell CPUs apart by
    assert aot._cpu_key(str(tmp_path / "absent")) == "generic"
    monkeypatch.setenv("NUMBA_CPU_NAME", "generic")
    assert aot._cpu_key() == "generic"
    monkeypatch.setenv("NUMBA_CPU_NAME", "skylake")
    assert aot._cpu_key().startswith("numba:skylake:")

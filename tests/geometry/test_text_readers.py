"""The ASCII STL and OBJ readers (inertia._ext.text, through geometry._text_readers).

Truths: Python's ``float()`` (correctly rounded, as strtod) for every number; trimesh's own
parsers for the triangles of made and real files; closed-form volumes for polygons, solids
and relative indices; MuJoCo for quadrilaterals split along their shorter diagonal and for its
triangulation of polygons; and a line-by-line reading of the grammar in plain Python (``tests/geometry/_text_oracle.py``:
``bytes.split`` and ``float()``), which the compiled readers must match array for array, and
error for error, on valid and mutated files.
"""

from __future__ import annotations

import hashlib
import json
import random
import subprocess
import sys

import numpy as np
import pytest

import inertia
from inertia.errors import MeshFileError
from inertia.geometry._text_readers import error_message, read_ascii_stl, read_obj
from inertia.geometry.mesh_io import load_mesh
from tests.fuzzing import mutate_any, seed_obj, seed_stl_ascii
from tests.geometry import _text_oracle as oracle


def _read(reader, text: bytes, **kw):
    return reader(np.frombuffer(text, dtype=np.uint8), "t", **kw)


def _outcome(reader, text: bytes):
    """The arrays read (for ASCII STL its facets' corners: a repeated corner is stored once),
    or the error's code and message."""
    try:
        v, f = _read(reader, text)
    except MeshFileError as exc:
        return exc.code, str(exc)
    return (v[f].reshape(-1, 3),) if reader is read_ascii_stl else (v, f)


def _oracle(reader, text: bytes):
    """:func:`_outcome` by the oracle, its error worded by the readers' message table."""
    if reader is read_ascii_stl:
        corners, err = oracle.read_ascii_stl(text)
        arrays, fmt = (corners,), "ASCII STL"
    else:
        v, f, largest, err, _ = oracle.read_obj(text)
        if err is None and largest > len(v):   # a positive index beyond the last vertex: its line
            err = oracle.read_obj(text, len(v))[3]
        arrays, fmt = (v, f), "OBJ"
    if err is None:
        return arrays
    return "malformed", error_message("t", fmt, err.kind, err.line, err.text, err.token, err.count)


def _same(a, b) -> bool:
    if isinstance(a[0], str) or isinstance(b[0], str):
        return a == b
    return all(x.shape == y.shape and np.array_equal(x, y, equal_nan=True) for x, y in zip(a, b))


# ---------------------------------------------------------------- numbers
def _random_number(rng: random.Random) -> str:
    digits = "".join(rng.choice("0123456789") for _ in range(rng.randint(1, 25)))
    point = rng.randint(0, len(digits))
    s = rng.choice(["", "-", "+"]) + digits[:point] + rng.choice([".", ""] if point == len(digits) else ["."]) \
        + digits[point:]
    if rng.random() < 0.5:
        s += rng.choice("eE") + rng.choice(["", "-", "+"]) + str(rng.choice([rng.randint(0, 25), rng.randint(0, 400)]))
    return s


def test_numbers_are_read_as_strtod_reads_them():
    rng = random.Random(7)
    words = [_random_number(rng) for _ in range(6000)] + [
        "0", "-0", ".5", "5.", "+.5e-3", "1e22", "1e23", "9007199254740993", "0.1", "1e-22", "4.9e-324",
        "1.7976931348623157e308", "1e309", "1e-400", "nan", "-inf", "Infinity", "NaN", "123456789012345678901234",
        "0.000000000000000000000000000001", "2.2250738585072011e-308", "1" + "0" * 30,
        # beyond the fast path: exponents past 1e+-22, 19 digits and more, overflow and underflow by a hair
        "1e0000000000000000000000005", "1e-99999999999999999999", "-1e99999999999999999999", "9007199254740993e-3",
        "1.7976931348623158e308", "1.7976931348623159e308", "2.4703282292062327e-324", "-2.4703282292062328e-324",
        "0.0e99999", "-0e-99999", "1.e5", "-.5E-3", "+iNfInItY", "-NAN", "0" * 400 + "1", "0." + "0" * 400 + "1e400",
        "1" * 800, "." + "9" * 800 + "e-5", "1234567890123456789", "12345678901234567890", "9007199254740992e22"]
    words += [repr(x) for x in (np.random.default_rng(3).normal(size=1000) * 10.0 ** np.arange(-150, 150, 0.3)).tolist()]
    words += [f"{x:.6e}" for x in np.random.default_rng(4).normal(size=1000)]
    # 17 digits and more near halfway between two doubles: Eisel-Lemire's hard cases
    words += [repr(rng.uniform(-1, 1) * 10.0 ** rng.randint(-320, 308)) for _ in range(3000)]
    words += [f"{2 * rng.randint(1, 2**53) + 1}e{rng.randint(-40, 40)}" for _ in range(3000)]
    words += [repr(float(rng.randint(1, 2**53)) * 2.0 ** rng.randint(-1070, 960)) for _ in range(3000)]
    text = "".join(f"v {a} {b} {c}\n" for a, b, c in zip(words[::3], words[1::3], words[2::3])).encode()
    v, f = _read(read_obj, text)
    truth = np.array([float(w) for w in words[:3 * (len(words) // 3)]]).reshape(-1, 3)
    assert f.shape == (0, 3) and v.shape == truth.shape
    nan = np.isnan(truth)
    assert np.array_equal(np.isnan(v), nan)
    assert np.array_equal(v[~nan].view(np.int64), truth[~nan].view(np.int64))   # bit for bit, signs of 0 too


# ---------------------------------------------------------------- the same triangles as trimesh
def _triangles(v, f):
    """The triangles as sorted tuples of corner coordinates, each starting at its smallest corner
    (same winding): equal for two readers that give the same surface in any vertex or face order."""
    out = []
    for tri in np.asarray(v)[np.asarray(f)].tolist():
        rots = [tuple(map(tuple, tri[k:] + tri[:k])) for k in range(3)]
        out.append(min(rots))
    return sorted(out)


@pytest.mark.parametrize("name", ["wingnut.obj", "spot.obj", "tray_bottom_ascii.stl"])
def test_text_files_give_trimesh_triangles(meshes, name):
    trimesh = pytest.importorskip("trimesh")
    path = meshes.path(name)
    data = np.fromfile(path, dtype=np.uint8)
    v, f = (read_obj if name.endswith(".obj") else read_ascii_stl)(data, path)
    m = trimesh.load(str(path), process=False, force="mesh")
    if name.endswith(".stl"):   # ASCII STL: the same corners, face for face
        assert np.array_equal(v[f], m.vertices[m.faces])
    assert _triangles(v, f) == _triangles(m.vertices, m.faces)


def test_large_real_obj_gives_trimesh_triangles(shared_data):
    trimesh = pytest.importorskip("trimesh")
    path = shared_data / "meshes" / "koala_large.obj"
    v, f = load_mesh(path, merge_rtol=0.0)
    m = trimesh.load(str(path), process=False, force="mesh")
    assert len(f) == 99994 and _triangles(v, f) == _triangles(m.vertices, m.faces)


# ---------------------------------------------------------------- OBJ features
CUBE_QUADS = (b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
              b"f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n")


def _props(tmp_path, text: bytes, name="t.obj"):
    p = tmp_path / name
    p.write_bytes(text)
    return inertia.mesh_file_properties(p, density=1.0)


def test_quads_are_fanned_and_match_trimesh(tmp_path):
    # truth: the unit cube, volume 1, inertia 1/6 about its centre
    p = _props(tmp_path, CUBE_QUADS)
    assert p.volume == pytest.approx(1.0, rel=1e-14)
    np.testing.assert_allclose(p.inertia_com, np.eye(3) / 6, atol=1e-14)
    trimesh = pytest.importorskip("trimesh")
    m = trimesh.load(str(tmp_path / "t.obj"), process=False)
    v, f = load_mesh(tmp_path / "t.obj", merge_rtol=0.0)
    assert _triangles(v, f) == _triangles(m.vertices, m.faces)


def test_polygons_are_fanned_from_their_first_vertex(tmp_path):
    # truth: a prism over a regular n-gon (two n-gon caps, quad sides), volume n/2 r^2 sin(2 pi/n) h
    n, r, h = 7, 1.3, 0.4
    a = 2 * np.pi * np.arange(n) / n
    ring = np.c_[r * np.cos(a), r * np.sin(a), np.zeros(n)]
    v = np.vstack([ring, ring + [0, 0, h]])
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()]
    lines.append("f " + " ".join(str(k + 1) for k in reversed(range(n))))
    lines.append("f " + " ".join(str(n + k + 1) for k in range(n)))
    lines += [f"f {k + 1} {(k + 1) % n + 1} {(k + 1) % n + n + 1} {k + n + 1}" for k in range(n)]
    p = _props(tmp_path, ("\n".join(lines) + "\n").encode())
    assert p.volume == pytest.approx(n / 2 * r * r * np.sin(2 * np.pi / n) * h, rel=1e-13)


def test_negative_indices_count_back_from_their_line(tmp_path):
    # two unit tetrahedra, each written as its vertices then faces with -4..-1: the OBJ
    # specification counts from the line (trimesh counts from the end of the file instead)
    tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n"
    text = (tet + tet.replace("v 0 0 0", "v 5 0 0", 1).replace("v 1 0 0", "v 6 0 0").replace(
        "v 0 1 0", "v 5 1 0").replace("v 0 0 1", "v 5 0 1")).encode()
    v, f = _read(read_obj, text)
    assert f.tolist()[:4] == [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] and f.min() == 0 and f[4:].min() == 4
    assert _props(tmp_path, text).volume == pytest.approx(2 / 6, rel=1e-14)


def test_obj_references_comments_groups_and_continuations():
    text = (b"# a comment\nmtllib x.mtl\no part\ng side\nusemtl steel\ns 1\n"
            b"v 0 0 0 1.0\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\n\tv  0 0 1 \r\nvt 0 0\nvn 0 0 1\n"
            b"f 1/1 3/1 2/1 # comment\nf 1//1 2//1 \\\n 4//1\nf 1/1/1 4/1/1 3/1/1\nf 2 3 4\n"
            b"l 1 2\nvp 0.5\n")
    v, f = _read(read_obj, text)
    assert v.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert f.tolist() == [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]


def test_faces_may_name_vertices_defined_below_them():
    v, f = _read(read_obj, b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n")
    assert len(v) == 3 and f.tolist() == [[0, 1, 2]]


# ---------------------------------------------------------------- ASCII STL features
def _stl_solid(name, tris, facet="facet normal 0 0 0", loop="outer loop"):
    out = [f"solid {name}"]
    for t in tris:
        out += [f" {facet}", f"  {loop}"] + [f"   vertex {x!r} {y!r} {z!r}" for x, y, z in t] + ["  endloop", " endfacet"]
    return "\n".join(out + [f"endsolid {name}"]) + "\n"


def _cube_triangles(offset):
    v = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float) + offset
    f = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
         (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return v[f].tolist()


def test_several_solids_in_one_file(tmp_path):
    # truth: two unit cubes; trimesh reads each solid as a mesh of a scene
    text = (_stl_solid("a", _cube_triangles([0, 0, 0])) + _stl_solid("b", _cube_triangles([3, 0, 0]))).encode()
    p = _props(tmp_path, text, "two.stl")
    assert p.volume == pytest.approx(2.0, rel=1e-14)
    np.testing.assert_allclose(p.com, [2.0, 0.5, 0.5], atol=1e-14)
    trimesh = pytest.importorskip("trimesh")
    scene = trimesh.load(str(tmp_path / "two.stl"), process=False)
    tris = np.concatenate([g.vertices[g.faces] for g in scene.geometry.values()])
    v, f = load_mesh(tmp_path / "two.stl", merge_rtol=0.0)
    assert len(scene.geometry) == 2 and _triangles(v, f) == _triangles(tris.reshape(-1, 3), np.arange(72).reshape(-1, 3))


def test_stl_keywords_in_any_case_with_crlf_lines():
    text = _stl_solid("X", _cube_triangles([0, 0, 0]), "FACET NORMAL 1 0 0", "Outer Loop")
    text = text.replace("vertex", "VERTEX").replace("endloop", "ENDLOOP").replace("\n", "\r\n").encode()
    v, f = _read(read_ascii_stl, text)
    assert np.array_equal(v[f], np.array(_cube_triangles([0, 0, 0]))) and f.shape == (12, 3)
    assert len(v) == 8   # a repeated corner is stored once


def test_stl_corners_are_welded_like_binary_stl(tmp_path):
    # truth: the cube's 8 corners once welded; and the binary STL path's arrays
    from tests._make import write_binary_stl

    text = _stl_solid("c", _cube_triangles([0, 0, 0])).encode()
    (tmp_path / "a.stl").write_bytes(text)
    write_binary_stl(tmp_path / "b.stl", np.array(_cube_triangles([0, 0, 0])))
    va, fa = load_mesh(tmp_path / "a.stl")
    vb, fb = load_mesh(tmp_path / "b.stl")
    assert len(va) == 8 and np.array_equal(va, vb) and np.array_equal(fa, fb)


# ---------------------------------------------------------------- malformed files, named
STL_OK = _stl_solid("t", _cube_triangles([0, 0, 0]))
MALFORMED = [
    ("t.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\nendloop\n", 4,
     "a vertex needs 3 coordinates, this one has 2 in 'vertex 0 0'"),
    ("t.stl", STL_OK.replace("vertex 1.0 1.0 0.0", "vertex 1.0 1,0 0.0", 1), None, "malformed number '1,0'"),
    ("t.stl", STL_OK.replace("vertex 0.0 0.0 0.0", "vertex 0.0 0.0 0.0 7", 1), 4,
     "unexpected '7' after the 3 coordinates of a vertex"),
    ("t.stl", STL_OK.replace("  endloop", "   vertex 0 0 0\n  endloop", 1), 7, "a facet with 4 vertices"),
    ("t.stl", STL_OK.replace("   vertex 0.0 0.0 1.0\n", "", 1), None, "a facet with 2 vertices"),
    ("t.stl", STL_OK.rsplit("endsolid", 1)[0], None, "the file ends inside a solid, outside a facet (no endsolid"),
    ("t.stl", STL_OK[:STL_OK.index(" endfacet")], 7, "the file ends inside a facet"),
    ("t.stl", STL_OK.replace(" facet normal", " facet normal 0 0 0\n facet normal", 1), 3,
     "unexpected 'facet' inside a facet"),
    ("t.stl", STL_OK + "garbage\n", 87, "unexpected 'garbage' outside a solid"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n", 4, "face vertex '4' names no vertex (3 defined in the file)"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", 3, "face vertex '-3' names no vertex (2 defined above it)"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 4, "a face needs at least 3 vertices, this one has 2"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", 4, "malformed face vertex 'x'"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1/1/1\n", 4, "malformed face vertex '3/1/1/1'"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.0\n", 4, "malformed face vertex '3.0'"),
    ("t.obj", "v 0 0 0\nv 1 0 1e\nv 0 1 0\nf 1 2 3\n", 2, "malformed number '1e'"),
    ("t.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", 2, "a vertex needs 3 coordinates, this one has 2"),
    ("t.obj", "v \r1 2 3\nv 1 2\nv 1 2 3\nf 1 2 3\n", 2, "a vertex needs 3 coordinates, this one has 2"),
    ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1/0/1 4/1/1 3/1/1\n", 7,
     "face index 0 in 'f 1/0/1 4/1/1 3/1/1'"),
]


@pytest.mark.parametrize("name, text, line, fragment", MALFORMED)
def test_malformed_files_are_named_with_their_line(name, text, line, fragment):
    reader = read_obj if name.endswith(".obj") else read_ascii_stl
    with pytest.raises(MeshFileError) as ei:
        _read(reader, text.encode())
    msg = str(ei.value)
    assert ei.value.code == "malformed" and fragment in msg, msg
    if line is not None:
        assert msg.startswith(f"t, line {line}: "), msg


def test_malformed_file_error_names_the_file(tmp_path):
    p = tmp_path / "bad.obj"
    p.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(MeshFileError, match=rf"^{p}, line 4: malformed OBJ: face vertex '9' names no vertex"):
        inertia.mesh_file_properties(p, density=1.0)


# ---------------------------------------------------------------- the oracle's grammar
def _seeds():
    stl = seed_stl_ascii()
    obj = seed_obj()
    return [(read_obj, obj), (read_obj, CUBE_QUADS), (read_obj, obj.replace(b"f ", b"f  ").replace(b"\n", b" # c\r\n")),
            (read_obj, b"v 1e-3 -2.5E+2 .5\nv 1 1 1\nv -0 0 1.00000000000000000001\nf 1/1/1 2//2 -1/3\n"
                       b"f 1 2 \\\n 3\n"),
            (read_obj, b"v 0 0 0 # \xe9t\xe9\nv\\\r\n 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2 4 # quad\nf -4 -3 -1\n"),
            (read_ascii_stl, stl), (read_ascii_stl, stl + stl.replace(b"cube", b"two")),
            (read_ascii_stl, stl.upper().replace(b"\n", b"\r\n")),
            (read_ascii_stl, stl.replace(b"solid cube", b"solid pi\xe8ce \x00\x01").replace(b"  outer", b"\t\v\f outer"))]


def test_readers_match_the_oracle_on_mutated_files():
    rng = random.Random(11)
    seeds = _seeds()
    kinds = {"arrays": 0, "errors": 0}
    for k in range(3000):
        reader, seed = seeds[k % len(seeds)]
        text = mutate_any(seed, rng)
        got, want = _outcome(reader, text), _oracle(reader, text)
        assert _same(got, want), (text, got, want)
        kinds["errors" if isinstance(want[0], str) else "arrays"] += 1
    assert min(kinds.values()) > 400   # both outcomes exercised


@pytest.mark.parametrize("k", range(len(_seeds())))
def test_readers_match_the_oracle_on_valid_files(k):
    reader, text = _seeds()[k]
    got, want = _outcome(reader, text), _oracle(reader, text)
    assert not isinstance(want[0], str) and _same(got, want)


# ---------------------------------------------------------------- the same bits
def _digest(reader, text: bytes) -> str:
    v, f = _read(reader, text)
    return hashlib.sha256(v.tobytes() + f.tobytes() + repr((v.shape, f.shape)).encode()).hexdigest()


def _big_texts():
    """An ASCII STL and an OBJ of 20,000 facets with 17-digit coordinates (both number paths)."""
    rng = np.random.default_rng(8)
    pool = rng.normal(size=(3000, 3)) * 10.0 ** rng.integers(-30, 30, size=(3000, 1))
    faces = rng.integers(0, len(pool), size=(20000, 3))
    pool = pool.tolist()
    stl = "solid s\n" + "".join("facet normal 0 0 1\nouter loop\n" + "".join(
        "vertex %r %r %r\n" % tuple(pool[i]) for i in t) + "endloop\nendfacet\n" for t in faces.tolist()) + "endsolid s\n"
    obj = "".join("v %r %r %r\n" % tuple(p) for p in pool) + "".join(
        "f %d %d %d %d\n" % (a + 1, b + 1, c + 1, -1) for a, b, c in faces.tolist())
    return {"stl": stl.encode(), "obj": obj.encode()}


def test_readers_give_the_same_bits_twice_and_in_a_fresh_process():
    texts = _big_texts()
    readers = {"stl": read_ascii_stl, "obj": read_obj}
    here = {k: _digest(readers[k], t) for k, t in texts.items()}
    assert here == {k: _digest(readers[k], t) for k, t in texts.items()}
    code = ("import json\nfrom tests.geometry import test_text_readers as t\n"
            "r = {'stl': t.read_ascii_stl, 'obj': t.read_obj}\n"
            "print(json.dumps({k: t._digest(r[k], x) for k, x in t._big_texts().items()}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=300)
    assert json.loads(out.stdout) == here


def test_readers_release_the_gil_and_give_the_same_arrays_on_threads():
    from concurrent.futures import ThreadPoolExecutor

    texts = _big_texts()
    alone = [_digest(read_ascii_stl, texts["stl"]), _digest(read_obj, texts["obj"])]
    with ThreadPoolExecutor(4) as pool:
        jobs = [pool.submit(_digest, r, texts[k]) for _ in range(3) for r, k in ((read_ascii_stl, "stl"), (read_obj, "obj"))]
        assert [j.result() for j in jobs] == alone * 3


def test_quads_split_along_the_shorter_diagonal_as_mujoco_does(tmp_path):
    """A box whose top quad is twisted (one corner raised): fanned from its first vertex the
    volume depends on where the quad starts; split along its shorter diagonal it does not, and
    equals MuJoCo's compiled mass of the same OBJ (its float32 vertices aside)."""
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1.6], [0, 1, 1]], float)
    sides = [[0, 3, 2, 1], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    volumes = {}
    for name, top in (("a", [4, 5, 6, 7]), ("b", [5, 6, 7, 4])):
        text = "".join(f"v {x} {y} {z}\n" for x, y, z in V) + "".join(
            "f " + " ".join(str(i + 1) for i in q) + "\n" for q in [top] + sides)
        path = tmp_path / f"{name}.obj"
        path.write_text(text)
        for polygons in ("fan", "shorter", "mujoco"):
            v, f = read_obj(np.frombuffer(text.encode(), dtype=np.uint8), path, polygons=polygons)
            t = v[f]
            volumes[name, polygons] = float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6)
    assert volumes["a", "shorter"] == pytest.approx(1.1, abs=1e-14) == volumes["b", "shorter"] == volumes["a", "mujoco"]
    assert {round(volumes["a", "fan"], 12), round(volumes["b", "fan"], 12)} == {1.2, 1.1}
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_string(
        f'<mujoco><compiler meshdir="{tmp_path}"/><asset><mesh name="m" file="a.obj" inertia="exact"/></asset>'
        '<worldbody><body><freejoint/><geom type="mesh" mesh="m" density="1"/></body></worldbody></mujoco>')
    assert model.body_mass[1] == pytest.approx(volumes["a", "shorter"], rel=1e-7)


def _mujoco_faces(tmp_path, text: str) -> list:
    """The triangles MuJoCo's compiler holds for an OBJ, each from its smallest vertex, sorted."""
    mujoco = pytest.importorskip("mujoco")
    (tmp_path / "p.obj").write_text(text)
    m = mujoco.MjModel.from_xml_string(
        f'<mujoco><compiler meshdir="{tmp_path}"/><asset><mesh name="p" file="p.obj" inertia="shell"/></asset>'
        '<worldbody><geom type="mesh" mesh="p"/></worldbody></mujoco>')
    return _rotated(m.mesh_face[m.mesh_faceadr[0]:m.mesh_faceadr[0] + m.mesh_facenum[0]])


def _rotated(faces) -> list:
    return sorted(tuple(t[t.index(min(t)):] + t[:t.index(min(t))]) for t in np.asarray(faces).tolist())


@pytest.mark.parametrize("seed", range(12))
def test_polygons_are_triangulated_as_mujoco_reads_them(tmp_path, seed):
    """polygons="mujoco" against the triangles MuJoCo's compiler holds for the same OBJ, triangle
    for triangle: prisms over star-shaped or self-crossing n-gons (5 to 150 vertices; its reader
    ear-clips 5 to 100 with a test that depends on the origin, leaves some polygons half cut and
    drops faces of more than 100), tilted or not, around the origin or away from it."""
    rng = np.random.default_rng(seed)
    n = [5, 6, 9, 30, 49, 99, 100, 101, 150, 7, 12, 60][seed]
    k = np.arange(n)
    angle = np.sort(rng.uniform(0, 2 * np.pi, n)) if seed % 2 else 2 * np.pi * k / n + 0.1 * np.sin(3 * k)
    r = 1 + (0.5 if seed % 4 < 2 else 0.0) * rng.uniform(-1, 1, n)
    R = np.linalg.qr(rng.standard_normal((3, 3)))[0] if seed % 3 == 0 else np.eye(3)
    ring = np.c_[r * np.cos(angle), 0.7 * r * np.sin(angle), np.zeros(n)] @ R.T + rng.uniform(-3, 3, 3) * (seed % 5 > 1)
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in np.vstack([ring, ring + 0.5 * R[:, 2]])]
    lines += ["f " + " ".join(str(i + 1) for i in k[::-1]), "f " + " ".join(str(n + i + 1) for i in k)]
    lines += [f"f {i + 1} {(i + 1) % n + 1} {n + (i + 1) % n + 1} {n + i + 1}" for i in k]
    text = "\n".join(lines) + "\n"
    v, f = _read(read_obj, text.encode(), polygons="mujoco")
    assert _rotated(f) == _mujoco_faces(tmp_path, text)
    assert len(v) == 2 * n


@pytest.mark.parametrize("separator", ["o a", "g a", "g   ", "o\tb"])
def test_mujoco_reads_the_first_obj_group_with_triangles(tmp_path, separator):
    """MuJoCo keeps the faces of its reader's first shape: up to the first `o` or `g` line (with a
    space or tab after the letter) that follows triangles; a group whose faces it all dropped
    (here a 120-gon) does not count; a bare `g` starts no group.  Truth: MuJoCo's triangles."""
    cube = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = [f"v {x + 3 * j} {y} {z}" for j in range(3) for x, y, z in cube]
    lines += [f"v {np.cos(a) + 10} {np.sin(a)} 0" for a in np.linspace(0, 2 * np.pi, 120, endpoint=False).tolist()]

    def faces(j):
        return ["f " + " ".join(str(i + 1 + 8 * j) for i in q) for q in quads]

    dropped = "f " + " ".join(str(25 + i) for i in range(120))
    text = "\n".join(lines + [separator, dropped, separator, "g"] + faces(0) + [separator] + faces(1) + faces(2)) + "\n"
    v, f = _read(read_obj, text.encode(), polygons="mujoco")
    assert _rotated(f) == _mujoco_faces(tmp_path, text)
    assert len(f) == 12 and f.max() < 8 and len(v) == 24 + 120
    assert len(_read(read_obj, text.encode())[1]) == 3 * 12 + 118


def test_mujoco_triangulation_reads_mutated_files_as_the_fan_does():
    """Mutated OBJ files with polygons, groups and coordinates beyond float's range: polygons="mujoco"
    refuses what the fan reading refuses, with the same message, and otherwise reads the same
    vertices and no more triangles, all indexing them."""
    ring = [f"v {np.cos(a)!r} {np.sin(a)!r} {z}" for z in (0, 1) for a in np.linspace(0, 6.28, 12, endpoint=False).tolist()]
    seed = "\n".join(ring + ["o a", "f " + " ".join(map(str, range(1, 13))), "g b", "f " + " ".join(map(str, range(13, 25))),
                             "f 1 2 14 13", "f -1 -2 -3 -4 -5", "v 1e39 -1e39 nan", "f 1 2 25"]).encode() + b"\n"
    rng = random.Random(5)
    for _ in range(2000):
        text = mutate_any(seed, rng)
        fan, mujoco = _outcome(read_obj, text), None
        try:
            mujoco = _read(read_obj, text, polygons="mujoco")
        except MeshFileError as exc:
            assert (exc.code, str(exc)) == fan
            continue
        (v, f), (v0, f0) = mujoco, fan
        assert np.array_equal(v, v0, equal_nan=True) and len(f) <= len(f0) and (len(f) == 0 or 0 <= f.min() <= f.max() < len(v))

"""Inputs that once crashed the process or passed as numbers: each is now refused by name.

The compiled kernels index without bounds checks, so every array they see must have been
validated in its final shape; these tests feed the shapes and values that slipped through.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import inertia
from inertia.errors import InputError, MeshError, MeshFileError
from inertia.geometry import check_mesh

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_obj_whose_vertices_come_back_transposed_is_malformed_not_a_segfault(tmp_path):
    # a bare carriage return inside a vertex line (trimesh's parser returned vertices of shape
    # (3, 0)); the native reader reads CR as a separator and names the short vertex line
    f = tmp_path / "t.obj"
    f.write_bytes(b"v \r1 2 3\nv 1 2\nv 1 2 3\nf 1 2 3\n")
    with pytest.raises(MeshFileError) as ei:
        inertia.load_mesh(f)
    assert ei.value.code == "malformed" and "t.obj" in str(ei.value) and "line 2" in str(ei.value)
    # the whole process: exit 1 with one line, never a signal
    out = subprocess.run([sys.executable, "-m", "inertia.cli.main", "props", str(f)], capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 1 and "malformed" in out.stderr and "Traceback" not in out.stderr


@pytest.mark.parametrize("bad", [[[0, 1, 7]], [[-1, 1, 2]]])
def test_out_of_range_indices_never_reach_a_compiled_kernel(bad):
    faces = np.vstack([TET_F, bad])
    with pytest.raises(InputError) as ei:
        inertia.geometry.weld_vertices(TET_V, faces)
    assert ei.value.code == "bad_index"
    assert "bad_index" in check_mesh(TET_V, faces).codes
    from inertia.geometry.checks import analyse_mesh

    # welded=True skips the weld; the index range is still checked before the kernel
    assert "bad_index" in analyse_mesh(TET_V, faces, welded=True).report.codes


@pytest.mark.parametrize("scale", [1e61, 1e200, 1e300])
def test_coordinates_whose_moments_overflow_are_out_of_range_not_zero_area(scale):
    # truth: the tetrahedron's second moments grow as scale**5, beyond float64 here
    report = check_mesh(TET_V * scale, TET_F)
    assert report.codes == ("out_of_range",)
    with pytest.raises(MeshError) as ei:
        inertia.mesh_properties(TET_V * scale, TET_F, density=1.0)
    assert ei.value.code == "out_of_range" and "units" in str(ei.value)


def test_largest_representable_scale_still_gives_exact_numbers():
    # truth: the unit tetrahedron's volume 1/6, scaled by s**3 (s = 1e50, inside the limit)
    s = 1e50
    p = inertia.mesh_properties(TET_V * s, TET_F, density=1.0)
    assert p.mass == pytest.approx(s**3 / 6, rel=1e-12)
    assert np.all(np.isfinite(p.inertia_com))


def test_running_out_of_memory_while_reading_is_named(tmp_path, monkeypatch):
    # a binary STL whose consistent header announces 4e7 triangles (a sparse 2 GB file in the
    # original report); memory is made to run out where the records are decoded
    from inertia.geometry import mesh_io

    f = tmp_path / "big.stl"
    with open(f, "wb") as fh:
        fh.write(b"x" * 80 + (1000).to_bytes(4, "little"))
        fh.truncate(84 + 50 * 1000)

    def no_memory(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(mesh_io, "_read_binary_stl_merged", no_memory)
    with pytest.raises(MeshFileError) as ei:
        inertia.load_mesh(f)
    assert ei.value.code == "too_large" and "big.stl" in str(ei.value) and "memory" in str(ei.value)


@pytest.mark.parametrize("command", [["lagrangian", "-o", "{out}"], ["batch", "{mesh}", "-o", "{out}"]])
@pytest.mark.parametrize("where", ["under_a_file", "a_folder"])
def test_an_output_that_cannot_be_written_is_named_before_any_work(tmp_path, capsys, command, where):
    if command[0] == "lagrangian":
        pytest.importorskip("sympy")
    else:
        pytest.importorskip("pandas")
    from inertia.cli.main import main

    (tmp_path / "plain").write_text("a file")
    (tmp_path / "folder").mkdir()
    mesh = tmp_path / "t.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    out = tmp_path / ("plain/sub/x.csv" if where == "under_a_file" else "folder")
    code = main([a.format(out=out, mesh=mesh) for a in command])
    err = capsys.readouterr().err
    assert code == 1 and "internal error" not in err and str(out) in err
    assert ("is a file, not a folder" if where == "under_a_file" else "is a folder") in err


@pytest.mark.parametrize("face, line", [("f 0 4 3", 7), ("f 1/0/1 4/1/1 3/1/1", 7), ("f  00 4 3", 7)])
def test_obj_index_zero_is_refused_with_its_line(tmp_path, face, line):
    # truth: OBJ indices count from 1 (trimesh reads 0 as the first vertex)
    pytest.importorskip("trimesh")
    f = tmp_path / "z.obj"
    f.write_text(f"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n{face}\nf 2 3 4\n")
    with pytest.raises(MeshFileError) as ei:
        inertia.load_mesh(f)
    assert ei.value.code == "malformed" and f"line {line}" in str(ei.value) and face.strip() in str(ei.value)


def test_obj_indices_with_zeros_inside_them_are_read(tmp_path):
    # 10, 100, -10: not index 0; truth: the unit tetrahedron's volume 1/6 whatever the index spelling
    pytest.importorskip("trimesh")
    f = tmp_path / "t.obj"
    pad = "".join("v 5 5 5\n" for _ in range(10))
    f.write_text(pad + "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 11 13 12\nf 11 12 14\nf -4 -1 -2\nf 12 13 14\n")
    assert inertia.mesh_file_properties(f, density=1.0).mass == pytest.approx(1 / 6, rel=1e-12)


CUBE_V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
CUBE_F = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                   (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


def _obj(path, v, f):
    path.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
                    + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f.tolist()))
    return path


@pytest.mark.parametrize("seed", range(12))
def test_a_micrometre_body_far_from_the_origin_keeps_every_face(tmp_path, seed):
    pytest.importorskip("trimesh")   # OBJ: float64 text (binary STL's float32 cannot hold 1e7 + 1e-6)
    # truth: the same arrays integrated without reading a file (no merging); the merge
    # tolerance follows the faces' own edges, not the distance from the origin
    rng = np.random.default_rng(seed)
    R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    R *= np.sign(np.linalg.det(R))
    v = (CUBE_V - 0.5) @ R.T * 1e-6 * rng.uniform(0.5, 2) + rng.normal(size=3) * 1e7
    p = inertia.mesh_file_properties(_obj(tmp_path / "far.obj", v, CUBE_F), density=1.0)
    truth = inertia.mesh_properties(v, CUBE_F, density=1.0)
    assert p.volume == pytest.approx(truth.volume, rel=1e-9)
    assert np.allclose(p.inertia_com, truth.inertia_com, rtol=1e-6, atol=0)


def test_two_micrometre_cubes_twenty_kilometres_apart_load_as_two_cubes(tmp_path):
    pytest.importorskip("trimesh")
    # truth: 2 x (1e-6 m)^3; faces are degenerate relative to their own size, not the mesh's
    v = np.vstack([CUBE_V * 1e-6, CUBE_V * 1e-6 + [2e4, 0, 0]])
    f = np.vstack([CUBE_F, CUBE_F + 8])
    vv, ff = inertia.load_mesh(_obj(tmp_path / "two.obj", v, f))
    report = check_mesh(vv, ff)
    assert (len(vv), len(ff), report.codes) == (16, 24, ())
    assert report.volume == pytest.approx(2e-18, rel=1e-6)


# ---------------------------------------------------------------- text in other encodings (issue 34)
LEGS, OFFSET = np.array([0.2, 0.3, 0.5]), np.array([1.0, 2.0, 3.0])


def _tet_text(fmt: str, comment: str) -> str:
    """A right tetrahedron (legs LEGS at OFFSET, outward wound) as ``fmt`` text, with ``comment``
    (non-ASCII) where the format holds one: a comment, the STL solid's name, the glTF node's."""
    v = (TET_V * LEGS + OFFSET).tolist()
    if fmt == "gltf":   # trimesh's writer, buffers inside (float32 coordinates), the name unescaped
        import json

        import trimesh

        scene = trimesh.Scene()
        scene.add_geometry(trimesh.Trimesh(v, TET_F, process=False), geom_name=comment, node_name=comment)
        text = trimesh.exchange.gltf.export_gltf(scene, embed_buffers=True)["model.gltf"].decode()
        return text.replace(json.dumps(comment)[1:-1], comment)
    if fmt == "stl":
        facets = "".join(" facet normal 0 0 0\n  outer loop\n" + "".join(f"   vertex {x!r} {y!r} {z!r}\n"
                                                                       for x, y, z in (v[i] for i in t))
                         + "  endloop\n endfacet\n" for t in TET_F.tolist())
        return f"solid {comment}\n{facets}endsolid {comment}\n"
    rows = "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in v)
    if fmt == "obj":
        # a vertex first (a mark must not hide it) and one unused last: a lost line shifts faces silently
        vs = [f"v {r}" for r in rows.splitlines(True)] + ["v 9 9 9\n"]
        return vs[0] + f"# {comment}\n" + "".join(vs[1:]) + f"o {comment}\n" + "".join(f"f {a + 1} {b + 1} {c + 1} # {comment}\n" for a, b, c in TET_F.tolist())
    if fmt == "off":
        return f"OFF\n# {comment}\n4 4 0\n{rows}" + "".join(f"3 {a} {b} {c}\n" for a, b, c in TET_F.tolist())
    return ("ply\nformat ascii 1.0\ncomment " + comment + "\nelement vertex 4\nproperty double x\nproperty double y\n"
            "property double z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n" + rows
            + "".join(f"3 {a} {b} {c}\n" for a, b, c in TET_F.tolist()))


ENCODINGS = {   # name -> (codec of the text, byte-order mark written before it)
    "utf-8 with BOM": ("utf-8", b"\xef\xbb\xbf"), "utf-16 LE with BOM": ("utf-16-le", b"\xff\xfe"),
    "utf-16 BE with BOM": ("utf-16-be", b"\xfe\xff"), "utf-16 LE": ("utf-16-le", b""), "utf-16 BE": ("utf-16-be", b""),
    "utf-32 LE with BOM": ("utf-32-le", b"\xff\xfe\x00\x00"), "utf-32 BE with BOM": ("utf-32-be", b"\x00\x00\xfe\xff"),
    "utf-32 LE": ("utf-32-le", b""), "utf-32 BE": ("utf-32-be", b""), "latin-1 comment": ("latin-1", b""),
}


@pytest.mark.parametrize("encoding", ENCODINGS)
@pytest.mark.parametrize("fmt", ["stl", "obj", "ply", "off", "gltf"])
def test_text_meshes_read_the_same_in_every_encoding(tmp_path, fmt, encoding):
    # truth: the tetrahedron the test wrote, volume legs/6 and centroid OFFSET + legs/4 (glTF:
    # float32), and the same file in plain UTF-8 (an OBJ with a byte-order mark lost its first
    # vertex line, every face shifted; UTF-16 read as "holds no triangles"; Latin-1 broke
    # trimesh's PLY and OFF; trimesh's glTF took a marked file for a missing one)
    if fmt in ("ply", "off", "gltf"):
        pytest.importorskip("trimesh")
    rel = 1e-6 if fmt == "gltf" else 1e-14
    codec, bom = ENCODINGS[encoding]
    text = _tet_text(fmt, "pièce café")
    (tmp_path / f"plain.{fmt}").write_bytes(text.encode("utf-8"))
    (tmp_path / f"t.{fmt}").write_bytes(bom + text.encode(codec))
    p = inertia.mesh_file_properties(tmp_path / f"t.{fmt}", density=1.0)
    assert p.volume == pytest.approx(np.prod(LEGS) / 6, rel=rel)
    np.testing.assert_allclose(p.com, OFFSET + LEGS / 4, rtol=rel)
    plain = inertia.mesh_file_properties(tmp_path / f"plain.{fmt}", density=1.0)
    assert (p.mass, p.com.tolist(), p.inertia_com.tolist()) == (plain.mass, plain.com.tolist(), plain.inertia_com.tolist())


@pytest.mark.parametrize("fmt", ["stl", "obj", "ply", "off", "gltf"])
@pytest.mark.parametrize("codec, bom", [("utf-16-le", b"\xff\xfe"), ("utf-32-be", b"")])
def test_text_that_does_not_decode_in_its_encoding_is_refused_naming_it(tmp_path, fmt, codec, bom):
    if fmt in ("ply", "off", "gltf"):
        pytest.importorskip("trimesh")
    path = tmp_path / f"t.{fmt}"
    path.write_bytes(bom + _tet_text(fmt, "x").encode(codec) + b"\x00")   # a stray byte: a character cut short
    with pytest.raises(MeshFileError) as ei:
        inertia.mesh_file_properties(path, density=1.0)
    assert ei.value.code == "malformed" and str(ei.value).startswith(f"{path}: malformed ")
    assert f"the file starts as {codec.upper()} text but byte" in str(ei.value)


def test_a_crossing_shell_swamped_by_a_far_vertex_is_refused_by_name(tmp_path):
    # fuzz case (bench/fuzz.py, seed 11): a cube's faces reordered and a vertex moved to 1e20, so
    # the solid the surface bounds once has zero volume in doubles: the crossing's effect has no
    # scale (it was a ZeroDivisionError)
    p = tmp_path / "far.obj"
    p.write_bytes(b"v 0 0 0\nv 1 0 0\nf 5 6 7\nv 0 1 1e20\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 3 2\n"
                  b"f 1 4 3\nv 1 1 0\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\n"
                  b"f 4 1 5\nf 4 5 8\n")
    with pytest.raises(MeshError) as ei:
        inertia.mesh_file_properties(p, density=1.0)
    assert "self_intersecting" in str(ei.value) and "far.obj" in str(ei.value)

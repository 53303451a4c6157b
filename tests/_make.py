"""Test inputs the tests write themselves: meshes in every file format and robot files.

The "made" tier of ``tests/conftest.py``: a plain clone runs every mesh-file and robot-file
test on these, and again on the curated real files of ``../shared/data`` when they are beside
the checkout (the "real" tier).  Each made file stands in for one real file of the same name
and carries the trait the tests exercise (binary STL whose header starts with "solid", float
noise copies of vertices, UV-seam duplicates, an open surface, a triangle soup, balanced
non-manifold edges, ...).  The facts the tests assert come with each set: for the made files
from closed forms (volumes of prisms, annuli and boxes) or from a plain count done here,
for the real files from ``../shared/data/SOURCES.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


# ----------------------------------------------------------------------------- writers
def write_binary_stl(path: Path, corners, header: bytes = b"inertia test mesh") -> Path:
    """Binary STL of triangles ``corners`` (F, 3, 3), stored as float32 (zero normals)."""
    corners = np.asarray(corners)
    rec = np.zeros(len(corners), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = corners
    path.write_bytes(header[:80].ljust(80) + len(corners).to_bytes(4, "little") + rec.tobytes())
    return path


def write_ascii_stl(path: Path, corners) -> Path:
    lines = ["solid part"]
    for tri in np.asarray(corners, float):
        lines += ["  facet normal 0 0 0", "    outer loop"]
        lines += [f"      vertex {x!r} {y!r} {z!r}" for x, y, z in tri.tolist()]
        lines += ["    endloop", "  endfacet"]
    path.write_text("\n".join(lines + ["endsolid part"]) + "\n")
    return path


def write_obj(path: Path, vertices, faces) -> Path:
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_off(path: Path, vertices, faces) -> Path:
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += [f"3 {a} {b} {c}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ply(path: Path, vertices, faces) -> Path:
    head = ["ply", "format ascii 1.0", f"element vertex {len(vertices)}", "property double x",
            "property double y", "property double z", f"element face {len(faces)}",
            "property list uchar int vertex_indices", "end_header"]
    lines = [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, float).tolist()]
    lines += [f"3 {a} {b} {c}" for a, b, c in np.asarray(faces).tolist()]
    path.write_text("\n".join(head + lines) + "\n")
    return path


# ----------------------------------------------------------------------------- closed forms
def prism_volume(n: int, r: float, h: float) -> float:
    """Volume of a right prism over the regular n-gon inscribed in radius r."""
    return n / 2 * r * r * np.sin(2 * np.pi / n) * h


def box_inertia(extents, mass: float) -> np.ndarray:
    a, b, c = np.asarray(extents, float) ** 2
    return mass / 12 * np.diag([b + c, a + c, a + b])


def open_edge_count(corners) -> int:
    """Edges used by exactly one triangle, vertices identified by exactly equal coordinates."""
    pts = np.asarray(corners, float).reshape(-1, 3)
    _, ids = np.unique(pts, axis=0, return_inverse=True)
    tri = ids.reshape(-1, 3)
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts == 1).sum())


def _noisy(corners, every: int):
    """Float noise copies: in every ``every``-th triangle an exact 0 coordinate is written
    -2.7e-16, as CAD exporters leave them (closed again by the near merge only)."""
    c = np.asarray(corners, np.float32).copy()
    sel = c[::every]
    c[::every] = np.where(sel == 0, np.float32(-2.7e-16), sel)
    return c


# ----------------------------------------------------------------------------- meshes
@dataclass
class MeshSet:
    """A folder of test meshes and what the tests may assert about them."""

    dir: Path
    watertight: dict          # name -> (faces, volume in file units^3)
    broken: dict              # name -> (faces, defect code, count)
    noise_open_edges: int     # featuretype.stl: open edges left by exact welding alone
    soup_volume: float        # soup.stl as placed (trimesh)
    soup_volume_centred: float  # soup.stl moved to its bounding-box centre (trimesh)
    soup_message_volume: str  # regex of the signed volume our refusal names
    tier: str = "made"
    extra: dict = field(default_factory=dict)

    def path(self, name: str) -> Path:
        return self.dir / name


def real_mesh_set(root: Path) -> MeshSet:
    """``../shared/data/meshes`` with the figures of ``../shared/data/SOURCES.md``."""
    return MeshSet(
        dir=root, tier="real",
        watertight={"wingnut.obj": (6090, 22.0966), "ballA.off": (3796, 1401.11),
                    "featuretype.stl": (3476, 11.6277), "idler_riser_binary_solid_header.stl": (1572, 1.4878),
                    "tray_bottom_ascii.stl": (4520, 347866.0), "spot.obj": (23062, 0.687986)},
        # cycloidal: not open: 242 edges where closed parts touch (4 faces each, 2 per direction)
        broken={"teapot_open.stl": (894, "open_edges", 64), "soup.stl": (100, "open_edges", 300),
                "cycloidal.ply": (43368, "non_manifold_edges", 242)},
        noise_open_edges=576, soup_volume=0.168215, soup_volume_centred=-0.0653581,
        soup_message_volume=r"-0\.11\d+")


def _cylinder(n, r, h, centre):
    import trimesh

    m = trimesh.creation.cylinder(radius=r, height=h, sections=n)
    return m.vertices + centre, np.asarray(m.faces)


def _soup(rng, n=100):
    """n loose triangles facing +x, most at low x, one far out: the signed volume is positive
    as placed and negative about the bounding-box centre.  Flat triangles facing +x make the
    figures plain sums: trimesh's volume integrates x n_x over the surface, sum(A x_mean)."""
    yz = rng.uniform(0, 1, size=(n, 2))
    x = np.concatenate([rng.uniform(1.0, 1.2, size=n - 1), [3.0]])
    s = np.concatenate([rng.uniform(0.05, 0.1, size=n - 1), [0.01]])
    a = np.column_stack([x, yz])
    zero = 0 * s
    corners = np.stack([a, a + np.column_stack([zero, s, zero]), a + np.column_stack([zero, zero, s])], axis=1)
    corners = corners.astype(np.float32).astype(float)
    area = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])[:, 0]
    xc = 0.5 * (corners[..., 0].min() + corners[..., 0].max())
    return corners, float((corners[:, 0, 0] * area).sum()), float(((corners[:, 0, 0] - xc) * area).sum())


def make_mesh_set(d: Path) -> MeshSet:
    """Write the made meshes into folder ``d`` (same names as the real ones)."""
    import trimesh

    rng = np.random.default_rng(20261124)
    watertight, broken = {}, {}

    # wingnut.obj: an annulus (genus 1), OBJ
    n, r0, r1, h = 24, 0.8, 2.0, 1.5
    m = trimesh.creation.annulus(r_min=r0, r_max=r1, height=h, sections=n)
    write_obj(d / "wingnut.obj", m.vertices + [0.3, -0.2, 1.0], m.faces)
    watertight["wingnut.obj"] = (len(m.faces), prism_volume(n, r1, h) - prism_volume(n, r0, h))

    # ballA.off: a 40-gon prism, OFF, far from the origin
    v, f = _cylinder(40, 7.0, 9.0, [20.0, 10.0, -5.0])
    write_off(d / "ballA.off", v, f)
    watertight["ballA.off"] = (len(f), prism_volume(40, 7.0, 9.0))

    # featuretype.stl: binary STL with float noise copies of vertices (open unless merged)
    v, f = _cylinder(64, 1.25, 2.5, [0.0, 0.0, 1.25])   # vertices with exact zeros
    corners = _noisy(v[f], every=5)
    write_binary_stl(d / "featuretype.stl", corners)
    watertight["featuretype.stl"] = (len(f), prism_volume(64, 1.25, 2.5))
    noise_open = open_edge_count(corners)

    # idler_riser_binary_solid_header.stl: binary STL whose header begins with "solid", noisy too
    v, f = _cylinder(30, 0.5, 1.75, [0.0, 0.0, 0.875])
    write_binary_stl(d / "idler_riser_binary_solid_header.stl", _noisy(v[f], every=4),
                     header=b"solid idler_riser exported as binary")
    watertight["idler_riser_binary_solid_header.stl"] = (len(f), prism_volume(30, 0.5, 1.75))

    # tray_bottom_ascii.stl: ASCII STL of a large box (mm-like coordinates)
    m = trimesh.creation.box(extents=(120.0, 80.0, 25.0))
    write_ascii_stl(d / "tray_bottom_ascii.stl", (m.vertices + [60.0, 40.0, 12.5])[m.faces])
    watertight["tray_bottom_ascii.stl"] = (12, 120.0 * 80.0 * 25.0)

    # spot.obj: 5120 faces, split at a "UV seam": the top cap has its own copies of its vertices
    n = 1280
    v, f = _cylinder(n, 0.5, 0.8, [0.1, 0.2, 0.3])
    top = np.all(np.isclose(v[f][..., 2], v[:, 2].max()), axis=1)
    seam = np.unique(f[top])
    copy = np.full(len(v), -1)
    copy[seam] = len(v) + np.arange(len(seam))
    g = f.copy()
    g[top] = copy[f[top]]
    write_obj(d / "spot.obj", np.concatenate([v, v[seam]]), g)
    watertight["spot.obj"] = (len(f), prism_volume(n, 0.5, 0.8))

    # teapot_open.stl: a cup (a prism without its top cap), binary STL
    n = 48
    v, f = _cylinder(n, 3.0, 4.0, [1.0, 2.0, 2.0])
    top = np.all(np.isclose(v[f][..., 2], v[:, 2].max()), axis=1)
    write_binary_stl(d / "teapot_open.stl", v[f[~top]])
    broken["teapot_open.stl"] = (int((~top).sum()), "open_edges", n)

    # soup.stl: 100 loose triangles, binary STL
    corners, vol, vol_c = _soup(rng)
    write_binary_stl(d / "soup.stl", corners)
    broken["soup.stl"] = (100, "open_edges", 300)

    # cycloidal.ply: three closed cubes in a chain, each touching the next along one edge
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    parts = [box.vertices + [k, k, 0.5] for k in range(3)]
    vv = np.concatenate(parts)
    ff = np.concatenate([np.asarray(box.faces) + 8 * k for k in range(3)])
    write_ply(d / "cycloidal.ply", vv, ff)
    broken["cycloidal.ply"] = (len(ff), "non_manifold_edges", 2)

    return MeshSet(dir=d, watertight=watertight, broken=broken, noise_open_edges=noise_open,
                   soup_volume=vol, soup_volume_centred=vol_c, soup_message_volume=r"-\d+\.\d+")

"""Benchmarks of the robust path (inertia.geometry.robust): speed and memory, the accuracy /
bound table on generated cases, the real imperfect meshes beside trimesh and MuJoCo.

Run from the repository root, e.g.::

    PYTHONPATH=$PWD/src python bench/robust.py --speed --rounds 7 [--against OTHER/bin/python] [--threads 1]
    PYTHONPATH=$PWD/src python bench/robust.py --table --cases 100
    PYTHONPATH=$PWD/src python bench/robust.py --real [--data ../shared/data]
    PYTHONPATH=$PWD/src python bench/robust.py --manifold /path/to/site-packages   (manifold3d)

--speed: 100k-face open meshes through the whole public call
``inertia.mesh_properties(..., on_defect="robust")``, interleaved rounds, best and median wall
time, beside two anchors measured in the same rounds (the exact path on the closed mesh,
and ``robust_integrals`` alone), and with ``--against`` another install (e.g. the numba one)
in the same interleaved rounds; the peak RSS of a fresh process running one call.
--table: hundreds of generated cases (tests/geometry/_robust_cases.py) per kind: the worst
ratio true error / bound (honest when <= 1), the largest true error, bounds, convergence.
--real: teapot_open, soup, cycloidal (../shared/data): our answer and bounds, trimesh's mass
properties, MuJoCo's legacy mesh inertia (compiled from a tiny MJCF).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import warnings
import zlib
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull

import inertia
from inertia.geometry.integrals import solid_integrals
from inertia.geometry.robust import robust_integrals

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
from tests.geometry._robust_cases import CASES, ORIGIN, OTHER_CASES, error_ratio, random_case  # noqa: E402


def hull(n_faces, seed, r=1.0, c=(0.0, 0.0, 0.0)):
    """Convex polyhedron with about n_faces outward faces (hull of points on a sphere)."""
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(n_faces // 2 + 2, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    f = ConvexHull(p).simplices.astype(np.int64)
    nrm = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    flip = (nrm * p[f].mean(1)).sum(1) < 0
    f[flip] = f[flip][:, ::-1]
    return p * r + np.asarray(c), f


def speed_cases(data):
    """(name, vertices, faces of the open mesh, faces of the closed one) of about 100k faces."""
    v, f = hull(100_000, 0)
    out = [("sphere, 10 one-face holes", v, np.delete(f, np.arange(0, len(f), len(f) // 10)[:10], axis=0), f)]
    koala = Path(data) / "meshes" / "koala_large.obj"
    if koala.is_file():
        from inertia.geometry.mesh_io import load_mesh
        kv, kf = (np.asarray(a) for a in load_mesh(str(koala))[:2])
        drop = np.random.default_rng(0).choice(len(kf), 10, replace=False)
        out.append(("koala (real), 10 one-face holes", kv, np.delete(kf, drop, axis=0), kf))
    return out


def _round(cases, threads):
    """One round of every case: wall seconds of the public call, ``robust_integrals`` alone and the
    exact path on the closed mesh, and the CPU seconds of the public call."""
    kw = {} if threads is None else {"threads": threads}
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _, v, fo, fc in cases:
            t, c = time.perf_counter(), time.process_time()
            inertia.mesh_properties(v, fo, density=1.0, on_defect="robust")
            row = [time.perf_counter() - t, time.process_time() - c]
            t = time.perf_counter()
            robust_integrals(v, fo, **kw)
            row.append(time.perf_counter() - t)
            t = time.perf_counter()
            inertia.mesh_properties(v, fc, density=1.0)
            out.append(row + [time.perf_counter() - t])
    return out


def _worker(data):
    """``--speed-worker``: a round of :func:`_round` per line read, its figures printed as JSON (the
    interpreter of another install, run beside ours by ``--speed --against``)."""
    cases = speed_cases(data)
    for _ in range(3):
        _round(cases, None)          # warm: numba's cache, first-call costs
    print("ready", flush=True)
    for _ in sys.stdin:
        print(json.dumps(_round(cases, None)), flush=True)


def speed(data, rounds, against=None, threads=None):
    """Interleaved rounds of ours and, with ``against`` (another install's Python), of that install."""
    cases = speed_cases(data)
    other = None
    if against:
        env = {k: x for k, x in os.environ.items() if k != "PYTHONPATH"}
        other = subprocess.Popen([against, __file__, "--speed-worker", "--data", data], stdin=subprocess.PIPE,
                                 stdout=subprocess.PIPE, text=True, env=env, cwd=REPO)
        assert other.stdout.readline().strip() == "ready"
    for _ in range(3):
        _round(cases, threads)
    ours, theirs = [], []
    for _ in range(rounds):
        ours.append(_round(cases, threads))
        if other:
            other.stdin.write("go\n")
            other.stdin.flush()
            theirs.append(json.loads(other.stdout.readline()))
    if other:
        other.stdin.close()
        other.wait()
    print("## Speed: whole public call, 100k-face open meshes (wall s; best / median of interleaved rounds)")
    print(f"threads={threads} (None: one per core); the other install: {against or 'not run'}")
    print("| case | faces | install | public call on_defect='robust' (wall) | CPU s of it | Mfaces/s (best) "
          "| robust_integrals alone | exact path, closed mesh |")
    print("|---|---|---|---|---|---|---|---|")
    fmt = lambda x: f"{min(x):.3f} / {np.median(x):.3f}"  # noqa: E731
    for i, (name, _, fo, _) in enumerate(cases):
        for label, runs in (("this", ours), ("other", theirs)):
            if not runs:
                continue
            col = [np.array([r[i][j] for r in runs]) for j in range(4)]
            print(f"| {name} | {len(fo)} | {label} | {fmt(col[0])} | {fmt(col[1])} | {len(fo) / col[0].min() / 1e6:.2f} "
                  f"| {fmt(col[2])} | {fmt(col[3])} |")
        if theirs:
            r = [np.array([x[i][j] for x in runs]) / np.array([x[i][j] for x in ours]) for j, runs in
                 ((0, theirs), (2, theirs))]
            print(f"| {name} | | other / this | {np.median(r[0]):.2f} (median of rounds) | | | "
                  f"{np.median(r[1]):.2f} | |")
    print()
    print("Memory of a fresh process (MiB): resident after imports and loading the mesh / peak during the exact "
          "path on the closed mesh / peak during the robust call on the open one (VmHWM, reset before each call)")
    with tempfile.TemporaryDirectory() as d:
        for i, (name, v, fo, fc) in enumerate(cases):
            path = Path(d) / f"{i}.npz"
            np.savez(path, v=v, fo=fo, fc=fc)
            print(f"  {name}: this {_rss(path, sys.executable)}" + (f"; other {_rss(path, against)}" if against else ""))


def _rss(path, python):
    """Resident memory (MiB) of a fresh process of ``python``: after importing and loading the mesh,
    the peak during the exact path on the closed mesh, the peak during the robust call on the
    open one (Linux: the peak is reset through /proc/self/clear_refs before each call)."""
    code = f"""
import re, warnings
import numpy as np, inertia
def mib(key):
    return int(re.search(key + r":\\s+(\\d+)", open("/proc/self/status").read()).group(1)) // 1024
def peak(call):
    open("/proc/self/clear_refs", "w").write("5")
    call()
    return mib("VmHWM")
a = np.load({str(path)!r})
v, fo, fc = a["v"], a["fo"], a["fc"]
warnings.simplefilter("ignore")
r0 = mib("VmRSS")
r1 = peak(lambda: inertia.mesh_properties(v, fc, density=1.0))
r2 = peak(lambda: inertia.mesh_properties(v, fo, density=1.0, on_defect="robust"))
print(f"{{r0}} / {{r1}} / {{r2}}")
"""
    env = dict(os.environ)
    if python != sys.executable:
        env.pop("PYTHONPATH", None)
    out = subprocess.run([python, "-c", code], capture_output=True, text=True, env=env)
    return out.stdout.strip() or out.stderr.strip().splitlines()[-1]


def table(n_cases, tol):
    print(f"## Accuracy and bound on generated cases (tol={tol:g}, {n_cases} cases per kind)")
    print("| kind | cases | worst error / bound | largest error (vol, rel.) | bound vol (median / max) "
          "| bound inertia (median / max) | converged | s per case (max) |")
    print("|---|---|---|---|---|---|---|---|")
    for kind in list(CASES) + list(OTHER_CASES):
        rng = np.random.default_rng(zlib.crc32(kind.encode()))
        rows = []
        for _ in range(n_cases):
            _, v, f, truth = random_case(rng, kind)
            t = time.perf_counter()
            res = robust_integrals(v, f, reference=ORIGIN, tol=tol)
            dt = time.perf_counter() - t
            rel = res.bounds
            rows.append((error_ratio(res, truth), abs(res.volume - truth[0]) / abs(truth[0]), rel["volume"],
                         rel["inertia"], res.converged, dt))
        a = np.array(rows, float)
        honest = f"{a[:, 0].max():.2g}" + ("" if kind in CASES else " (not the GWN truth)")
        print(f"| {kind} | {len(a)} | {honest} | {a[:, 1].max():.1e} | {np.median(a[:, 2]):.1e} / {a[:, 2].max():.1e} "
              f"| {np.median(a[:, 3]):.1e} / {a[:, 3].max():.1e} | {int(a[:, 4].sum())}/{len(a)} "
              f"| {np.mean(a[:, 5]):.3f} ({a[:, 5].max():.2f}) |")


def real(data):
    import trimesh

    print("## Real imperfect meshes (density 1000; mass in the file's units^3 x 1000)")
    print("| file | faces | defects | inertia robust: mass (bounds vol / COM / inertia) | s "
          "| trimesh mass | MuJoCo legacy mass |")
    print("|---|---|---|---|---|---|---|")
    for name in ("teapot_open.stl", "soup.stl", "cycloidal.ply"):
        path = Path(data) / "meshes" / name
        if not path.is_file():
            print(f"| {name} | missing | | | | | |")
            continue
        t = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                p = inertia.mesh_file_properties(str(path), density=1000.0, on_defect="robust")
            text = [f.message for f in p.findings if "relative error bounds" in f.message][0]
            bounds = text.split("relative error bounds: ")[1].split(";")[0]
            ours = f"{p.mass:.6g} ({bounds})"
        except inertia.errors.MeshError as exc:
            ours = f"refused: {exc.code} ({str(exc).split(':')[1].split('(')[0].strip()[:60]})"
        dt = time.perf_counter() - t
        tm = trimesh.load(str(path), force="mesh", process=False)
        tm.density = 1000.0
        from inertia.geometry.mesh_io import load_mesh
        v, f = (np.asarray(a) for a in load_mesh(str(path))[:2])
        codes = ", ".join(robust_integrals(v, f, max_pieces=1000).codes)
        print(f"| {name} | {len(f)} | {codes} | {ours} | {dt:.2f} | {tm.mass:.6g} | {_mujoco_legacy(v, f)} |")


def _mujoco_legacy(v, f, density=1000.0):
    """MuJoCo's legacy mesh inertia: compile a one-body MJCF around the mesh (written as a
    binary STL, float32, which MuJoCo reads itself)."""
    try:
        import mujoco
    except ImportError:
        return "mujoco missing"
    with tempfile.TemporaryDirectory() as d:
        stl = Path(d) / "m.stl"
        rec = np.zeros(len(f), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
        rec["v"] = v[f]
        stl.write_bytes(b"bench".ljust(80, b" ") + np.uint32(len(f)).tobytes() + rec.tobytes())
        xml = (f'<mujoco><asset><mesh name="m" file="{stl}" inertia="legacy"/></asset><worldbody>'
               f'<body><freejoint/><geom type="mesh" mesh="m" density="{density}"/></body></worldbody></mujoco>')
        try:
            m = mujoco.MjModel.from_xml_string(xml)
        except Exception as exc:  # noqa: BLE001 (reported in the table)
            return f"error: {str(exc).splitlines()[0][:60]}"
    return f"{m.body_mass[1]:.6g}"


def manifold(path):
    """manifold3d's boolean union of overlapping closed shells beside the robust path."""
    sys.path.insert(0, path)
    try:
        import manifold3d as m3
    except ImportError as exc:
        print("manifold3d not importable:", exc)
        return
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    def union(v, f):
        n = len(v)
        e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        _, lab = connected_components(coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n)), directed=False)
        parts = []
        for c in np.unique(lab[f[:, 0]]):
            used, inv = np.unique(f[lab[f[:, 0]] == c], return_inverse=True)
            parts.append(m3.Manifold(m3.Mesh64(vert_properties=np.ascontiguousarray(v[used]),
                                               tri_verts=inv.reshape(-1, 3).astype(np.uint64))))
        mesh = m3.Manifold.batch_boolean(parts, m3.OpType.Add).to_mesh64()
        return solid_integrals(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts).astype(np.int64),
                               reference=ORIGIN)[0]

    print("## manifold3d (boolean union, Mesh64) beside the robust path: overlapping closed shells")
    print("| case | faces | robust s | robust vol error (bound) | manifold3d s | manifold3d vol error |")
    print("|---|---|---|---|---|---|")
    from tests.geometry._robust_cases import combine, concat, intersection_moments, moments
    for n in (4000, 40000, 200000):
        a, b = hull(n // 2, 1), hull(n // 2, 2, c=(0.8, 0.0, 0.0))
        v, f = concat(a, b)
        truth = combine((1, moments(a)), (1, moments(b)), (-1, intersection_moments(a, b)))[0]
        robust_integrals(v, f)
        union(v, f)
        t = time.perf_counter()
        r = robust_integrals(v, f, reference=ORIGIN)
        tr = time.perf_counter() - t
        t = time.perf_counter()
        mv = union(v, f)
        tm = time.perf_counter() - t
        print(f"| two spheres | {len(f)} | {tr:.3f} | {abs(r.volume - truth) / truth:.1e} ({r.bound_volume / truth:.0e}) "
              f"| {tm:.3f} | {abs(mv - truth) / truth:.1e} |")
    rng = np.random.default_rng(7)
    cases = [random_case(rng, ("box union", "convex union")[i % 2]) for i in range(100)]
    for _, v, f, _ in cases:
        robust_integrals(v, f)
        union(v, f)
    er, em, tr, tm = 0.0, 0.0, 0.0, 0.0
    for _, v, f, truth in cases:
        t = time.perf_counter()
        r = robust_integrals(v, f, reference=ORIGIN)
        tr += time.perf_counter() - t
        t = time.perf_counter()
        mv = union(v, f)
        tm += time.perf_counter() - t
        er, em = max(er, abs(r.volume - truth[0]) / truth[0]), max(em, abs(mv - truth[0]) / truth[0])
    print(f"| 100 generated unions (12-80 faces) | | {tr / 100:.4f} | {er:.1e} | {tm / 100:.4f} | {em:.1e} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--speed", action="store_true")
    ap.add_argument("--against", default=None, metavar="PYTHON",
                    help="with --speed: another install's Python, measured in the same interleaved rounds")
    ap.add_argument("--threads", type=int, default=None, help="with --speed: robust_integrals(threads=...)")
    ap.add_argument("--speed-worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--real", action="store_true")
    ap.add_argument("--manifold", default=None, metavar="PATH", help="directory holding manifold3d")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--cases", type=int, default=100)
    ap.add_argument("--tol", type=float, default=1e-3)
    ap.add_argument("--data", default=str(REPO.parent / "shared" / "data"))
    a = ap.parse_args()
    if a.speed_worker:
        return _worker(a.data)
    if not (a.speed or a.table or a.real or a.manifold):
        a.speed = a.table = a.real = True
    if a.speed:
        speed(a.data, a.rounds, a.against, a.threads)
    if a.table:
        table(a.cases, a.tol)
    if a.real:
        real(a.data)
    if a.manifold:
        manifold(a.manifold)


if __name__ == "__main__":
    main()

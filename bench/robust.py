"""Benchmark of inertia.geometry.robust.robust_integrals on generated meshes.

Run from the repository root:  ``PYTHONPATH=$PWD/src python bench/robust.py [--faces 100000]``.
Prints, per case: faces, seconds (median of --repeat runs, numba compiled beforehand),
faces/s, peak traced memory (tracemalloc: NumPy buffers included), the relative bounds,
the true relative error where a closed form is known, and the refinement statistics.
Optional: ``--manifold /path`` adds that directory to sys.path and, when manifold3d
imports from it, times its boolean union on the overlapping-shells case for comparison.
"""

from __future__ import annotations

import argparse
import sys
import time
import tracemalloc

import numpy as np
from scipy.spatial import ConvexHull

from inertia.geometry.integrals import solid_integrals
from inertia.geometry.robust import robust_integrals


def hull(n_faces, seed, r=1.0, c=(0.0, 0.0, 0.0)):
    """Convex polyhedron with about n_faces outward faces (hull of points on a sphere)."""
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(n_faces // 2 + 2, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    f = ConvexHull(p).simplices.copy()
    nrm = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    flip = (nrm * p[f].mean(1)).sum(1) < 0
    f[flip] = f[flip][:, ::-1]
    return p * r + np.asarray(c), f


def measure(v, f, repeat, **kw):
    robust_integrals(v, f, **kw)                      # compile / warm up
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        res = robust_integrals(v, f, **kw)
        times.append(time.perf_counter() - t)
    tracemalloc.start()
    robust_integrals(v, f, **kw)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return res, float(np.median(times)), peak


def report(name, res, dt, peak, n_faces, truth=None):
    rel = res.relative_bounds
    err = "" if truth is None else f" true vol err {abs(res.volume - truth) / abs(truth):.2e}"
    st = res.stats
    print(f"{name:34s} F={n_faces:7d} {dt:7.3f} s {n_faces / dt / 1e6:6.2f} Mfaces/s peak {peak / 2**20:6.1f} MiB "
          f"bound vol {rel['volume']:.1e} com {rel['com']:.1e} I {rel['inertia']:.1e}{err} "
          f"conv={res.converged} cut={st.get('cut_faces')} pieces={st.get('pieces')} "
          f"amb={res.ambiguous_fraction:.1e}", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--faces", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tol", type=float, default=1e-3)
    ap.add_argument("--manifold", default=None)
    a = ap.parse_args()
    n = a.faces
    v, f = hull(n, 0)
    exact = solid_integrals(v, f)[0]
    res, dt, peak = measure(v, f, a.repeat, tol=a.tol)
    report("closed", res, dt, peak, len(f), exact)
    fo = np.delete(f, [len(f) // 2], axis=0)
    res, dt, peak = measure(v, fo, a.repeat, tol=a.tol)
    report("open, 1 hole", res, dt, peak, len(fo), exact)
    fo = np.delete(f, np.arange(0, len(f), len(f) // 10)[:10], axis=0)
    res, dt, peak = measure(v, fo, a.repeat, tol=a.tol)
    report("open, 10 holes", res, dt, peak, len(fo), exact)
    vv = np.concatenate([v, v])
    ff = np.concatenate([f, f[:, ::-1] + len(v)])
    res, dt, peak = measure(np.concatenate([v, v * 0.5]), ff, a.repeat, tol=a.tol)
    report("inside-out inner shell (cavity)", res, dt, peak, len(ff), exact * (1 - 0.125))
    ff = np.concatenate([f, f + len(v)])
    res, dt, peak = measure(vv, ff, a.repeat, tol=a.tol)
    report("same shell listed twice", res, dt, peak, len(ff), exact)
    for m in (2000, 20000):
        v1, f1 = hull(m, 1)
        v2, f2 = hull(m, 2, c=(0.8, 0.0, 0.0))
        V = np.concatenate([v1, v2])
        F = np.concatenate([f1, f2 + len(v1)])
        res, dt, peak = measure(V, F, 1, tol=a.tol, time_budget=120)
        report(f"two overlapping spheres ({m} each)", res, dt, peak, len(F))
        if a.manifold:
            _manifold(a.manifold, v1, f1, v2, f2, res)


def _manifold(path, v1, f1, v2, f2, res):
    sys.path.insert(0, path)
    try:
        import manifold3d as m3
    except ImportError as exc:
        print("manifold3d not importable:", exc)
        return
    t = time.perf_counter()
    a = m3.Manifold(m3.Mesh(vert_properties=v1.astype(np.float32), tri_verts=f1.astype(np.uint32)))
    b = m3.Manifold(m3.Mesh(vert_properties=v2.astype(np.float32), tri_verts=f2.astype(np.uint32)))
    u = a + b
    mesh = u.to_mesh()
    dt = time.perf_counter() - t
    vol = solid_integrals(np.asarray(mesh.vert_properties, float), np.asarray(mesh.tri_verts))[0]
    print(f"    manifold3d union: {dt:.3f} s, volume {vol:.9f} (float32 vertices), robust {res.volume:.9f} "
          f"+- {res.bound_volume:.1e}, manifold volume() {u.volume():.9f}")


if __name__ == "__main__":
    main()

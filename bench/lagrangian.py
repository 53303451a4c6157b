"""Benchmark: derive, solve and generate code for the Z-Y-X Euler-angle equations.

Ours (inertia.symbolic: rigid-body E^T route, closed-form E^-1, CSE) against
sympy.physics.mechanics' LagrangesMethod on the same body in the same run: time and the
size of the result (sympy count_ops).  LagrangesMethod's own simplify took 241 s in the
issue's measurement (count_ops 2,008 after); pass --with-simplify to time it here.

    python bench/lagrangian.py [--repeat 5] [--with-simplify]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time


def ours(inertia: str):
    from sympy.core.cache import clear_cache

    from inertia.symbolic import derive

    clear_cache()  # sympy memoises; every run starts cold
    t0 = time.perf_counter()
    eom = derive("ZYX", inertia=inertia)
    t1 = time.perf_counter()
    eom.python_code(), eom.c_code(), eom.cse_latex()
    t2 = time.perf_counter()
    import sympy as sp

    flat = int(sum(sp.count_ops(e) for e in eom.accelerations))  # before CSE, for a like-for-like size
    return t1 - t0, t2 - t0, eom.count_ops, flat


def lagranges_method(inertia: str, simplify: bool):
    import sympy as sp
    from sympy.core.cache import clear_cache
    from sympy.physics import mechanics as me

    clear_cache()
    t0 = time.perf_counter()
    q = me.dynamicsymbols("psi theta phi")
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, q, "ZYX")
    O = me.Point("O")
    O.set_vel(N, 0)
    m = sp.Symbol("m")
    if inertia == "diagonal":
        I = me.inertia(B, *sp.symbols("J_xx J_yy J_zz"))
    else:
        Jxx, Jyy, Jzz, Jxy, Jyz, Jxz = sp.symbols("J_xx J_yy J_zz J_xy J_yz J_xz")
        I = me.inertia(B, Jxx, Jyy, Jzz, Jxy, Jyz, Jxz)
    body = me.RigidBody("B", O, B, m, (I, O))
    L = me.Lagrangian(N, body)
    lm = me.LagrangesMethod(L, q)
    lm.form_lagranges_equations()
    t1 = time.perf_counter()
    qdd = lm.mass_matrix.LUsolve(lm.forcing)  # accelerations M^-1 f
    t2 = time.perf_counter()
    ops = int(sum(sp.count_ops(e) for e in qdd))
    t3 = None
    if simplify:
        qdd_s = sp.simplify(qdd)
        t3 = time.perf_counter() - t0
        ops_s = int(sum(sp.count_ops(e) for e in qdd_s))
        return t1 - t0, t2 - t0, ops, t3, ops_s
    return t1 - t0, t2 - t0, ops, None, None


def cold_cli() -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "inertia.cli.main", "lagrangian", "--format", "c"],
                   check=True, capture_output=True)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--with-simplify", action="store_true", help="also time LagrangesMethod + simplify (minutes)")
    args = ap.parse_args()
    import sympy  # noqa: F401 - import once, outside the timings

    for inertia in ("diagonal", "full"):
        runs = [ours(inertia) for _ in range(args.repeat)]
        d = [r[0] for r in runs]
        e = [r[1] for r in runs]
        lm = [lagranges_method(inertia, False) for _ in range(args.repeat)]
        lm_eq = [r[0] for r in lm]
        lm_solve = [r[1] for r in lm]
        print(f"\nZ-Y-X, {inertia} inertia ({args.repeat} runs, min / median, seconds)")
        print(f"  ours: derive+solve+CSE        {min(d):.3f} / {statistics.median(d):.3f}")
        print(f"  ours: + Python, C, LaTeX code {min(e):.3f} / {statistics.median(e):.3f}   count_ops {runs[0][2]} "
              f"(CSE form; {runs[0][3]} written out without CSE)")
        print(f"  LagrangesMethod: equations    {min(lm_eq):.3f} / {statistics.median(lm_eq):.3f}")
        print(f"  LagrangesMethod: + LU solve   {min(lm_solve):.3f} / {statistics.median(lm_solve):.3f}   "
              f"count_ops {lm[0][2]} (unsimplified)")
        print(f"  ratio count_ops LagrangesMethod/ours: {lm[0][2] / runs[0][2]:.1f}x; "
              f"time ours end-to-end / LagrangesMethod equations only: {min(e) / min(lm_eq):.2f}")
        if args.with_simplify:
            r = lagranges_method(inertia, True)
            print(f"  LagrangesMethod + simplify: {r[3]:.1f} s, count_ops {r[4]}")
    cold = [cold_cli() for _ in range(3)]
    print(f"\ncold `inertia lagrangian --format c` (new process, incl. Python and sympy import): "
          f"min {min(cold):.3f} s, median {statistics.median(cold):.3f} s")


if __name__ == "__main__":
    main()

"""How closely our UsdPhysics mass properties match usd-core's ``ComputeMassProperties``.

Usage::

    python bench/usd_oracle.py [--seeds 200]

Three sets of stages (the builders of ``tests/robots/test_usd.py``): OpenUSD's own rigid-body
test cases, the float32-exact stages of every precedence rule, and ``--seeds`` generated stages
with every shape, scaled, rotated and nested.  For each body, usd-core is fed our per-collider
values and the largest relative difference in mass, COM (relative to the body's size) and
tensor (relative to its largest entry) is reported.  usd-core computes in float32.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def rel_error(ours, theirs) -> float:
    m, c, I = theirs[:3]
    size = max(np.abs(ours.com_B).max(), np.sqrt(np.abs(ours.I_B).max() / ours.mass), 1e-300)
    return max(abs(ours.mass - m) / abs(m), np.abs(ours.com_B - c).max() / size,
               np.abs(ours.I_B - I).max() / np.abs(I).max())


def main(argv=None) -> int:
    from tests.robots import test_usd as t
    from tests.robots import usd_make as um

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=200)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        sets = {
            "OpenUSD testenv cases": [um.build(tmp, name)[0] for name in um.SCENARIOS],
            "float32-exact precedence rules": [t._exact_stage(tmp, rule) for rule in t.EXACT_RULES],
            "generated stages (every shape, scaled, rotated)": [t._general_stage(tmp, s) for s in range(args.seeds)],
        }
        for label, paths in sets.items():
            errors = []
            for path in paths:
                stage = um.read(path)
                for i in range(len(stage.bodies)):
                    errors.append(rel_error(*um.oracle(stage, i)))
            e = np.array(errors)
            print(f"{label}: {len(e)} bodies, largest relative difference {e.max():.2e}, median {np.median(e):.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

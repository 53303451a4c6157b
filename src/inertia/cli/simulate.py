"""``inertia simulate``: torque-free rotation of a rigid body, exactly or with an integrator.

The body is either ``--moments I1,I2,I3`` (principal moments in kg m^2; the body axes are
the principal axes) or a SOURCE (a mesh file or a primitive spec such as
``box:0.1,0.2,0.4``, with the mass options of ``inertia props``).  For a SOURCE the motion
is computed in its principal frame and reported in the SOURCE's own axes, about its
center of mass: ``--omega`` and ``--q0`` are read in those axes too.

Output per sample: time ``t`` [s], ``omega_body`` [rad/s] (body frame), ``q_world_body``
(unit quaternion ``(w, x, y, z)``, body -> world), kinetic ``energy`` [J] and
``angular_momentum_norm`` ``|I w|`` [kg m^2/s].  ``--method exact`` evaluates the closed-form
solution (:mod:`inertia.dynamics.exact`); any name of
``inertia.dynamics.integrators.METHODS`` integrates with fixed steps.

Only the standard library is imported at module level (``inertia --help`` must start fast).
"""

from __future__ import annotations

import math

from . import _format as fmt

#: samples refused beyond this (memory and time guard)
MAX_SAMPLES = 5_000_000
#: Integrator steps a run may take unless --max-steps allows more (well under a second; the
#: exact solution takes no steps).
DEFAULT_MAX_STEPS = 1_000_000

CONVENTIONS = ("SI units; omega_body in rad/s in the body frame; q_world_body scalar-first (w, x, y, z), "
               "body -> world; energy = 1/2 w.I w in J; angular_momentum_norm = |I w| in kg m^2/s")

EPILOG = """\
examples:
  inertia simulate --moments 1,2,3 --omega 0.01,1,0 --duration 60 --step 0.5
  inertia simulate --moments 1,2,3 --omega 0.01,1,0 --times 0,20.75,1e6 --format json
  inertia simulate --moments 1,2,3 --omega 0.01,1,0 --duration 60 --step 0.01 --method rk4 --format csv
  inertia simulate --moments 1,2,3 --omega 0.01,1,0 --duration 1e4 --step 0.01 --every 1000 --method splitting
  inertia simulate --moments 1,2,3 --omega 0.01,1,0 --duration 100 --step 0.01 --output-step 2.5 --method dmv
  inertia simulate box:0.1,0.2,0.4 --mass 2 --omega 0,5,0.05 --duration 10 --step 0.1

times: --step H is the integrator's time step; the samples are separate.  --duration T
samples t = 0, H, 2H, ... and T (the last step is shortened when T is not a whole number of
steps); add --every N to sample every N steps (0, N H, 2 N H, ... and T), or --output-step D
to sample every D seconds (0, D, 2D, ... and T; steps of at most H, equal within each
interval).  --times lists the sample times (steps of at most H between them).
--method exact takes no steps: --step only spaces the samples of --duration.
On a terminal, a run of an integrator that lasts more than a second draws a progress bar on
stderr.

JSON keys: t (N), omega_body (N x 3), q_world_body (N x 4), energy (N),
angular_momentum_norm (N), plus method, moments, regime, period, conventions.

exit status: 0 on success, 1 on bad input (the message names the problem), 2 on bad usage."""

HELP = "torque-free rotation: exact solution or a fixed-step integrator"
DESCRIPTION = ("Torque-free rotation of a rigid body from an initial angular velocity: the exact "
               "closed-form solution (--method exact, any time at the same cost) or a fixed-step "
               "integrator.  Prints the angular velocity, attitude quaternion, energy and |L| at "
               "each sample time.")


# ============================================================================ shared with `flip`
def allow_negative_lists(p) -> None:
    """Let option values such as ``--omega -0.4,0.3,-0.7`` start with a minus sign.

    argparse (before Python 3.13) only recognises plain negative numbers as values, so
    ``-0.4,0.3,-0.7`` would be taken for an unknown option.  This widens the parser's
    negative-number pattern (a private attribute, hence the guard); ``--omega=-0.4,...``
    works everywhere regardless.
    """
    import re

    if hasattr(p, "_negative_number_matcher"):
        p._negative_number_matcher = re.compile(r"^-\.?\d")


def add_body_arguments(p) -> None:
    """SOURCE or --moments, --omega, and the SOURCE options (shared blocks)."""
    from ._options import add_body_options, add_mesh_options

    allow_negative_lists(p)

    p.add_argument("source", nargs="?", metavar="SOURCE",
                   help="instead of --moments: a mesh file or a primitive NAME:numbers such as box:0.1,0.2,0.4 "
                        "(inertia help source)")
    p.add_argument("--moments", metavar="I1,I2,I3",
                   help="principal moments of inertia in kg m^2 along the body x, y, z axes (any order)")
    p.add_argument("--omega", metavar="W1,W2,W3", required=True,
                   help="initial angular velocity in rad/s in the body frame (SOURCE: in its axes)")
    add_body_options(p)
    add_mesh_options(p)


def parse_numbers(text, option: str, count: int | None = None, *, what: str = "numbers") -> list:
    """Comma-separated finite floats; InputError naming ``option`` and the bad item."""
    from .._core.errors import InputError

    if text is None:
        raise InputError(f"{option} is required")
    parts = [s.strip() for s in str(text).split(",")]
    if parts == [""]:
        parts = []
    if count is not None and len(parts) != count:
        raise InputError(f"{option} takes {count} comma-separated {what}, got {len(parts)}: {text!r}")
    if not parts:
        raise InputError(f"{option} needs at least one number, got {text!r}")
    values = []
    for i, s in enumerate(parts):
        try:
            v = float(s)
        except ValueError:
            raise InputError(f"{option}: item {i + 1} = {s!r} is not a number (in {text!r})") from None
        if not math.isfinite(v):
            raise InputError(f"{option}: item {i + 1} = {s!r} must be finite (in {text!r})")
        values.append(v)
    return values


class Body:
    """The body to simulate: moments in the frame P of the computation and the map to the
    output frame B (``R_BP``; identity for --moments)."""

    def __init__(self, moments, R_BP, label: str, info=None):
        self.moments = moments      # numpy (3,), in frame P
        self.R_BP = R_BP            # numpy (3, 3)
        self.label = label
        self.info = info            # SourceInfo or None

    def to_dict(self) -> dict:
        out = {"moments": self.moments}
        if self.info is not None:
            out.update(self.info.to_dict(fmt.Units()))
            out["R_body_principal"] = self.R_BP
        return out


def resolve_body(args) -> Body:
    """Body from SOURCE or --moments (exactly one), validated (physical principal moments)."""
    import numpy as np

    from .._core.errors import InputError
    from ..massprops.validity import as_principal_moments

    if args.source is not None and args.moments is not None:
        raise InputError(f"give either SOURCE ({args.source!r}) or --moments ({args.moments!r}), not both")
    if args.source is None and args.moments is None:
        raise InputError("give the body: --moments I1,I2,I3 (principal moments in kg m^2) or a SOURCE "
                         "(a mesh file or a primitive spec such as box:0.1,0.2,0.4)")
    if args.source is None:
        used = [flag for flag, on in (("--density", args.density is not None), ("--mass", args.mass is not None),
                                      ("--shell", args.shell), ("--units", args.units not in (None, "m")),
                                      ("--fix-orientation", args.fix_orientation),
                                      ("--accept-defects", args.accept_defects)) if on]
        if used:
            raise InputError(f"{', '.join(used)} appl{'ies' if len(used) == 1 else 'y'} to a SOURCE only, "
                             f"not to --moments")
        I = as_principal_moments(parse_numbers(args.moments, "--moments", 3, what="moments (kg m^2)"), "--moments",
                                 allow_batch=False)
        return Body(I, np.eye(3), f"moments {fmt.vector(I)} kg m^2")
    from ._source import load_source

    props, info = load_source(args, source=args.source)
    pf = props.principal()
    I = as_principal_moments(pf.moments, f"principal moments of {args.source}", allow_batch=False)
    label = f"{args.source} (principal moments {fmt.vector(I)} kg m^2)"
    return Body(I, np.asarray(pf.R_body_principal, float), label, info)


def initial_state(args, body):
    """``(omega0_P, q0_WP)`` in the computation frame P from --omega and --q0 (given in frame B)."""
    import numpy as np

    from .._core.errors import InputError
    from .._core.rotations import matrix_to_quat, quat_multiply
    from .._core.tolerances import QUAT_NORM_TOL

    w_B = np.array(parse_numbers(args.omega, "--omega", 3, what="components (rad/s)"))
    q_text = getattr(args, "q0", None)
    if q_text is None:
        q_WB = np.array([1.0, 0.0, 0.0, 0.0])
    else:
        q_WB = np.array(parse_numbers(q_text, "--q0", 4, what="quaternion components (w, x, y, z)"))
        norm = float(np.linalg.norm(q_WB))
        if abs(norm - 1.0) > QUAT_NORM_TOL:
            raise InputError(f"--q0 must be a unit quaternion (w, x, y, z) (|q| - 1 within {QUAT_NORM_TOL:g}), "
                             f"got |q| = {norm:.12g}")
        q_WB = q_WB / norm
    w_P = body.R_BP.T @ w_B
    q_WP = quat_multiply(q_WB, matrix_to_quat(body.R_BP))
    return w_P, q_WP


def to_output_frame(body, q_WP, w_P):
    """Map (N, 4) quaternions and (N, 3) angular velocities from frame P back to the body frame B."""
    from .._core.rotations import matrix_to_quat, quat_conjugate, quat_multiply

    w_B = w_P @ body.R_BP.T
    q_WB = quat_multiply(q_WP, quat_conjugate(matrix_to_quat(body.R_BP)))
    return q_WB, w_B


# ============================================================================ simulate
def register(sub) -> None:
    p = fmt.add_command(sub, "simulate", HELP, DESCRIPTION, EPILOG,
                        usage="[SOURCE | --moments I1,I2,I3] --omega W1,W2,W3 (--duration T --step H | --times "
                              "T1,...) [options]")
    add_body_arguments(p)
    p.add_argument("--q0", metavar="W,X,Y,Z",
                   help="initial attitude, unit quaternion body -> world, scalar first (default 1,0,0,0)")
    t = p.add_argument_group("sample times (give --duration with --step, or --times)")
    t.add_argument("--duration", type=float, metavar="T", help="end time in s (samples from t = 0)")
    t.add_argument("--step", type=float, metavar="H",
                   help="integrator time step in s (the largest step between samples); with --duration alone "
                        "also the sample spacing")
    t.add_argument("--every", type=int, metavar="N",
                   help="with --duration: a sample every N steps of --step (default 1)")
    t.add_argument("--output-step", type=float, metavar="D",
                   help="with --duration: a sample every D s, independent of --step")
    t.add_argument("--times", metavar="T1,T2,...", help="comma-separated sample times in s")
    p.add_argument("--method", default="exact", metavar="NAME",
                   help="exact (default) or an integrator of inertia.dynamics.integrators.METHODS: "
                        "euler_explicit, euler_implicit, rk4, splitting, dmv, dmv4, midpoint")
    p.add_argument("--max-steps", type=int, default=DEFAULT_MAX_STEPS, metavar="N",
                   help=f"refuse a run that needs more than N integrator steps (default {DEFAULT_MAX_STEPS:,}); "
                        "the count is estimated before any step is taken")
    p.add_argument("--format", choices=("table", "csv", "json"), default="table",
                   help="table: aligned text (default); csv: one row per sample; json: arrays")
    p.set_defaults(func=run)


def available_methods() -> tuple:
    """``("exact", <integrator names>...)``; only ``exact`` when the integrators are unavailable."""
    try:
        from ..dynamics.integrators import METHODS
    except ImportError:
        return ("exact",)
    return ("exact",) + tuple(METHODS)


def _check_positive(value, option: str, *, allow_zero: bool = False) -> float:
    from .._core.errors import InputError

    v = float(value)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        rel = "non-negative" if allow_zero else "positive"
        raise InputError(f"{option} must be a finite {rel} number of seconds, got {value!r}")
    return v


def sample_plan(args, method: str):
    """``(times, h_max)``: the sample times (numpy (N,)) and the largest step for integrators."""
    import numpy as np

    from .._core.errors import InputError

    if args.times is not None and args.duration is not None:
        raise InputError(f"give either --times or --duration/--step, not both (got --times {args.times!r} "
                         f"and --duration {args.duration!r})")
    every, output_step = getattr(args, "every", None), getattr(args, "output_step", None)
    if every is not None and output_step is not None:
        raise InputError(f"give either --every ({every}) or --output-step ({output_step!r}), not both")
    step = None if args.step is None else _check_positive(args.step, "--step")
    if args.times is not None:
        if every is not None or output_step is not None:
            raise InputError("--every and --output-step space the samples of --duration; --times lists them")
        return _listed_times(args, method, step), step
    if args.duration is None:
        raise InputError("give the sample times: --duration T with --step H, or --times T1,T2,...")
    duration = _check_positive(args.duration, "--duration", allow_zero=True)
    if step is None and (method != "exact" or output_step is None):
        raise InputError(f"--duration {args.duration!r} needs --step (the time step in s)")
    if output_step is not None:
        spacing = _check_positive(output_step, "--output-step")
    elif every is not None:
        if every < 1:
            raise InputError(f"--every must be a positive whole number of steps, got {every}")
        spacing = every * step
    else:
        spacing = step
    n = math.ceil(duration / spacing - 1e-9)
    if n + 1 > MAX_SAMPLES:
        raise InputError(f"--duration {duration:g} sampled every {spacing:g} s gives {n + 1} samples, more than the "
                         f"limit {MAX_SAMPLES}; sample less often (--every, --output-step) or use --times")
    times = np.arange(n + 1, dtype=float) * spacing
    times[-1] = duration
    return times, step


def _listed_times(args, method: str, step):
    import numpy as np

    from .._core.errors import InputError

    times = np.array(parse_numbers(args.times, "--times", what="times (s)"))
    if len(times) > MAX_SAMPLES:
        raise InputError(f"--times lists {len(times)} samples, more than the limit {MAX_SAMPLES}")
    if method != "exact":
        if step is None:
            raise InputError(f"--method {method} integrates with fixed steps: give --step (the largest "
                             f"step in s) with --times")
        if times[0] < 0 or np.any(np.diff(times) < 0):
            raise InputError(f"--times must be non-negative and in increasing order for --method {method} "
                             f"(only --method exact evaluates any time), got {args.times!r}")
    return times


def run_exact(body, w_P, q_WP, times):
    from ..dynamics.exact import ExactSolution

    sol = ExactSolution(body.moments, w_P, q_WP)
    q, w = sol.at(times)
    return q, w, sol


#: Scales the computation represents: the angular momentum I w (kg m^2/s) and the kinetic
#: energy I w^2 (J) of the spin.  Their squares (|L|^2, the elliptic parameters) must stay
#: finite and normal in double precision (1e-308 .. 1e308); beyond, |omega| overflows to inf,
#: or |L| underflows to 0 and the body looks at rest.
MOMENTUM_RANGE = (1e-140, 1e140)
ENERGY_RANGE = (1e-280, 1e280)


def check_spin_scale(moments, w_P) -> None:
    """Refuse a spin whose momentum or energy scale double precision cannot carry, by name."""
    import numpy as np

    from .._core.errors import InputError

    w = float(np.max(np.abs(w_P)))
    if w == 0.0:
        return
    big = float(np.max(moments))
    log_L, log_E = math.log10(big) + math.log10(w), math.log10(big) + 2.0 * math.log10(w)   # logs: no overflow
    for what, unit, log_v, (lo, hi) in (("angular momentum I w", "kg m^2/s", log_L, MOMENTUM_RANGE),
                                        ("kinetic energy I w^2", "J", log_E, ENERGY_RANGE)):
        if not math.log10(lo) <= log_v <= math.log10(hi):
            raise InputError(f"the {what} of this spin is about 1e{log_v:.0f} {unit}, outside the range "
                             f"[{lo:g}, {hi:g}] {unit} that double precision carries through the computation "
                             f"(|omega| {w:.3g} rad/s, largest moment {big:.3g} kg m^2); express the body in "
                             f"other units")


def check_work(times, h_max, method: str, max_steps: int) -> None:
    """Refuse, before any step, a run whose step count exceeds ``--max-steps``."""
    from .._core.errors import InputError

    if max_steps is None or max_steps < 1:
        raise InputError(f"--max-steps must be a positive whole number, got {max_steps!r}")
    import numpy as np

    gaps = np.diff(np.concatenate(([0.0], np.asarray(times, dtype=float))))
    estimate = float(np.sum(np.ceil(gaps[gaps > 0] / h_max - 1e-9)))   # float: never overflows
    if estimate > max_steps:
        raise InputError(f"--method {method} would take about {estimate:.3g} steps of at most --step {h_max:g} s "
                         f"to reach t = {float(times[-1]):g} s, more than --max-steps {max_steps:,}; use a larger "
                         f"--step, fewer or earlier --times, --method exact (any time at the same cost), or "
                         f"raise --max-steps")


def step_plan(times, h_max):
    """``(counts, hs)``: per interval between samples, equal steps of at most ``h_max``."""
    import numpy as np

    gaps = np.diff(np.concatenate(([0.0], np.asarray(times, dtype=float))))
    counts = np.where(gaps > 0, np.maximum(1, np.ceil(gaps / h_max - 1e-9)), 0).astype(np.int64)
    hs = np.where(counts > 0, gaps / np.maximum(counts, 1), h_max)
    return counts, hs


def run_integrator(body, w_P, q_WP, times, h_max, method: str):
    """Fixed steps of at most ``h_max`` between consecutive sample times (equal steps per interval),
    in one call of the integrator; a progress bar on a terminal when that takes over a second."""
    from .._core.progress import Progress
    from ..dynamics.integrators import integrate_segments

    counts, hs = step_plan(times, h_max)
    bar = Progress(int(counts.sum()), unit="steps", tty_only=True, delay=1.0)
    try:
        traj = integrate_segments(q_WP, w_P, body.moments, counts, hs, method=method, progress=bar.update)
    finally:
        bar.clear()
    return traj.q_world_body[1:], traj.omega_body[1:]


def run(args) -> int:
    import numpy as np

    from .._core.errors import InputError

    method = args.method
    methods = available_methods()
    if method not in methods:
        raise InputError(f"--method must be one of {', '.join(methods)}, got {method!r}")
    body = resolve_body(args)
    w_P, q_WP = initial_state(args, body)
    check_spin_scale(body.moments, w_P)
    times, h_max = sample_plan(args, method)
    sol = None
    if method == "exact":
        q_P, w_Pt, sol = run_exact(body, w_P, q_WP, times)
    else:
        check_work(times, h_max, method, args.max_steps)
        q_P, w_Pt = run_integrator(body, w_P, q_WP, times, h_max, method)
    I = body.moments
    energy = 0.5 * np.sum(I * w_Pt * w_Pt, axis=-1)
    L_norm = np.linalg.norm(I * w_Pt, axis=-1)
    q_B, w_B = to_output_frame(body, q_P, w_Pt)
    data = {"t": times, "omega_body": w_B, "q_world_body": q_B, "energy": energy, "angular_momentum_norm": L_norm}
    for name, value in data.items():
        if not np.all(np.isfinite(value)):
            from .._core.errors import IntegrationError

            k = int(np.argmax(~np.all(np.isfinite(np.reshape(value, (len(times), -1))), axis=1)))
            raise IntegrationError(f"--method {method}: {name} is not finite at t = {times[k]:g} s (sample {k + 1}); "
                                   f"the method diverged at --step {h_max:g} s or the state left double "
                                   f"precision's range: try --method exact or a smaller --step")
    if args.format == "json":
        out = {"method": method}
        out.update(body.to_dict())
        if sol is not None:
            out.update({"regime": sol.regime, "period": sol.period})
        out.update(data)
        out["conventions"] = CONVENTIONS
        fmt.emit(fmt.to_json(out))
    elif args.format == "csv":
        fmt.emit(csv_lines(data))
    else:
        fmt.emit(table_lines(data, body, method, sol))
    return 0


COLUMNS = ("t", "omega_x", "omega_y", "omega_z", "q_w", "q_x", "q_y", "q_z", "energy", "angular_momentum_norm")


def _rows(data):
    for k in range(len(data["t"])):
        yield ([float(data["t"][k])] + [float(x) for x in data["omega_body"][k]]
               + [float(x) for x in data["q_world_body"][k]]
               + [float(data["energy"][k]), float(data["angular_momentum_norm"][k])])


def csv_lines(data) -> list:
    """Header and one row per sample, full precision (``repr`` of each float)."""
    return [",".join(COLUMNS)] + [",".join(repr(x) for x in row) for row in _rows(data)]


def table_lines(data, body, method: str, sol) -> list:
    pairs = [("body", body.label), ("method", method)]
    if sol is not None:
        pairs += [("regime", sol.regime), ("period of omega", f"{fmt.num(sol.period)} s")]
    pairs += [("energy at t = 0", f"{fmt.num(data['energy'][0])} J"),
              ("|L| at t = 0", f"{fmt.num(data['angular_momentum_norm'][0])} kg m^2/s")]
    lines = fmt.key_values(pairs, indent=0)
    lines.append("")
    header = ["t [s]", "wx", "wy", "wz [rad/s]", "qw", "qx", "qy", "qz", "energy [J]", "|L|"]
    lines += fmt.table(header, [[fmt.num(x) for x in row] for row in _rows(data)], indent=0)
    return lines

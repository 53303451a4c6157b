"""The readable equations ``M(q) q'' = f(q, q')``: equal to the CSE form at random states, equal
to the Lagrangian differentiated by sympy, and their LaTeX, parsed back by sympy's LaTeX
parser, equal to both; never simplify; the CLI formats (LaTeX, Markdown, HTML)."""

from __future__ import annotations

import re

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

from inertia.cli.main import main  # noqa: E402
from inertia.symbolic import derive  # noqa: E402
from inertia.symbolic.document import symbol_names  # noqa: E402
from inertia.symbolic.readable import readable_form  # noqa: E402
from inertia.symbolic.rigid import lagrangian  # noqa: E402
from tests.symbolic.test_symbolic import _flat_args, _numeric_kwargs, _random_angles, _random_body  # noqa: E402

CASES = [("ZYX", {}), ("ZYX", {"inertia": "diagonal"}), ("ZYX", {"gravity": True}), ("XYZ", {"translation": True}),
         ("ZXZ", {"gravity": True}), ("ZYX", {"translation": True, "gravity": True}), ("YZY", {})]
IDS = [f"{s}-{'+'.join(f'{k}={v}' for k, v in kw.items()) or 'rotation'}" for s, kw in CASES]


def _states(eom, rng, n=6):
    """Random states: (q, qd, numeric kwargs, value of every symbol of the system)."""
    s = eom.system
    for _ in range(n):
        props = _random_body(rng, diagonal=s.inertia_form == "diagonal", com=s.has_com)
        q = np.concatenate([rng.normal(size=len(s.position)), _random_angles(s.sequence, rng)])
        qd = rng.normal(size=s.n)
        kw = _numeric_kwargs(s, props, rng)
        params, inputs = _flat_args(s, props, kw)
        if s.inertia_form == "diagonal":
            params = params[:3] + params[6:]
            kw["inertia"] = np.diag(props.inertia_com)
        values = dict(zip(s.coordinates, q)) | dict(zip(s.rates, qd)) | dict(zip(s.parameters, params)) \
            | dict(zip(s.inputs, inputs))
        yield q, qd, kw, values


def _evaluate(exprs, values):
    symbols = list(values)
    fn = sp.lambdify(symbols, exprs, modules="numpy")
    return np.array(fn(*[values[k] for k in symbols]), float)


@pytest.mark.parametrize("seq, kw", CASES, ids=IDS)
def test_readable_form_solves_to_the_cse_accelerations(seq, kw):
    eom = derive(seq, **kw)
    form = eom.readable()
    f = eom.numeric()
    for q, qd, kwargs, values in _states(eom, np.random.default_rng(5)):
        M = _evaluate(form.M, values)
        rhs = _evaluate(form.f, values).ravel()
        expected = f(q, qd, **kwargs)
        np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-13 * np.abs(M).max())
        np.testing.assert_allclose(np.linalg.solve(M, rhs), expected, rtol=0, atol=1e-10 * max(1, np.abs(expected).max()))


@pytest.mark.parametrize("seq, kw", CASES[:4], ids=IDS[:4])
def test_mass_matrix_and_force_are_the_lagrangians(seq, kw):
    """M = d^2L/dq'^2 and f = Q + dL/dq - (d^2L/dq'dq) q', L differentiated by sympy here."""
    eom = derive(seq, **kw)
    s = eom.system
    form = eom.readable()
    L = lagrangian(s)
    qd = sp.Matrix(s.rates)
    p = sp.Matrix([L]).jacobian(s.rates).T
    nt = len(s.position)
    Q = sp.zeros(s.n, 1)
    Q[nt:, 0] = s.E.T * s.torque_body
    if s.has_com:
        Q += s.com_world().jacobian(s.coordinates).T * s.force_world
    f_lagrange = Q + sp.Matrix([L]).jacobian(s.coordinates).T - p.jacobian(s.coordinates) * qd
    for _, _, _, values in _states(eom, np.random.default_rng(8), n=4):
        np.testing.assert_allclose(_evaluate(form.M, values), _evaluate(p.jacobian(s.rates), values), atol=1e-12)
        np.testing.assert_allclose(_evaluate(form.f, values), _evaluate(f_lagrange, values), atol=1e-11)
        np.testing.assert_allclose(float(_evaluate(form.lagrangian, values)), float(_evaluate(L, values)), atol=1e-12)


def test_readable_form_never_simplifies(monkeypatch):
    import sys

    system = derive("ZYX", gravity=True).system        # derive's own nine trigsimp calls on adj E come first

    def refuse(*a, **k):
        raise AssertionError("simplify or trigsimp called")

    for module, name in (("sympy.simplify.simplify", "simplify"), ("sympy.simplify.trigsimp", "trigsimp")):
        monkeypatch.setattr(sys.modules[module], name, refuse)
    monkeypatch.setattr(sp, "simplify", refuse)
    monkeypatch.setattr(sp, "trigsimp", refuse)
    form = readable_form(system)
    assert form.M.shape == (3, 3)


# ----------------------------------------------------------------------------- LaTeX read back

parse_latex = pytest.importorskip("sympy.parsing.latex").parse_latex


def _parser_ready():
    try:
        parse_latex("x")
    except ImportError as exc:       # antlr4 runtime missing
        pytest.skip(f"sympy's LaTeX parser needs antlr4: {exc}")


def _entries(tex: str, letter: str) -> dict:
    """``{"11": latex, ...}`` of the rows ``M_{11} &= ...`` (with their continuation lines)."""
    out, current = {}, None
    for line in tex.splitlines():
        line = line.rstrip().removesuffix("\\\\").rstrip()
        m = re.match(rf"{letter}_\{{(\d+)\}} &= (.*)$", line)
        if m:
            current = m.group(1)
            out[current] = m.group(2)
        elif current and line.startswith(r"&\quad "):
            out[current] += " " + line[len(r"&\quad "):]
        else:
            current = None
    return out


def _parse(text: str, system):
    """sympy expression of one entry, the system's symbols substituted back in."""
    names = symbol_names(system)
    for k, rate in enumerate(system.rates):          # \dot{\psi} -> r_{k}: the parser knows no accents
        text = text.replace(names[rate], f"r_{{{k}}}")
    # "m \left(...\right)" reads as a product to a person and as a call of m to the parser
    expr = parse_latex(re.sub(r"(?<=[}\w]) \\left\(", r" \\cdot \\left(", text))
    back = {parse_latex(sp.latex(x)): x for x in (*system.coordinates, *system.parameters, *system.inputs)}
    back |= {parse_latex(f"r_{{{k}}}"): rate for k, rate in enumerate(system.rates)}
    unknown = expr.free_symbols - set(back)
    assert not unknown, unknown
    return expr.xreplace(back)


@pytest.mark.parametrize("seq, kw", [CASES[0], CASES[2]], ids=[IDS[0], IDS[2]])   # the parser is slow on 6-DOF
def test_latex_parses_back_to_the_same_equations(seq, kw):
    _parser_ready()
    eom = derive(seq, **kw)
    s = eom.system
    tex = eom.latex()
    M_tex, f_tex = _entries(tex, "M"), _entries(tex, "f")
    n = s.n
    M = sp.zeros(n, n)
    for key, text in M_tex.items():
        i, j = int(key[: len(key) // 2]) - 1, int(key[len(key) // 2:]) - 1
        M[i, j] = M[j, i] = _parse(text, s)
    f = sp.Matrix([_parse(f_tex[str(i + 1)], s) if str(i + 1) in f_tex else 0 for i in range(n)])
    rhs_cse = eom.numeric()
    for q, qd, kwargs, values in _states(eom, np.random.default_rng(3), n=4):
        M_v, f_v = _evaluate(M, values), _evaluate(f, values).ravel()
        np.testing.assert_allclose(np.linalg.solve(M_v, f_v), rhs_cse(q, qd, **kwargs), atol=1e-10)


def test_latex_lagrangian_parses_back():
    """omega components and T, read back from the LaTeX, give the Lagrangian sympy builds."""
    _parser_ready()
    eom = derive("ZYX")
    s = eom.system
    tex = eom.latex()
    w = [_parse(re.search(rf"\\omega_{{{a}}} &= (.*?)( \\\\)?$", tex, re.M).group(1), s) for a in "xyz"]
    T_text = re.search(r"^T &= (.*?)( \\\\)?$", tex, re.M).group(1)
    wsyms = {parse_latex(rf"\omega_{{{a}}}"): w[k] for k, a in enumerate("xyz")}
    T = parse_latex(T_text).xreplace(wsyms)
    T = T.xreplace({parse_latex(sp.latex(x)): x for x in s.parameters})
    for _, _, _, values in _states(eom, np.random.default_rng(4), n=3):
        assert float(_evaluate(T, values)) == pytest.approx(float(_evaluate(lagrangian(s), values)), rel=1e-12)


# ----------------------------------------------------------------------------- the command line


def test_cli_formats(capsys, tmp_path):
    assert main(["lagrangian"]) == 0
    tex = capsys.readouterr().out
    assert r"M(q)\,\ddot q &= f(q, \dot q)" in tex and r"\dot{\psi}" in tex and "x_{0}" not in tex
    assert "_d" not in re.sub(r"\\ddot|\\dot", "", tex.split("\n% Coordinates")[1])   # no psi_d in the equations
    assert main(["lagrangian", "--format", "markdown", "--sequence", "zxz"]) == 0
    md = capsys.readouterr().out
    assert md.startswith("# Equations of motion of a rotating rigid body in ZXZ Euler angles")
    assert md.count("$$") == 2 * 6 and r"\begin{aligned}" in md
    assert main(["lagrangian", "--format", "latex-cse"]) == 0
    assert "x_{0}" in capsys.readouterr().out          # the code-generation form stays
    assert main(["lagrangian", "--format", "html", "-o", str(tmp_path / "eom.html")]) == 0
    page = (tmp_path / "eom.html").read_text()
    assert "katex.render" in page and "data:font/woff2;base64," in page and "url(fonts/" not in page

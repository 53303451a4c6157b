"""README.md stays true: its two opening commands match CI, its Python examples run
(doctest), and the console output pasted in it is what the CLI prints today.

Regenerate the pasted console output after changing the CLI::

    python tests/cli/test_readme.py --update
"""

from __future__ import annotations

import contextlib
import doctest
import io
import os
import re
import shlex
import sys
import tempfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
CI = REPO / ".ci" / "run"

_BLOCK = re.compile(r"^```console\n(.*?)^```", re.S | re.M)


def opening_commands(text: str) -> list[str]:
    """The lines of the first fenced code block of the README."""
    m = re.search(r"^```[a-z]*\n(.*?)^```", text, re.S | re.M)
    return [line for line in m.group(1).splitlines() if line.strip()]


def run_cli(command: str) -> str:
    """stdout + stderr of ``$ inertia ...`` run in-process from the repository root."""
    from inertia.cli.main import main

    argv = shlex.split(command)
    assert argv[0] == "inertia", command
    out, err = io.StringIO(), io.StringIO()
    cwd = os.getcwd()
    # the demo writes its report folder into the working folder: run it in a fresh one
    os.chdir(tempfile.mkdtemp(prefix="inertia-readme-") if argv[1:2] == ["demo"] else REPO)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                main(argv[1:])
            except SystemExit:
                pass
    finally:
        os.chdir(cwd)
    return out.getvalue() + err.getvalue()


def console_sessions(text: str):
    """``(match, [(command, pasted output), ...])`` for each ```console block."""
    for m in _BLOCK.finditer(text):
        sessions, cmd, lines = [], None, []
        for line in m.group(1).splitlines():
            if line.startswith("$ "):
                if cmd is not None:
                    sessions.append((cmd, "\n".join(lines)))
                cmd, lines = line[2:], []
            else:
                lines.append(line)
        if cmd is not None:
            sessions.append((cmd, "\n".join(lines)))
        yield m, sessions


def _normal(text: str) -> str:
    return "\n".join(line.rstrip() for line in text.strip("\n").splitlines())


def update(path: Path = README) -> int:
    """Rewrite every ```console block of the README with fresh output; returns the number changed."""
    text = path.read_text(encoding="utf-8")
    pieces, pos, changed = [], 0, 0
    for m, sessions in console_sessions(text):
        body = "".join(f"$ {cmd}\n{_normal(run_cli(cmd))}\n" for cmd, _ in sessions)
        changed += body != m.group(1)
        pieces += [text[pos:m.start(1)], body]
        pos = m.end(1)
    pieces.append(text[pos:])
    path.write_text("".join(pieces), encoding="utf-8")
    return changed


# ---------------------------------------------------------------------------- tests


def test_readme_opens_with_the_two_commands_ci_runs():
    text = README.read_text(encoding="utf-8")
    assert text.index("```") < text.index("\n## ")  # the commands come first
    install_run, install_test = opening_commands(text)
    assert install_run == 'pip install ".[all]" && inertia demo'
    assert install_test.startswith('pip install ".[test]" && python -m pytest')
    ci_lines = [line.strip() for line in CI.read_text().splitlines()]
    # CI installs the wheel it built once, with the same test extra, then runs the same command
    test_command = install_test.split(" && ", 1)[1]
    assert any(line.endswith(f"&& {test_command}") and "[test]" in line for line in ci_lines), \
        "README's test command and .ci/run differ"
    if " -n " in install_test:  # xdist must be installed by the test extra
        assert "pytest-xdist" in (REPO / "pyproject.toml").read_text()


def test_readme_python_examples_run(monkeypatch):
    monkeypatch.chdir(REPO)
    text = README.read_text(encoding="utf-8")
    parser = doctest.DocTestParser()
    test = parser.get_doctest(text, {}, "README.md", str(README), 0)
    assert len(test.examples) > 20
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    out = io.StringIO()
    result = runner.run(test, out=out.write)
    assert result.failed == 0, out.getvalue()


@pytest.mark.parametrize("command", [cmd for _, s in console_sessions(README.read_text(encoding="utf-8"))
                                     for cmd, _ in s])
def test_readme_console_output_is_current(command):
    pasted = {cmd: out for _, s in console_sessions(README.read_text(encoding="utf-8")) for cmd, out in s}
    assert _normal(run_cli(command)) == _normal(pasted[command]), (
        f"README output of `{command}` is stale: run python tests/cli/test_readme.py --update")


if __name__ == "__main__":
    if sys.argv[1:] == ["--update"]:
        print(f"README.md: {update()} console block(s) updated")
    else:
        print(__doc__)

"""Run the command line in process: ``(exit code, stdout, stderr)``, a usage exit included."""

from __future__ import annotations

from inertia.cli.main import main


def run(capsys, *argv):
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    out, err = capsys.readouterr()
    return rc, out, err

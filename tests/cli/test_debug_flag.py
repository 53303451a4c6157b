"""``--debug`` works anywhere on the command line and only there changes error output."""

from __future__ import annotations

import pytest

from inertia.cli.main import _pop_debug, main


@pytest.mark.parametrize("argv, rest, debug", [
    (["--debug", "props", "x.stl"], ["props", "x.stl"], True),
    (["props", "x.stl", "--debug"], ["props", "x.stl"], True),
    (["props", "--debug", "x.stl"], ["props", "x.stl"], True),
    (["props", "x.stl"], ["props", "x.stl"], False),
    (["props", "--", "--debug"], ["props", "--", "--debug"], False),  # after --, a file name
])
def test_debug_flag_is_taken_anywhere_before_double_dash(argv, rest, debug):
    assert _pop_debug(argv) == (rest, debug)


def test_debug_after_the_subcommand_shows_the_traceback(tmp_path, capsys):
    missing = tmp_path / "missing.stl"
    # without --debug: a one-line named error, exit 1
    assert main(["props", str(missing)]) == 1
    err = capsys.readouterr().err
    assert "missing.stl" in err and "Traceback" not in err
    # with --debug after the subcommand: the error propagates (the traceback is shown)
    from inertia.errors import InertiaError
    with pytest.raises(InertiaError, match="missing.stl"):
        main(["props", str(missing), "--debug"])

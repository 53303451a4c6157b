"""docs/symbolic.md stays true: its Python examples run (doctest)."""

import doctest
from pathlib import Path

import pytest

pytest.importorskip("sympy")

DOC = Path(__file__).resolve().parents[2] / "docs" / "symbolic.md"


def test_symbolic_doc_examples_run():
    result = doctest.testfile(str(DOC), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0

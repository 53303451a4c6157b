"""Command-line tests run in a fresh working folder: ``inertia demo`` writes its report
folder into the working folder, and tests must not leave files in the repository (or race
each other for one folder under pytest-xdist)."""

import pytest


@pytest.fixture(autouse=True)
def _fresh_working_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)

"""Shared fixtures of the report tests: one demo report per session, one headless Chromium."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from tests.viz._helpers import CHROMIUM, CHROMIUM_ARGS


@pytest.fixture(scope="session")
def report(tmp_path_factory):
    """``inertia demo`` run once: the report folder of the steel T-handle."""
    pytest.importorskip("matplotlib")
    from inertia.cli.main import main

    out = tmp_path_factory.mktemp("demo") / "report"
    assert main(["demo", "--out", str(out), "--format", "json"]) == 0
    return out


@pytest.fixture(scope="session")
def browser():
    """Debian's Chromium, headless, through Playwright; skipped (or failed with
    INERTIA_REQUIRE_BROWSER=1) when either is missing."""
    required = bool(os.environ.get("INERTIA_REQUIRE_BROWSER"))
    if not shutil.which(CHROMIUM) and not Path(CHROMIUM).is_file():
        if required:
            pytest.fail(f"Chromium not found at {CHROMIUM} (INERTIA_REQUIRE_BROWSER is set)")
        pytest.skip(f"Chromium not found at {CHROMIUM}")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        if required:
            raise
        pytest.skip("playwright is not installed")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()

"""Helpers of the report tests: the browser's settings, a watched page, the demo's body."""

from __future__ import annotations

import os

CHROMIUM = os.environ.get("INERTIA_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]


def t_handle():
    """The demo's body: the steel T-handle (exact mass properties)."""
    from inertia.massprops.bodies import t_handle as make

    return make()


class Watched:
    """A page with its console errors, page errors and network requests recorded."""

    def __init__(self, browser, **kwargs):
        self.page = browser.new_page(**kwargs)
        self.problems: list[str] = []
        self.page.on("console", lambda m: self.problems.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.problems.append(str(e)))
        self.page.on("request", lambda r: self.problems.append(f"network: {r.url[:80]}")
                     if not r.url.startswith(("file:", "data:")) else None)

    def close(self):
        self.page.close()

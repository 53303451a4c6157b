"""The readable equations of motion as one offline HTML page, typeset by KaTeX.

KaTeX (vendored from the npm registry, MIT, see ``vendor/README.md``) is inlined: its
script as is, its stylesheet with every font as a ``data:`` URL (WOFF2, which every current
browser reads), so the page loads nothing from a network and opens from a ``file://`` URL.
Each block of :mod:`inertia.symbolic.document` becomes a heading, a sentence and one
display (``aligned``); a block KaTeX cannot parse shows its error in place, and
``window.katexErrors`` lists them (empty when everything rendered).
"""

from __future__ import annotations

import base64
import html
import json
import re

from .page import vendor_bytes


def katex_css() -> str:
    """KaTeX's stylesheet with each ``@font-face`` reduced to its WOFF2 font as a ``data:`` URL."""
    css = vendor_bytes("katex.min.css").decode("utf-8")

    def inline(match) -> str:
        name = match.group(1)
        data = base64.b64encode(vendor_bytes(f"{name}.woff2")).decode("ascii")
        return f'src:url(data:font/woff2;base64,{data}) format("woff2")'

    return re.sub(r"src:url\(fonts/([A-Za-z0-9_-]+)\.woff2\)[^;}]*", inline, css)


STYLE = """
:root { --bg: #fbfbfc; --fg: #1c2230; --muted: #5d6778; --line: #dde2e8; --panel: #fff; --err: #b3261e; }
@media (prefers-color-scheme: dark) {
  :root { --bg: #14171c; --fg: #e6e9ee; --muted: #9aa3b2; --line: #2c323c; --panel: #1b1f26; --err: #ff8a80; }
}
body { margin: 0; background: var(--bg); color: var(--fg);
       font: 16px/1.55 system-ui, -apple-system, "Segoe UI", sans-serif; }
main { max-width: 1100px; margin: 0 auto; padding: 1.5rem 1.2rem 3rem; }
h1 { font-size: 1.6rem; margin: 0 0 .4rem; }
.meta { color: var(--muted); font-size: .85rem; margin: 0 0 1.2rem; }
.meta div { margin: .1rem 0; }
section { background: var(--panel); border: 1px solid var(--line); border-radius: 10px; padding: .8rem 1rem;
          margin: 0 0 1rem; }
h2 { font-size: 1.1rem; margin: 0 0 .2rem; }
p { margin: 0 0 .4rem; color: var(--muted); }
.math { overflow-x: auto; overflow-y: hidden; padding: .2rem 0; }
.error { color: var(--err); font-family: ui-monospace, monospace; white-space: pre-wrap; }
@media print { section { break-inside: avoid; } .math { overflow: visible; } }
"""


def equations_html(doc, header: list[str], title: str) -> str:
    """The page: ``doc`` a list of :class:`~inertia.symbolic.document.Block`."""
    sections = []
    for b in doc:
        tex = "\\begin{aligned}" + " \\\\ ".join(b.rows) + "\\end{aligned}"
        sections.append(f"<section><h2>{html.escape(b.title)}</h2><p>{html.escape(b.text)}</p>"
                        f'<div class="math" data-tex="{html.escape(tex, quote=True)}"></div></section>')
    meta = "".join(f"<div>{html.escape(line)}</div>" for line in header)
    script = vendor_bytes("katex.min.js").decode("utf-8").replace("</script", "<\\/script")
    render = """
window.katexErrors = [];
for (const el of document.querySelectorAll(".math")) {
  try {
    katex.render(el.dataset.tex, el, {displayMode: true, throwOnError: true, strict: "ignore"});
  } catch (e) {
    window.katexErrors.push(String(e.message || e));
    el.innerHTML = "";
    const pre = document.createElement("div");
    pre.className = "error";
    pre.textContent = "KaTeX could not typeset this block: " + (e.message || e) + "\\n" + el.dataset.tex;
    el.appendChild(pre);
  }
}
window.katexDone = true;
"""
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f'<meta name="color-scheme" content="light dark"><title>{html.escape(title)}</title>'
            f"<style>{katex_css()}</style><style>{STYLE}</style></head><body><main>"
            f"<h1>{html.escape(title)}</h1><div class=\"meta\">{meta}</div>{''.join(sections)}</main>"
            f"<script>{script}</script><script>{render}</script>"
            f'<script type="application/json" id="inertia-equations">{_rows_json(doc)}</script>'
            "</body></html>\n")


def _rows_json(doc) -> str:
    """Every row of every block, for tests and tools (the LaTeX the page typesets)."""
    return json.dumps({b.title: list(b.rows) for b in doc}).replace("</", "<\\/")

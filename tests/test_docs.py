"""The documentation stays true: every docstring example in ``src/`` (doctest), every
``>>>`` example and every ``python`` block of the docs pages runs and shows what it says.

A fenced ``python`` block without ``>>>`` is run as a script in a fresh folder (holding a
``meshes/`` folder with one cube, for the batch page); a block that is a synopsis and not
runnable is fenced ``text``.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil
import re
from pathlib import Path

import numpy as np
import pytest

import inertia

REPO = Path(__file__).resolve().parents[1]
DOCS = sorted((REPO / "docs").glob("*.md"))
_FENCE = re.compile(r"^```python\n(.*?)^```", re.S | re.M)
# the page -> the extras its examples need (skips only in the no-extras CI job)
_PAGE_NEEDS = {"batch.md": ("pandas", "pyarrow", "dask"), "symbolic.md": ("sympy",)}
# module prefix -> the extra it needs to be imported at all
_MODULE_NEEDS = {"inertia.batch": "pandas", "inertia.symbolic": "sympy", "inertia.viz": "matplotlib"}


def _modules():
    names = []
    for info in pkgutil.walk_packages(inertia.__path__, prefix="inertia."):
        names.append(info.name)
    return sorted(names)


def _needs(name: str):
    """The optional module without which ``name`` cannot be imported (None: the core)."""
    for prefix, module in _MODULE_NEEDS.items():
        if name.startswith(prefix):
            return module
    return None


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples_run(name):
    need = _needs(name)
    if need:
        pytest.importorskip(need)
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(module, name):
        if test.filename and not test.filename.startswith(str(Path(module.__file__).parent)):
            continue  # re-exported objects are tested in their own module
        runner.run(test)
    assert runner.failures == 0, f"{runner.failures} failing docstring example(s) in {name} (run pytest -s to see them)"


def test_every_module_was_found():
    # truth: the files on disk; a module the walk misses would never have its examples run
    on_disk = {p.relative_to(REPO / "src").with_suffix("").as_posix().replace("/", ".").removesuffix(".__init__")
               for p in (REPO / "src" / "inertia").rglob("*.py")}
    assert on_disk <= set(_modules()) | {"inertia"}, on_disk - set(_modules())


def _cube_folder(folder: Path):
    (folder / "meshes").mkdir()
    v = np.array([[x, y, z] for x in (0, 10) for y in (0, 10) for z in (0, 10)], float)
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    lines = ["solid cube"]
    for f in faces:
        a, b, c = v[list(f)]
        n = np.cross(b - a, c - a)
        lines += [f" facet normal {n[0]} {n[1]} {n[2]}", "  outer loop"]
        lines += [f"   vertex {p[0]} {p[1]} {p[2]}" for p in (a, b, c)]
        lines += ["  endloop", " endfacet"]
    (folder / "meshes" / "cube.stl").write_text("\n".join(lines + ["endsolid cube"]) + "\n")


@pytest.mark.parametrize("page", DOCS, ids=[p.name for p in DOCS])
def test_docs_page_examples_run(page, tmp_path, monkeypatch):
    for module in _PAGE_NEEDS.get(page.name, ()):
        pytest.importorskip(module)
    text = page.read_text(encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    _cube_folder(tmp_path)
    ran = 0
    if ">>> " in text:
        result = doctest.testfile(str(page), module_relative=False, globs={},
                                  optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
        assert result.failed == 0, f"{page.name}: {result.failed} failing example(s)"
        ran += result.attempted
    for block in _FENCE.findall(text):
        if ">>> " in block:
            continue
        exec(compile(block, f"{page.name} (python block)", "exec"), {"__name__": "__docs__"})
        ran += 1
    if "```python" in text:
        assert ran > 0, page.name


# ---------------------------------------------------------------------------- the site: pages, links, the CLI page

PAGES = sorted(p.relative_to(REPO / "docs").as_posix() for p in (REPO / "docs").rglob("*.md"))
_LINK = re.compile(r"\]\(([^)#\s]+\.md)(?:#[^)]*)?\)")


def _links(page: str) -> set:
    """The pages a docs page links to, as paths under docs/."""
    folder = Path(page).parent
    return {(folder / target).as_posix().replace("api/../", "") for target in
            _LINK.findall((REPO / "docs" / page).read_text(encoding="utf-8"))}


def test_every_page_is_reachable_from_the_index():
    seen, todo = {"index.md"}, ["index.md"]
    while todo:
        for target in _links(todo.pop()):
            assert target in PAGES, f"a link to {target}, which does not exist"
            if target not in seen:
                seen.add(target)
                todo.append(target)
    assert set(PAGES) <= seen, sorted(set(PAGES) - seen)
    assert {p for p in PAGES if "/" not in p} - {"index.md"} <= _links("index.md")   # each top page directly


def test_every_page_is_in_the_site_navigation():
    config = (REPO / "mkdocs.yml").read_text(encoding="utf-8")
    nav = set(re.findall(r"^\s+- (?:[^:\n]+: )?(\S+\.md)$", config[config.index("\nnav:"):], re.M))
    assert nav == set(PAGES)


def test_the_readme_links_every_page_and_names_none_as_code():
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    linked = set(re.findall(r"\]\(docs/([^)#\s]+\.md)", readme))
    assert {p for p in PAGES if "/" not in p} <= linked | {"hooks.md"}, sorted({p for p in PAGES if "/" not in p}
                                                                          - linked)
    for name, text in [("README.md", readme)] + [(p, (REPO / "docs" / p).read_text(encoding="utf-8")) for p in PAGES]:
        assert not re.search(r"`(?:docs/)?[a-z-]+\.md`", text), f"{name} names a page as code: link it"


def test_the_cli_page_describes_every_option_of_every_command():
    from inertia.cli.main import build_parser, sub_parsers

    page = (REPO / "docs" / "cli.md").read_text(encoding="utf-8")
    prose = re.sub(r"^```.*?^```", "", page, flags=re.S | re.M)
    spans = " ".join(re.findall(r"`[^`]+`", prose))      # every option is named in code somewhere
    missing = sorted({s for sub in sub_parsers(build_parser()).values() for a in sub._actions for s in a.option_strings
                      if s.startswith("--") and s != "--help" and not re.search(rf"{re.escape(s)}(?![\w-])", spans)})
    assert not missing, missing


@pytest.mark.parametrize("page", ["quickstart.md", "cli.md"])
def test_console_examples_of_the_pages_are_current(page):
    from tests.cli.test_readme import _normal, console_sessions, run_cli

    sessions = [s for _, found in console_sessions((REPO / "docs" / page).read_text(encoding="utf-8")) for s in found]
    assert sessions
    for command, pasted in sessions:
        assert _normal(run_cli(command)) == _normal(pasted), f"{page}: the output of `{command}` is stale"

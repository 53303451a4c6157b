"""The demo's report: every linked file exists, the pictures show the library's numbers,
the animation has the frames it claims, and the 3D page works in a real browser."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import inertia  # noqa: E402
from inertia.cli.main import main  # noqa: E402
from inertia.dynamics.flip import flip_interval, flip_times  # noqa: E402
from inertia.viz.report import MARKER, linked_files  # noqa: E402

CHROMIUM = os.environ.get("INERTIA_CHROMIUM", "/usr/bin/chromium")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo") / "report"
    assert main(["demo", "--out", str(out), "--format", "json"]) == 0
    return out


def _nut():
    """The demo's body: the steel T-handle (exact mass properties)."""
    from inertia.massprops.bodies import t_handle

    return t_handle().props


def test_every_file_index_links_to_exists(report):
    linked = linked_files(report / "index.html")
    expected = {"omega.png", "omega.svg", "invariants.png", "invariants.svg", "polhodes.png", "polhodes.svg",
                "body.png", "body.svg", "flip.gif", "body3d.html", "report.json"}
    assert expected <= set(linked)
    for name in linked:
        assert (report / name).is_file() and (report / name).stat().st_size > 0, name
    assert (report / MARKER).is_file()


def test_marked_flip_times_are_the_predicted_ones(report):
    data = json.loads((report / "report.json").read_text())
    nut = _nut()
    moments = nut.principal()[0]
    w0 = np.array(data["omega0_body_principal"])
    T = flip_interval(moments, w0)
    assert data["flip_interval"] == pytest.approx(T, rel=1e-12)
    marked = np.array(data["flip_times_marked"])
    np.testing.assert_allclose(np.diff(marked), T, rtol=1e-9)
    np.testing.assert_allclose(marked, flip_times(moments, w0, marked[-1] + 1e-9), rtol=1e-12)
    # and the flips found in the simulated (exact) motion sit at the predicted times
    found = np.array(data["flips_detected"])
    np.testing.assert_allclose(found, marked[: len(found)], atol=1e-3 * T)


def test_page_data_has_the_librarys_six_points(report):
    html = (report / "body3d.html").read_text()
    start = html.index('<script type="application/json" id="inertia-data">') + len(
        '<script type="application/json" id="inertia-data">')
    data = json.loads(html[start: html.index("</script>", start)])
    nut = _nut()
    cf = nut.canonical()
    six = inertia.six_point_model(nut)
    expected = (six.positions_body - nut.com) @ cf.R_body_principal
    np.testing.assert_allclose(np.array(data["six_points"]), expected, atol=1e-15)
    assert data["mass"] == pytest.approx(nut.mass, rel=1e-15)
    assert "https://" not in html.split("</style>")[1].split('id="inertia-data"')[0]  # nothing from a CDN
    assert "data:text/javascript;base64," in html


def test_gif_has_the_frames_and_duration_it_claims(report):
    from PIL import Image

    data = json.loads((report / "report.json").read_text())
    claim = data["animation"]
    with Image.open(report / "flip.gif") as im:
        assert im.n_frames == claim["frames"] == 48
        total = 0
        for k in range(im.n_frames):
            im.seek(k)
            total += im.info["duration"]
    assert total / 1000 == pytest.approx(claim["duration_s"], abs=1e-9)


def test_mp4_has_the_frames_and_duration_it_claims(tmp_path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    from inertia.viz.animation import write_animation

    frames = np.zeros((30, 64, 80, 3), np.uint8)
    frames[:, :, :, 0] = np.arange(30)[:, None, None] * 8
    info = write_animation(frames, tmp_path / "a.mp4", fps=10)
    reader = imageio_ffmpeg.read_frames(str(tmp_path / "a.mp4"))
    meta = next(reader)
    n = sum(1 for _ in reader)
    assert n == info["frames"] == 30
    assert meta["fps"] == pytest.approx(10) and meta["duration"] == pytest.approx(info["duration_s"], abs=0.11)


def test_a_folder_we_did_not_create_is_refused(tmp_path, capsys):
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "thesis.tex").write_text("precious")
    assert main(["demo", "--out", str(foreign), "--no-video"]) == 1
    assert "was not created by inertia" in capsys.readouterr().err
    assert sorted(os.listdir(foreign)) == ["thesis.tex"]
    assert main(["demo", "--out", str(foreign), "--no-video", "--force", "--format", "json"]) == 0
    assert (foreign / "thesis.tex").read_text() == "precious" and (foreign / "index.html").is_file()


# ----------------------------------------------------------------------------- the real browser


def _browser():
    if not shutil.which(CHROMIUM) and not Path(CHROMIUM).is_file():
        if os.environ.get("INERTIA_REQUIRE_BROWSER"):
            pytest.fail(f"Chromium not found at {CHROMIUM} (INERTIA_REQUIRE_BROWSER is set)")
        pytest.skip(f"Chromium not found at {CHROMIUM}")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        if os.environ.get("INERTIA_REQUIRE_BROWSER"):
            raise
        pytest.skip("playwright is not installed")
    return sync_playwright


def _nonblank(png: bytes) -> float:
    from io import BytesIO

    from PIL import Image

    a = np.asarray(Image.open(BytesIO(png)).convert("L"), float)
    return float(a.std())


@pytest.mark.slow
def test_page_in_headless_chromium(report):
    sync_playwright = _browser()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--use-gl=swiftshader",
                                                                    "--enable-unsafe-swiftshader"])
        page = browser.new_page(viewport={"width": 1000, "height": 700})
        problems = []
        page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: problems.append(str(e)))
        page.on("request", lambda r: problems.append(f"network: {r.url}") if r.url.startswith("http") else None)
        page.goto((report / "body3d.html").as_uri())
        page.wait_for_function("window.inertiaState && window.inertiaState.ready", timeout=30_000)
        page.wait_for_timeout(300)
        first = page.screenshot()
        assert _nonblank(first) > 5.0  # not a blank canvas

        nut = _nut()
        six = inertia.six_point_model(nut)
        expected = (six.positions_body - nut.com) @ nut.canonical().R_body_principal
        np.testing.assert_allclose(np.array(page.evaluate("window.inertiaState.points")), expected, rtol=1e-12,
                                   atol=1e-15)
        # moving the I1 slider moves the points (d2, d3 grow with I1; d1 shrinks)
        before = np.array(page.evaluate("window.inertiaState.points"))
        page.eval_on_selector("#s-I0", "(s) => { s.value = s.value * 1.5; s.dispatchEvent(new Event('input')); }")
        after = np.array(page.evaluate("window.inertiaState.points"))
        assert not np.allclose(before, after)
        assert abs(after[0][0]) < abs(before[0][0]) and abs(after[2][1]) > abs(before[2][1])
        # a tensor breaking the triangle inequality shows the warning
        page.eval_on_selector("#s-I2", "(s) => { s.value = s.max; s.dispatchEvent(new Event('input')); }")
        assert page.is_visible("#warning") and "Triangle inequality fails" in page.inner_text("#warning")
        # play: the body's orientation changes between two screenshots
        q0 = page.evaluate("window.inertiaState.quaternion")
        shot0 = page.screenshot()
        page.click("#play")
        page.wait_for_function("window.inertiaState.frame > 10", timeout=20_000)
        page.wait_for_timeout(200)
        q1 = page.evaluate("window.inertiaState.quaternion")
        shot1 = page.screenshot()
        assert not np.allclose(q0, q1) and shot0 != shot1
        browser.close()
    assert problems == []

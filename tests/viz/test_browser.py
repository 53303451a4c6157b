"""The 3D page and the report in a real browser (Debian's Chromium, headless, Playwright):
offline, the body on screen, the mouse turns the camera, the models follow the sliders,
the polhode follows the time, themes and print work."""

from __future__ import annotations

from io import BytesIO

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import inertia  # noqa: E402
from tests.viz._helpers import Watched, t_handle  # noqa: E402

pytestmark = pytest.mark.slow


def _image(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(BytesIO(png)).convert("RGB")).astype(int)


@pytest.fixture(scope="module")
def page3d(browser, report):
    w = Watched(browser, viewport={"width": 1200, "height": 820}, color_scheme="light")
    w.page.goto((report / "body3d.html").as_uri())
    w.page.wait_for_function("window.inertiaState && window.inertiaState.ready", timeout=30_000)
    w.page.wait_for_timeout(300)
    yield w
    w.close()


def test_page_loads_offline_and_shows_the_librarys_models(page3d):
    page, state = page3d.page, "window.inertiaState"
    nut = t_handle().props
    R = nut.principal().R_body_principal
    six = inertia.six_point_model(nut)
    np.testing.assert_allclose(page.evaluate(f"{state}.points"), (six.positions_body - nut.com) @ R, atol=1e-15)
    # the table shows body-frame coordinates, as the CLI does, in mm with units in the header
    np.testing.assert_allclose(page.evaluate(f"{state}.points_body"), six.positions_body, atol=1e-15)
    header = page.inner_text("#points tr:first-child")
    assert "x [mm]" in header and "z [mm]" in header
    first_row = page.inner_text("#points tr:nth-child(2)").split()
    np.testing.assert_allclose([float(x) for x in first_row[1:]], 1e3 * six.positions_body[0], atol=0.006)
    np.testing.assert_allclose(page.evaluate(f"{state}.four_points"),
                               (inertia.four_point_model(nut).positions_body - nut.com) @ R, atol=1e-15)
    np.testing.assert_allclose(page.evaluate(f"{state}.box"), inertia.equivalent_box(nut).size, rtol=1e-12)
    np.testing.assert_allclose(page.evaluate(f"{state}.ellipsoid"), inertia.equivalent_ellipsoid(nut).dims,
                               rtol=1e-12)
    assert page.title() == "steel T-handle: inertia in 3D" and page.inner_text("h1") == "steel T-handle"
    assert page3d.problems == []


def test_the_body_is_on_screen(page3d):
    """Pixels where the body's vertices project are not the background in body mode, and change
    when the body is ghosted behind the six points."""
    page = page3d.page
    page.click('#modes label:has(input[value="body"])')
    page.wait_for_timeout(150)
    assert page.evaluate("window.inertiaState.mesh_faces") == len(t_handle().display_mesh()[1])
    pts = page.evaluate("window.inertiaState.bodyWorldPoints().map(window.inertiaState.project)")
    box = page.locator("#view").bounding_box()
    inside = [(x, y) for x, y in pts if box["x"] + 2 < x < box["x"] + box["width"] - 2
              and box["y"] + 2 < y < box["y"] + box["height"] - 2]
    assert len(inside) > 20
    shot_body = _image(page.screenshot())
    page.click('#modes label:has(input[value="six"])')
    page.wait_for_timeout(150)
    shot_ghost = _image(page.screenshot())
    background = shot_body[int(box["y"] + box["height"] - 60), int(box["x"] + box["width"] / 2)]
    at = np.array([[shot_body[int(y), int(x)] for x, y in inside], [shot_ghost[int(y), int(x)] for x, y in inside]])
    body_contrast = np.abs(at[0] - background).sum(axis=1)
    ghost_change = np.abs(at[0] - at[1]).sum(axis=1)
    assert np.median(body_contrast) > 60 and np.median(ghost_change) > 40
    page.click('#modes label:has(input[value="body"])')


def test_mode_toggle_shows_each_model(page3d):
    page = page3d.page
    for mode, title in (("box", "Six point masses"), ("ellipsoid", "Six point masses"),
                        ("six", "Six point masses"), ("four", "Four point masses"), ("body", "Six point masses")):
        page.click(f'#modes label:has(input[value="{mode}"])')
        assert page.evaluate("window.inertiaState.mode") == mode
        assert page.inner_text("#tabletitle").startswith(title)
    assert page3d.problems == []


def test_a_mouse_drag_turns_the_camera_and_the_wheel_zooms(page3d):
    page = page3d.page
    box = page.locator("#view canvas").bounding_box()
    cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    before = np.array(page.evaluate("window.inertiaState.camera()"))
    page.mouse.move(cx, cy)
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(cx + 15 * k, cy + 4 * k)
    page.mouse.up()
    page.wait_for_timeout(400)
    after = np.array(page.evaluate("window.inertiaState.camera()"))
    assert np.linalg.norm(after - before) > 0.1 * np.linalg.norm(before)
    assert np.linalg.norm(after) == pytest.approx(np.linalg.norm(before), rel=0.05)   # orbit: same distance
    page.mouse.move(cx, cy)
    page.mouse.wheel(0, -400)
    page.wait_for_timeout(400)
    zoomed = np.array(page.evaluate("window.inertiaState.camera()"))
    assert np.linalg.norm(zoomed) < 0.95 * np.linalg.norm(after)


def test_sliders_move_the_points_and_warn(page3d):
    page = page3d.page
    before = np.array(page.evaluate("window.inertiaState.points"))
    page.eval_on_selector("#s-I0", "(s) => { s.value = s.value * 1.5; s.dispatchEvent(new Event('input')); }")
    after = np.array(page.evaluate("window.inertiaState.points"))
    assert abs(after[0][0]) < abs(before[0][0]) and abs(after[2][1]) > abs(before[2][1])
    page.eval_on_selector("#s-I2", "(s) => { s.value = s.max; s.dispatchEvent(new Event('input')); }")
    assert page.is_visible("#warning") and "Triangle inequality fails" in page.inner_text("#warning")
    page.click("#reset")
    assert not page.is_visible("#warning")
    np.testing.assert_allclose(page.evaluate("window.inertiaState.points"), before, rtol=1e-12)


def test_time_turns_the_body_and_moves_the_polhode_point(page3d, report):
    """The slider sets the attitude and the polhode point from the exact solution; play runs."""
    import json

    from inertia.dynamics.exact import exact_solution

    page = page3d.page
    html = (report / "body3d.html").read_text()
    tag = 'id="inertia-data">'
    data = json.loads(html[html.index(tag) + len(tag): html.index("</script>", html.index(tag))])
    page.eval_on_selector("#s-time", "(s) => { s.value = 150; s.dispatchEvent(new Event('input')); }")
    t = page.evaluate("window.inertiaState.t")
    q, w = exact_solution(data["moments"], data["spin"], t)
    q_page = np.array(page.evaluate("window.inertiaState.quaternion"))
    assert abs(q_page @ q) == pytest.approx(1.0, abs=1e-6)
    m = w * np.array(data["moments"])
    np.testing.assert_allclose(page.evaluate("window.inertiaState.polhode_point"), m / np.linalg.norm(m), atol=1e-5)
    shot0 = page.screenshot()
    page.click("#play")
    page.wait_for_function("window.inertiaState.frame > 170", timeout=20_000)
    page.click("#play")
    assert page.screenshot() != shot0
    assert page3d.problems == []


def test_a_large_mesh_is_decimated_and_the_page_says_so(browser, tmp_path):
    from inertia.dynamics.flip_study import flip_study
    from inertia.viz.display_mesh import display_mesh
    from inertia.viz.page import page_data, write_page
    from tests.viz.test_display_mesh import _icosphere

    V, F = _icosphere(5, radius=0.05)
    V = V * [1.0, 0.7, 0.4]                    # an ellipsoid: three distinct moments
    props = inertia.mesh_properties(V, F, density=1000.0)
    data = page_data(props, flip_study(props.principal().moments), name="ellipsoid", display=display_mesh(props, (V, F)))
    assert len(data["mesh"]["faces"]) <= 20_000 < len(F)
    write_page(tmp_path / "big.html", data)
    w = Watched(browser, viewport={"width": 1000, "height": 800})
    w.page.goto((tmp_path / "big.html").as_uri())
    w.page.wait_for_function("window.inertiaState && window.inertiaState.ready", timeout=30_000)
    assert w.page.is_visible("#meshnote") and "20,480 faces" in w.page.inner_text("#meshnote")
    assert w.page.evaluate("window.inertiaState.mode") == "body" and w.problems == []
    w.close()


def test_report_page_in_the_browser(browser, report):
    """The index: offline, the 3D page alive inside it, the theme button switches both pages,
    and on paper the video and the 3D page give way to the poster."""
    w = Watched(browser, viewport={"width": 1280, "height": 900}, color_scheme="light")
    page = w.page
    page.goto((report / "index.html").as_uri())
    frame = page.frame_locator("iframe")
    page.locator("iframe").scroll_into_view_if_needed()
    inner = next(f for f in page.frames if f.url.endswith("body3d.html"))
    inner.wait_for_function("window.inertiaState && window.inertiaState.ready", timeout=30_000)
    assert page.evaluate("document.documentElement.dataset.theme") == "light"
    page.click("#theme")
    page.wait_for_timeout(200)
    assert page.evaluate("document.documentElement.dataset.theme") == "dark"
    assert inner.evaluate("document.documentElement.dataset.theme") == "dark"
    assert inner.evaluate("document.documentElement.classList.contains('embedded')")
    assert frame.locator("h1").is_hidden()              # the report has the header already
    page.emulate_media(media="print")
    assert page.locator("video, .flip img").first.count() == 1
    assert page.locator(".poster").is_visible() and page.locator("iframe").is_hidden()
    page.emulate_media(media="screen")
    page.click("#theme")                               # back to light for the next reader
    assert w.problems == []
    w.close()


@pytest.mark.parametrize("argv", [[], ["--translation", "--gravity", "--sequence", "ZXZ"]], ids=["zyx", "zxz-6dof"])
def test_equations_page_typesets_without_errors(browser, tmp_path, argv):
    """``inertia lagrangian --format html``: KaTeX typesets every block offline, no error."""
    from inertia.cli.main import main

    out = tmp_path / "eom.html"
    assert main(["lagrangian", "--format", "html", "-o", str(out), *argv]) == 0
    w = Watched(browser, viewport={"width": 1100, "height": 800})
    w.page.goto(out.as_uri())
    w.page.wait_for_function("window.katexDone === true", timeout=30_000)
    assert w.page.evaluate("window.katexErrors") == []
    blocks = w.page.locator("section").count()
    assert blocks == 6 and w.page.locator(".math .katex-display").count() == blocks
    assert w.page.locator(".katex-error, .error").count() == 0
    # the KaTeX fonts came from the page itself (data: URLs), not from a network
    assert w.page.evaluate("document.fonts.check('16px KaTeX_Main')")
    assert w.problems == []
    w.close()

"""The demo's report: every linked file exists, the pictures show the library's numbers, the
index reads as a page (units, captions, themes, print), the plots are legible."""

from __future__ import annotations

import json
import os
import re

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import inertia  # noqa: E402
from inertia.cli.main import main  # noqa: E402
from inertia.dynamics.flip import flip_interval, flip_times  # noqa: E402
from inertia.viz.animation import video_format  # noqa: E402
from inertia.viz.report import MARKER, linked_files  # noqa: E402
from tests.viz._helpers import t_handle  # noqa: E402


def _page_data(path):
    html = path.read_text()
    tag = '<script type="application/json" id="inertia-data">'
    start = html.index(tag) + len(tag)
    return html, json.loads(html[start: html.index("</script>", start)])


def test_every_file_index_links_to_exists(report):
    linked = linked_files(report / "index.html")
    expected = {"omega.png", "omega.svg", "invariants.png", "invariants.svg", "polhodes.png", "polhodes.svg",
                "body.png", "body.svg", f"flip.{video_format()}", "flip-poster.png", "body3d.html", "report.json"}
    assert expected <= set(linked)
    for name in linked:
        assert (report / name).is_file() and (report / name).stat().st_size > 0, name
        assert (report / name).stat().st_mode & 0o777 == 0o666 & ~_umask(), name   # like any file the user writes
    assert (report / MARKER).is_file()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_marked_flip_times_are_the_predicted_ones(report):
    data = json.loads((report / "report.json").read_text())
    moments = t_handle().props.principal().moments
    w0 = np.array(data["omega0_body_principal"])
    T = flip_interval(moments, w0)
    assert data["flip_interval"] == pytest.approx(T, rel=1e-12)
    marked = np.array(data["flip_times_marked"])
    np.testing.assert_allclose(np.diff(marked), T, rtol=1e-9)
    np.testing.assert_allclose(marked, flip_times(moments, w0, marked[-1] + 1e-9), rtol=1e-12)
    # and the flips found in the simulated (exact) motion sit at the predicted times
    found = np.array(data["flips_detected"])
    np.testing.assert_allclose(found, marked[: len(found)], atol=1e-3 * T)


def test_page_data_has_the_librarys_models(report):
    html, data = _page_data(report / "body3d.html")
    body = t_handle()
    nut = body.props
    R = nut.principal().R_body_principal
    for key, model in (("six_points", inertia.six_point_model), ("four_points", inertia.four_point_model)):
        np.testing.assert_allclose(np.array(data[key]), (model(nut).positions_body - nut.com) @ R, atol=1e-15)
    np.testing.assert_allclose(data["box_size"], inertia.equivalent_box(nut).size, rtol=1e-14)
    np.testing.assert_allclose(data["ellipsoid_semi_axes"], inertia.equivalent_ellipsoid(nut).dims, rtol=1e-14)
    assert data["mass"] == pytest.approx(nut.mass, rel=1e-15)
    assert data["name"] == "steel T-handle" and data["length_unit"] == "mm"
    # the body itself is on the page: the demo's display mesh in the principal frame, not decimated
    V, F = body.display_mesh()
    assert data["mesh"]["faces"] == F.tolist() and data["mesh"]["note"] == ""
    np.testing.assert_allclose(data["mesh"]["vertices"], (V - nut.com) @ R, atol=1e-7)
    assert "https://" not in html.split("</style>")[1].split('id="inertia-data"')[0]  # nothing from a CDN
    assert html.count("data:text/javascript;base64,") == 2                          # three.js and its OrbitControls


def test_index_reads_as_a_page(report):
    html = (report / "index.html").read_text()
    text = re.sub(r"<[^>]+>", " ", html)
    assert "<h1>steel T-handle</h1>" in html and "inertia demo:" not in html
    # key numbers with their units in the header
    nut = t_handle().props
    assert f"{nut.mass * 1e3:.4g}" in text and "kg m&sup2;" in html and "rad/s" in text
    # the video large, with its poster for print; the 3D page embedded
    assert re.search(r'<video src="flip\.mp4" poster="flip-poster\.png"', html) or video_format() == "gif"
    assert '<iframe src="body3d.html"' in html
    # every plot has a caption saying what to look at
    for what in ("reverses at each dashed line", "follows the separatrix", "keeps |L| to rounding", "six point masses"):
        assert what in text
    # themes: the reader's setting, a button, and the print style
    assert "prefers-color-scheme" in html and ':root[data-theme="dark"]' in html and "@media print" in html
    assert "-0.000" not in text and "nan" not in text.lower().split()


def test_polhode_ticks_do_not_overlap(tmp_path, monkeypatch):
    """Three ticks per axis in a power of ten of kg m^2/s: no two tick labels of an axis touch."""
    from inertia.dynamics.flip_study import flip_study
    from inertia.viz import plots

    plt = plots.pyplot()
    kept = []
    monkeypatch.setattr(plt, "close", lambda fig: kept.append(fig))
    r = plots.polhode_plot(flip_study(t_handle().props.principal().moments), tmp_path)
    fig = kept[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    for axis, label in zip((ax.xaxis, ax.yaxis, ax.zaxis), ("m_1", "m_2", "m_3")):
        boxes = [t.get_window_extent(renderer) for t in axis.get_ticklabels() if t.get_text()]
        assert len(boxes) == 3
        assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
        assert label in axis.get_label_text() and "kg m$^2$/s" in axis.get_label_text()
    assert r["axis_unit_exponent"] == -4
    plt.close("all")


def test_a_folder_we_did_not_create_is_refused(tmp_path, capsys):
    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "thesis.tex").write_text("precious")
    assert main(["demo", "--out", str(foreign), "--no-video"]) == 1
    assert "was not created by inertia" in capsys.readouterr().err
    assert sorted(os.listdir(foreign)) == ["thesis.tex"]
    assert main(["demo", "--out", str(foreign), "--no-video", "--force", "--format", "json"]) == 0
    assert (foreign / "thesis.tex").read_text() == "precious" and (foreign / "index.html").is_file()

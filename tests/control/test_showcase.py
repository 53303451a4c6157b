"""``inertia demo --control``: its JSON and tables, its report section (files linked, figures'
numbers) and its side-by-side video."""

from __future__ import annotations

import json

import numpy as np
import pytest

from inertia.cli.main import main
from inertia.control.studies import active_run, showcase, t_handle_setup


@pytest.fixture(scope="module")
def small_showcase():
    return showcase(64, seed=1)


def test_demo_control_reports_every_figure_of_the_issue(capsys):
    assert main(["demo", "--control", "--no-report", "--format", "json"]) == 0
    d = json.loads(capsys.readouterr().out)["control"]
    assert set(d) == {"steel T-handle", "Basilisk 900/800/600 spacecraft"}
    for body in d.values():
        p = body["passive"]
        assert abs(p["h_threshold_simulated"] / p["h_min_formula"] - 1) < 0.02
        assert body["active"]["max_tilt_after_settle_rad"] < np.radians(1)
        assert body["monte_carlo"]["runs"] == 1000 and body["monte_carlo"]["success_rate"] >= 0.99
    assert main(["demo", "--control", "--no-report"]) == 0
    text = capsys.readouterr().out
    assert "8. Holding the spin about the intermediate axis with reaction wheels" in text
    assert "(c) Monte Carlo" in text and "1000/1000" in text


def test_demo_control_refuses_a_mesh(capsys, tmp_path):
    rc = main(["demo", "--control", "--mesh", str(tmp_path / "x.stl"), "--no-report"])
    assert rc != 0
    assert "--control shows the built-in T-handle and Basilisk's spacecraft; it does not take --mesh" in \
        capsys.readouterr().err


def test_the_report_section_links_its_files_and_draws_the_studys_numbers(tmp_path, small_showcase):
    pytest.importorskip("matplotlib")
    from inertia.massprops.bodies import t_handle
    from inertia.viz.report import build_report, linked_files

    body = t_handle()
    r = build_report(tmp_path / "rep", body.props, title="T", mesh=body.display_mesh(), video=False,
                     control=small_showcase)
    text = r["index"].read_text()
    assert '<section id="control">' in text and "Holding the spin with reaction wheels" in text
    for name in linked_files(r["index"]):
        assert (tmp_path / "rep" / name).is_file(), name
    data = json.loads((tmp_path / "rep" / "control.json").read_text())
    for name, mc in small_showcase.monte_carlo.items():
        assert data[name]["monte_carlo_max_tilt_rad"] == mc.max_tilt.tolist()
    from inertia.viz.control_plots import passive_plot

    drawn = passive_plot(small_showcase.passive, tmp_path)["curves"]
    for name, sw in small_showcase.passive.items():
        assert drawn[name]["max_tilt_deg"] == np.degrees(sw.max_tilt).tolist()


def test_the_video_shows_both_bodies_at_the_simulated_attitudes(tmp_path):
    pytest.importorskip("PIL")
    from inertia.massprops.bodies import t_handle
    from inertia.viz.control_animation import HoldRenderer, render_hold
    from inertia.viz.display_mesh import display_mesh

    b = t_handle()
    mesh = display_mesh(b.props, b.display_mesh())
    run = active_run(t_handle_setup())
    info = render_hold(run, mesh, tmp_path / "c.gif", seconds=0.4, poster=tmp_path / "p.png")
    assert info["frames"] == 20 and (tmp_path / "c.gif").stat().st_size > 0 and (tmp_path / "p.png").is_file()
    r = HoldRenderer(run, mesh, [0.0, 0.5])
    # the held body's attitude is the rollout's: the frame's rotation is R_WB R_BP at t = 0.5 s
    from inertia._core.rotations import quat_to_matrix

    assert np.allclose(r.R["held"][1], quat_to_matrix(run.held[50, 6:10]) @ run.setup.gyrostat.body.R_body_principal)
    a, c = r.frame(0), r.frame(1)
    assert a.shape == (560, 960, 3) and not np.array_equal(a, c)

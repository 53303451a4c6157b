"""The flip video: it shows the body at the exact attitude of each frame's time, has the
frames, rate and duration it states, and moves (first and last frames differ)."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("matplotlib")
PIL = pytest.importorskip("PIL")

from inertia._core.rotations import quat_to_matrix  # noqa: E402
from inertia.dynamics.exact import exact_solution  # noqa: E402
from inertia.dynamics.flip_study import flip_study  # noqa: E402
from inertia.massprops.equivalent import equivalent_box  # noqa: E402
from inertia.particles.models import six_point_model  # noqa: E402
from inertia.viz.animation import (  # noqa: E402
    ACCENT,
    BACKGROUND,
    VIDEO_FPS,
    VIDEO_SIZE,
    FlipRenderer,
    FlipScene,
    film_span,
    playback_times,
    render_flip,
    video_format,
    write_animation,
)
from inertia.viz.display_mesh import display_mesh  # noqa: E402
from inertia.viz.raster import SUPERSAMPLE  # noqa: E402
from tests.viz._helpers import t_handle  # noqa: E402


@pytest.fixture(scope="module")
def scene():
    body = t_handle()
    props = body.props
    R = props.principal().R_body_principal
    six = (six_point_model(props).positions_body - props.com) @ R
    return FlipScene(flip_study(props.principal().moments), display_mesh(props, body.display_mesh()), six,
                     np.asarray(equivalent_box(props).size) / 2, "steel T-handle")


def _silhouette(camera, vertices_world, faces, size, top, bottom):
    """Every face of the mesh filled (no depth order needed for the outline), output pixels."""
    from PIL import Image, ImageDraw

    img = Image.new("L", (size * SUPERSAMPLE, (bottom - top) * SUPERSAMPLE), 0)
    d = ImageDraw.Draw(img)
    xy, _ = camera.project(vertices_world)
    for f in faces:
        d.polygon(xy[f].ravel().tolist(), fill=255)
    return np.asarray(img.reduce(SUPERSAMPLE)) > 127


def test_each_frame_shows_the_body_at_the_exact_attitude(scene):
    """The body's pixels in a frame match the outline of the mesh turned by the exact solution at
    that frame's time (dynamics.exact, called here), and not the outline a moment later."""
    t, speed = playback_times(film_span(scene.study), VIDEO_FPS)
    r = FlipRenderer(scene, t, speed)
    m = scene.mesh
    for k in (20, 90, 200):   # away from the flip banners
        frame = r.frame(k)[r.top:r.bottom].astype(int)
        drawn = (np.abs(frame - np.array(BACKGROUND)).sum(axis=2) > 40) & ~_amber(frame)
        R_now = quat_to_matrix(exact_solution(scene.study.moments, scene.study.omega0_body, t[k])[0])
        R_later = quat_to_matrix(exact_solution(scene.study.moments, scene.study.omega0_body, t[k] + 0.05)[0])
        iou = []
        for R in (R_now, R_later):
            outline = _silhouette(r.camera, m.vertices @ R.T, m.faces, r.size, r.top, r.bottom)
            iou.append((drawn & outline).sum() / (drawn | outline).sum())
        assert iou[0] > 0.97 and iou[1] < iou[0] - 0.1, (k, iou)


def _amber(frame):
    """Pixels of the L arrow and its legend: amber blended into the background (anti-aliasing)."""
    v = frame - np.array(BACKGROUND)
    d = np.array(ACCENT) - np.array(BACKGROUND)
    alpha = np.clip(v @ d / (d @ d), 0.0, 1.0)
    return (np.linalg.norm(v - alpha[..., None] * d, axis=-1) < 20) & (alpha > 0.05)


def test_the_model_view_draws_the_six_points(scene):
    t, speed = playback_times(film_span(scene.study), VIDEO_FPS)
    r = FlipRenderer(scene, t[:3], speed, view="model")
    frame = r.frame(0)
    R = quat_to_matrix(exact_solution(scene.study.moments, scene.study.omega0_body, 0.0)[0])
    # the three points on the negative half-axes: no axis line or arrow runs through them
    behind = scene.six_points[scene.six_points.sum(axis=1) < 0]
    assert len(behind) == 3
    xy, _ = r.camera.project(behind @ R.T)
    for x, y in xy / SUPERSAMPLE:
        assert tuple(frame[int(round(y)) + r.top, int(round(x))]) == (255, 150, 40)   # the point's colour


def test_video_has_the_frames_and_duration_it_states(report):
    """Read back with imageio-ffmpeg (MP4) or Pillow (GIF): count, rate, duration, size, motion."""
    claim = json.loads((report / "report.json").read_text())["animation"]
    path = report / claim["file"]
    frames = _read_frames(path)
    assert len(frames) == claim["frames"] and frames[0].shape == (VIDEO_SIZE, VIDEO_SIZE, 3)
    assert claim["width"] == claim["height"] == VIDEO_SIZE
    # real time: the film lasts three flip intervals of the T-handle (three flips, each mid-film)
    T = json.loads((report / "report.json").read_text())["flip_interval"]
    assert claim["duration_s"] == pytest.approx(claim["frames"] / claim["fps"])
    assert claim["frames"] == round(3 * T * claim["fps"])
    assert claim["speed"] == 1.0 and claim["t_end"] == pytest.approx(claim["duration_s"], abs=2 / claim["fps"])
    if path.suffix == ".mp4":
        import imageio_ffmpeg

        meta = next(imageio_ffmpeg.read_frames(str(path)))
        assert claim["fps"] == VIDEO_FPS and meta["fps"] == pytest.approx(VIDEO_FPS)
        assert meta["duration"] == pytest.approx(claim["duration_s"], abs=1.5 / VIDEO_FPS)
    first, last = frames[0].astype(int), frames[-1].astype(int)
    assert np.abs(first - last).mean() > 1.0        # the body has turned, the clock moved on


def _read_frames(path):
    if path.suffix == ".mp4":
        import imageio_ffmpeg

        reader = imageio_ffmpeg.read_frames(str(path))
        meta = next(reader)
        w, h = meta["size"]
        return [np.frombuffer(f, np.uint8).reshape(h, w, 3) for f in reader]
    from PIL import Image

    out = []
    with Image.open(path) as im:
        for k in range(im.n_frames):
            im.seek(k)
            out.append(np.asarray(im.convert("RGB")))
    return out


def test_default_format_is_mp4_where_ffmpeg_is(report):
    try:
        import imageio_ffmpeg

        imageio_ffmpeg.get_ffmpeg_exe()
        expected = "mp4"
    except Exception:  # noqa: BLE001
        expected = "gif"
    assert video_format() == expected and (report / f"flip.{expected}").is_file()


def test_gif_has_the_frames_and_duration_it_claims(scene, tmp_path):
    """The GIF fallback (25 fps: GIF delays are whole centiseconds), small for speed."""
    from PIL import Image

    info = render_flip(scene, tmp_path / "flip.gif", size=160)
    with Image.open(tmp_path / "flip.gif") as im:
        assert im.n_frames == info["frames"] and im.size == (160, 160)
        total = 0
        for k in range(im.n_frames):
            im.seek(k)
            total += im.info["duration"]
    assert info["fps"] == 25 and total / 1000 == pytest.approx(info["duration_s"], abs=1e-9)


def test_mp4_has_the_frames_and_duration_it_claims(tmp_path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    frames = np.zeros((30, 64, 80, 3), np.uint8)
    frames[:, :, :, 0] = np.arange(30)[:, None, None] * 8
    info = write_animation(iter(frames), tmp_path / "a.mp4", fps=10)
    reader = imageio_ffmpeg.read_frames(str(tmp_path / "a.mp4"))
    meta = next(reader)
    n = sum(1 for _ in reader)
    assert n == info["frames"] == 30
    assert meta["fps"] == pytest.approx(10) and meta["duration"] == pytest.approx(info["duration_s"], abs=0.11)

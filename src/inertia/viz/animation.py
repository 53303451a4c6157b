"""The flip video: the body itself tumbling by the exact solution, the angular momentum L
fixed in space, the flips marked, and a strip of the body angular velocity with a cursor.

Frames are drawn by :mod:`.raster` (shaded triangles, painter's algorithm) from the exact
elliptic-function solution at each frame's time; nothing is integrated.  ``view="model"``
draws the equivalent box, the six point masses and the principal axes instead of the body.

MP4 (H.264, through the ffmpeg binary that the ``imageio-ffmpeg`` package ships, no system
ffmpeg needed) when that package is present, GIF through Pillow otherwise.  Frames stream
into the encoder as they are drawn (ffmpeg encodes in its own process meanwhile), so no
film is ever held in memory.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: the video's size (square, pixels) and frame rate
VIDEO_SIZE = 720
VIDEO_FPS = 30
#: the most faces the video draws (the painter's algorithm costs per face and frame); the
#: display mesh is decimated further for it when larger
VIDEO_MAX_FACES = 3000
#: GIF frame delays are whole centiseconds, so the GIF runs at 25 fps (40 ms a frame)
GIF_FPS = 25
#: the video lasts the study's time span in real time, squeezed or stretched into these bounds [s]
MIN_SECONDS, MAX_SECONDS = 4.0, 12.0
#: layout, as fractions of the size: the title band, the 3D view, the angular-velocity strip
TITLE_BAND, STRIP = 0.1, 0.19
VIEWS = ("body", "model")

BACKGROUND = (27, 31, 38)
TEXT = (232, 236, 241)
MUTED = (150, 158, 170)
ACCENT = (255, 196, 64)              # L, and the flip banner
PART_RGB = ((176, 188, 204), (232, 140, 58), (120, 190, 140), (190, 140, 220))
AXIS_RGB = ((235, 95, 85), (95, 200, 120), (95, 150, 245))


def video_format() -> str:
    """``"mp4"`` when imageio-ffmpeg (and its ffmpeg binary) is available, else ``"gif"``."""
    try:
        import imageio_ffmpeg

        imageio_ffmpeg.get_ffmpeg_exe()
    except Exception:  # noqa: BLE001 - missing package or binary: the GIF needs neither
        return "gif"
    return "mp4"


def film_span(study) -> float:
    """The body time the film covers [s]: three flips and half an interval after the last
    (``3 T_flip``), or the whole study when it is shorter."""
    T = float(study.flip_interval)
    return min(float(study.t[-1]), 3.0 * T) if np.isfinite(T) and T > 0 else float(study.t[-1])


def playback_times(t_end: float, fps: float) -> tuple[np.ndarray, float]:
    """Frame times [s] from 0 to about ``t_end`` and the speed-up (video seconds x speed = body seconds)."""
    seconds = float(np.clip(t_end, MIN_SECONDS, MAX_SECONDS))
    speed = t_end / seconds
    n = max(2, int(round(seconds * fps)))
    return np.arange(n) * (speed / fps), speed


@dataclass(frozen=True)
class FlipScene:
    """What the video shows: the study, the body (a :class:`~.display_mesh.DisplayMesh` or
    None), the six points (6, 3) and the box half-extents (3,), principal frame, metres."""

    study: object
    mesh: object
    six_points: np.ndarray
    box_half: np.ndarray
    title: str

    @property
    def radius(self) -> float:
        r = float(np.linalg.norm(self.box_half))
        return max(r, self.mesh.radius) if self.mesh is not None else r


def font(size_px: int, bold: bool = False):
    """DejaVu Sans (matplotlib's) at ``size_px``, or Pillow's own font without matplotlib."""
    from PIL import ImageFont

    try:
        import matplotlib

        name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
        return ImageFont.truetype(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / name), size_px)
    except Exception:  # noqa: BLE001 - no matplotlib font: Pillow's own
        return ImageFont.load_default(size_px)


def _model_overlay(scene: FlipScene, R, overlay) -> None:
    """Equivalent box edges, principal axes and six points, turned by R (principal -> world)."""
    from .plots import box_wire

    corners, edges = box_wire(scene.box_half)
    cw = corners @ R.T
    for i, j in edges:
        overlay.lines.append((cw[i], cw[j], MUTED, 1.6))
    span = 1.15 * float(np.max(np.abs(scene.six_points)))
    for k in range(3):
        overlay.lines.append((np.zeros(3), span * R[:, k], AXIS_RGB[k], 2.5))
    for p in scene.six_points @ R.T:
        overlay.discs.append((p, 7.0, (255, 150, 40)))


class FlipRenderer:
    """Draws frame ``k`` (time ``times[k]``) of a :class:`FlipScene`; static parts drawn once."""

    def __init__(self, scene: FlipScene, times, speed: float, *, size: int = VIDEO_SIZE, view: str = "body"):
        from .._core.rotations import quat_to_matrix
        from ..dynamics.exact import exact_solution
        from .raster import Camera

        if view not in VIEWS:
            from .._core.errors import InputError

            raise InputError(f"video view must be one of {', '.join(VIEWS)}, got {view!r}")
        self.scene, self.t, self.speed, self.size = scene, np.asarray(times, float), float(speed), int(size)
        self.view = view if scene.mesh is not None else "model"
        study = scene.study
        self.R = quat_to_matrix(exact_solution(study.moments, study.omega0_body, self.t)[0])
        self.L = study.L_world / np.linalg.norm(study.L_world)
        self.top = int(round(size * TITLE_BAND))                    # the 3D view: rows top .. bottom
        self.bottom = int(round(size * (1 - STRIP)))
        h3d = self.bottom - self.top
        self.view_h = h3d - int(0.045 * size)                          # above the legend line
        self.camera = Camera.looking_at_origin(self.L, center=(size / 2, 0.52 * h3d),
                                               scale=0.30 * self.bottom / scene.radius)
        if scene.mesh is not None:
            from .display_mesh import cluster_decimate, face_parts

            V, F = cluster_decimate(scene.mesh.vertices, scene.mesh.faces, VIDEO_MAX_FACES)
            self.vertices, self.faces = V, F
            self.part = scene.mesh.part if len(F) == len(scene.mesh.faces) else face_parts(len(V), F)
            self.face_rgb = np.array(PART_RGB)[self.part % len(PART_RGB)]
        self.flips = np.asarray([x for x in study.flip_times if x <= self.t[-1] + 1e-9], float)
        self.fonts = {k: font(max(8, int(round(size * f))), bold=b) for k, f, b in
                      (("title", 0.031, True), ("text", 0.022, False), ("small", 0.018, False),
                       ("banner", 0.042, True))}
        self.base = self._static()

    def _static(self):
        """The background: title, legends and the angular-velocity strip (the view goes between)."""
        from PIL import Image, ImageDraw

        from .strip import draw_strip

        size, f = self.size, self.fonts
        img = Image.new("RGB", (size, size), BACKGROUND)
        d = ImageDraw.Draw(img)
        pad = int(0.022 * size)
        d.text((pad, pad), self.scene.title, font=f["title"], fill=TEXT)
        sub = ("the body" if self.view == "body" else "equivalent box, six point masses, principal axes") + \
            ", turning by the exact torque-free solution"
        d.text((pad, pad + int(0.045 * size)), sub, font=f["small"], fill=MUTED)
        speed = "real time" if abs(self.speed - 1) < 1e-6 else f"{self.speed:.3g}x real time"
        d.text((size - pad - d.textlength(speed, font=f["small"]), pad + int(0.045 * size)), speed,
               font=f["small"], fill=MUTED)
        d.text((pad, self.bottom - int(0.04 * size)), "amber arrow: angular momentum L, fixed in space",
               font=f["small"], fill=ACCENT)
        box = (pad, self.bottom, size - pad, size - pad // 2)
        self.strip = draw_strip(img, box, self.scene.study.t, self.scene.study.omega_exact, self.flips, self.t[-1],
                                fonts=f, colors=AXIS_RGB, muted=MUTED, text=TEXT, accent=ACCENT)
        return img

    def frame(self, k: int) -> np.ndarray:
        """Frame ``k`` as an (size, size, 3) uint8 array."""
        import dataclasses

        from PIL import Image, ImageDraw

        from .raster import SUPERSAMPLE, Overlay, paint

        R, s = self.R[k], SUPERSAMPLE
        overlay = Overlay()
        r = self.scene.radius
        overlay.arrow(-0.2 * r * self.L, 1.45 * r * self.L, ACCENT, 4.0, 22.0, self.camera, pieces=40)
        if self.view == "body":
            V = self.vertices @ R.T
        else:
            _model_overlay(self.scene, R, overlay)
            V = np.array([p for line in overlay.lines for p in line[:2]] + [d[0] for d in overlay.discs])
        # draw only the box around what moves: its corner (x0, y0) in view pixels
        xy, _ = self.camera.project(np.vstack([V, 1.55 * r * self.L, -0.2 * r * self.L]))
        x0, y0 = np.floor(xy.min(axis=0) / s - 12).astype(int)
        x1, y1 = np.ceil(xy.max(axis=0) / s + 12).astype(int)
        x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, self.size), min(y1, self.view_h)
        camera = dataclasses.replace(self.camera, center=(self.camera.center[0] - x0, self.camera.center[1] - y0))
        canvas = Image.new("RGB", ((x1 - x0) * s, (y1 - y0) * s), BACKGROUND)
        if self.view == "body":
            paint(canvas, camera, V, self.faces, self.face_rgb, overlay, face_part=self.part)
        else:
            paint(canvas, camera, overlay=overlay)
        img = self.base.copy()
        img.paste(canvas.reduce(s), (int(x0), self.top + int(y0)))
        self._annotate(ImageDraw.Draw(img), k)
        return np.asarray(img)

    def _annotate(self, d, k: int) -> None:
        """The clock, the strip's cursor, and the flip banner near a flip."""
        t, size, f = float(self.t[k]), self.size, self.fonts
        pad = int(0.022 * size)
        clock = f"t = {t:5.2f} s"
        d.text((size - pad - d.textlength(clock, font=f["text"]), pad), clock, font=f["text"], fill=TEXT)
        self.strip.cursor(d, t)
        near = np.flatnonzero(np.abs(self.flips - t) < 0.12 * self.scene.study.flip_interval)
        if len(near):
            i = int(near[0])
            y = self.top + int(0.02 * size)
            d.text((pad, y), f"flip {i + 1}", font=f["banner"], fill=ACCENT)
            d.text((pad, y + f["banner"].size + 6), f"predicted at {self.flips[i]:.2f} s", font=f["small"],
                   fill=ACCENT)


def render_flip(scene: FlipScene, path, *, size: int = VIDEO_SIZE, view: str = "body", fps: float | None = None,
                poster=None) -> dict:
    """Draw the flip and write it to ``path`` (``.mp4`` or ``.gif``), streaming; returns the
    writer's facts (file, frames, fps, duration_s, width, height) and the film's (view,
    speed, t_end).  ``poster``: also write the frame nearest the first flip there (PNG)."""
    path = Path(path)
    fps = fps or (GIF_FPS if path.suffix.lower() == ".gif" else VIDEO_FPS)
    t, speed = playback_times(film_span(scene.study), fps)
    r = FlipRenderer(scene, t, speed, size=size, view=view)
    info = write_animation((r.frame(k) for k in range(len(t))), path, fps=fps)
    info.update({"view": r.view, "speed": speed, "t_end": float(t[-1])})
    if poster is not None:
        import io

        from PIL import Image

        from .._core.atomic import write_bytes_atomic

        k = int(np.argmin(np.abs(t - (r.flips[0] if len(r.flips) else 0.0))))
        buf = io.BytesIO()
        Image.fromarray(r.frame(k)).save(buf, format="PNG", optimize=True)
        write_bytes_atomic(poster, buf.getvalue())
        info["poster"] = Path(poster).name
    return info


def write_animation(frames, path, *, fps: float = VIDEO_FPS) -> dict:
    """Write an iterable of (H, W, 3) uint8 frames as GIF (Pillow) or MP4 (imageio-ffmpeg) by
    the extension, atomically; returns file, frames, fps, duration_s, width, height."""
    path = Path(path)
    if path.suffix.lower() == ".gif":
        return _write_gif(frames, path, fps)
    if path.suffix.lower() == ".mp4":
        return _write_mp4(frames, path, fps)
    from .._core.errors import InputError

    raise InputError(f"animation file {path}: format {path.suffix!r} is not supported; use .gif or .mp4")


def _gif_palette(first):
    """One palette for the whole film: the first frame and ramps of every colour drawn."""
    from PIL import Image

    h, w = first.shape[:2]
    levels = np.linspace(0.25, 1.25, 48)[:, None]
    ramps = [np.clip(np.asarray(c, float) * levels, 0, 255) for c in PART_RGB + AXIS_RGB + (ACCENT,)]
    swatch = np.concatenate(ramps).astype(np.uint8)[None].repeat(8, axis=0)
    swatch = np.pad(swatch, ((0, 0), (0, max(0, w - swatch.shape[1])), (0, 0)), mode="edge")[:, :w]
    return Image.fromarray(np.concatenate([first, swatch])).quantize(colors=255, method=Image.Quantize.MEDIANCUT)


def _write_gif(frames, path: Path, fps: float) -> dict:
    import io

    from PIL import Image

    from .._core.atomic import write_bytes_atomic

    duration_ms = 10 * max(2, int(round(100 / fps)))  # GIF stores centiseconds; 20 ms is the browsers' floor
    it = iter(frames)
    first = np.asarray(next(it))
    palette = _gif_palette(first)
    count = [1]

    def rest():
        for f in it:
            count[0] += 1
            yield Image.fromarray(np.asarray(f)).quantize(palette=palette, dither=Image.Dither.NONE)

    buf = io.BytesIO()
    Image.fromarray(first).quantize(palette=palette, dither=Image.Dither.NONE).save(
        buf, format="GIF", save_all=True, append_images=rest(), duration=duration_ms, loop=0)
    write_bytes_atomic(path, buf.getvalue())
    n = count[0]
    return {"file": path.name, "frames": n, "fps": 1000 / duration_ms, "duration_s": n * duration_ms / 1000,
            "width": first.shape[1], "height": first.shape[0]}


def _write_mp4(frames, path: Path, fps: float) -> dict:
    import os

    import imageio_ffmpeg

    from .._core.atomic import replace_with_temp, temp_beside

    tmp = temp_beside(path)   # ffmpeg picks the container from the name: .tmp then -f mp4
    writer, n, shape = None, 0, None
    try:
        for f in frames:
            if writer is None:
                shape = f.shape
                writer = imageio_ffmpeg.write_frames(tmp, (shape[1], shape[0]), fps=fps, macro_block_size=8,
                                                     quality=7, output_params=["-f", "mp4", "-preset", "veryfast",
                                                                               "-movflags", "+faststart"])
                writer.send(None)
            writer.send(np.ascontiguousarray(f))
            n += 1
        writer.close()
        writer = None
        replace_with_temp(tmp, path)
    finally:
        if writer is not None:      # a frame failed: stop ffmpeg
            writer.close()
        if os.path.exists(tmp):
            os.unlink(tmp)
    return {"file": path.name, "frames": n, "fps": float(fps), "duration_s": n / fps,
            "width": shape[1], "height": shape[0]}

"""The control showcase's video: the same spin side by side, wheels idle (it flips) and under the
LQR (it holds), the angular momentum fixed in space, and a strip of both tilts against time.

Every frame is the simulated attitude at its time (the rollout's saved states), drawn by
:mod:`.raster` as the flip video is; written by :func:`.animation.write_animation`.
"""

from __future__ import annotations

import numpy as np

from .animation import ACCENT, BACKGROUND, MUTED, PART_RGB, TEXT, font, write_animation

#: frame size (pixels), the body time filmed [s] and its playback speed
SIZE = (960, 560)
FILM_SECONDS = 6.0
SPEED = 0.5
MAX_FACES = 1500
HELD_RGB, FREE_RGB = (90, 160, 230), (225, 95, 80)
#: the strip's tilt axis [deg] (log scale)
TILT_RANGE = (1e-2, 180.0)


class HoldRenderer:
    """Frame k of the two panels (free | held) at body time ``times[k]``."""

    def __init__(self, run, mesh, times, *, size=SIZE, speed: float = SPEED):
        from .._core.rotations import quat_to_matrix
        from .display_mesh import cluster_decimate, face_parts
        from .raster import Camera

        self.run, self.t, self.speed = run, np.asarray(times, float), float(speed)
        self.W, self.H = size
        idx = np.clip(np.round(self.t / (run.t[1] - run.t[0])).astype(int), 0, run.t.size - 1)
        R_BP = run.setup.gyrostat.body.R_body_principal         # the mesh is in the principal frame
        self.R = {k: quat_to_matrix(x[idx, 6:10]) @ R_BP for k, x in (("free", run.free), ("held", run.held))}
        self.tilt = {"free": np.degrees(run.tilt_free[idx]), "held": np.degrees(run.tilt_held[idx])}
        g = run.setup.gyrostat
        x0 = run.held[0]
        L = quat_to_matrix(x0[6:10]) @ (g.body.inertia_com @ x0[10:13] + x0[13:] @ g.wheel_axes)
        self.L = L / np.linalg.norm(L)
        V, F = cluster_decimate(mesh.vertices, mesh.faces, MAX_FACES)
        self.V, self.F = V, F
        self.part = mesh.part if len(F) == len(mesh.faces) else face_parts(len(V), F)
        self.radius = float(np.sqrt((V ** 2).sum(axis=1).max()))
        self.top, self.bottom = int(0.12 * self.H), int(0.76 * self.H)
        half = self.W // 2
        self.camera = Camera.looking_at_origin(self.L, center=(half / 2, 0.5 * (self.bottom - self.top)),
                                               scale=0.36 * (self.bottom - self.top) / self.radius)
        self.fonts = {k: font(max(8, int(round(self.H * f))), bold=b) for k, f, b in
                      (("title", 0.038, True), ("text", 0.03, False), ("small", 0.024, False))}
        self.base = self._static()

    def _x(self, t):
        return self.sx0 + (self.sx1 - self.sx0) * np.asarray(t) / self.t[-1]

    def _y(self, deg):
        lo, hi = np.log10(TILT_RANGE)
        v = (np.log10(np.clip(deg, *TILT_RANGE)) - lo) / (hi - lo)
        return self.sy1 - (self.sy1 - self.sy0) * v

    def _static(self):
        from PIL import Image, ImageDraw

        W, H, f = self.W, self.H, self.fonts
        img = Image.new("RGB", (W, H), BACKGROUND)
        d = ImageDraw.Draw(img)
        pad = int(0.02 * W)
        st = self.run.setup
        d.text((pad, pad), f"{st.name}: {st.spin_rate:g} rad/s about the intermediate axis, "
               f"{np.degrees(st.initial_tilt):g} deg off at t = 0", font=f["title"], fill=TEXT)
        speed = "real time" if abs(self.speed - 1) < 1e-6 else f"{self.speed:.3g}x real time"
        d.text((pad, pad + int(0.05 * H)), f"simulated (splitting, {st.substeps} steps per {1e3 * st.period:g} ms "
               f"control period), played at {speed}", font=f["small"], fill=MUTED)
        for k, (label, rgb) in enumerate((("wheels idle: the flip", FREE_RGB),
                                          ("LQR on three wheels: held", HELD_RGB))):
            d.text((k * W // 2 + pad, self.top), label, font=f["text"], fill=rgb)
        d.line((W // 2, self.top, W // 2, self.bottom), fill=MUTED, width=1)
        d.text((pad, self.bottom - int(0.04 * H)), "amber arrow: the angular momentum, fixed in space",
               font=f["small"], fill=ACCENT)
        # the strip: both tilts against time, log scale, the bound dashed
        small = f["small"]
        self.sx0, self.sx1 = pad + small.getlength("180 deg") + 10, W - pad
        self.sy0, self.sy1 = self.bottom + int(0.05 * H), H - int(0.06 * H)
        d.text((pad, self.bottom + 4), "tilt of the spin axis from the angular momentum (log scale)", font=small,
               fill=TEXT)
        for deg in (0.01, 0.1, 1.0, 10.0, 180.0):
            y = float(self._y(deg))
            label = f"{deg:g} deg"
            d.text((self.sx0 - 6 - d.textlength(label, font=small), y - small.size / 2), label, font=small, fill=MUTED)
            dash = deg == np.degrees(st.max_tilt)
            for x in np.arange(self.sx0, self.sx1, 10.0 if dash else 4.0):
                d.line((x, y, min(x + (5 if dash else 1), self.sx1), y), fill=MUTED, width=1)
        i = np.arange(self.t.size)
        for key, rgb in (("free", FREE_RGB), ("held", HELD_RGB)):
            pts = list(zip(self._x(self.t[i]).tolist(), self._y(self.tilt[key][i]).tolist()))
            d.line(pts, fill=rgb, width=2, joint="curve")
        for tick in range(int(self.t[-1]) + 1):
            label = f"{tick} s"
            d.text((float(self._x(tick)) - d.textlength(label, font=small) / 2, self.sy1 + 3), label, font=small,
                   fill=MUTED)
        return img

    def frame(self, k: int) -> np.ndarray:
        import dataclasses

        from PIL import Image, ImageDraw

        from .raster import SUPERSAMPLE, Overlay, paint

        s, img = SUPERSAMPLE, self.base.copy()
        h3d, half = self.bottom - self.top - int(0.1 * self.H), self.W // 2
        rgb = np.array(PART_RGB)[self.part % len(PART_RGB)]
        for j, key in enumerate(("free", "held")):
            overlay = Overlay()
            r = self.radius
            overlay.arrow(-0.2 * r * self.L, 1.45 * r * self.L, ACCENT, 4.0, 20.0, self.camera, pieces=30)
            camera = dataclasses.replace(self.camera, center=(self.camera.center[0], self.camera.center[1]))
            canvas = Image.new("RGB", (half * s, h3d * s), BACKGROUND)
            paint(canvas, camera, self.V @ self.R[key][k].T, self.F, rgb, overlay, face_part=self.part)
            img.paste(canvas.reduce(s), (j * half + 1 if j else 0, self.top + int(0.05 * self.H)))
        d = ImageDraw.Draw(img)
        pad, f = int(0.02 * self.W), self.fonts
        t = float(self.t[k])
        clock = f"t = {t:5.2f} s"
        d.text((self.W - pad - d.textlength(clock, font=f["text"]), pad + int(0.045 * self.H)), clock, font=f["text"],
               fill=TEXT)
        for j, (key, rgb_) in enumerate((("free", FREE_RGB), ("held", HELD_RGB))):
            text = f"tilt {self.tilt[key][k]:.3g} deg"
            d.text(((j + 1) * half - pad - d.textlength(text, font=f["text"]), self.top), text, font=f["text"],
                   fill=rgb_)
            x, y = float(self._x(t)), float(self._y(self.tilt[key][k]))
            d.ellipse((x - 4, y - 4, x + 4, y + 4), fill=rgb_, outline=TEXT)
        x = float(self._x(t))
        d.line((x, self.sy0, x, self.sy1), fill=TEXT, width=1)
        return np.asarray(img)


def render_hold(run, mesh, path, *, seconds: float = FILM_SECONDS, speed: float = SPEED, fps: float | None = None,
                poster=None) -> dict:
    """Film ``seconds`` of body time of an :class:`inertia.control.studies.ActiveRun` beside its free
    twin into ``path`` (.mp4 or .gif); ``mesh`` a :class:`.display_mesh.DisplayMesh` of the body.
    Returns the writer's facts with the speed and the body time filmed; ``poster``: the frame
    nearest the free body's first turn past 90 degrees, as PNG."""
    from pathlib import Path

    from .animation import GIF_FPS, VIDEO_FPS

    path = Path(path)
    fps = fps or (GIF_FPS if path.suffix.lower() == ".gif" else VIDEO_FPS)
    span = min(float(seconds), float(run.t[-1]))
    n = max(2, int(round(span / speed * fps)))
    times = np.arange(n) * (speed / fps)
    r = HoldRenderer(run, mesh, times, speed=speed)
    info = write_animation((r.frame(k) for k in range(n)), path, fps=fps)
    info.update({"speed": speed, "t_end": float(times[-1])})
    if poster is not None:
        import io

        from PIL import Image

        from .._core.atomic import write_bytes_atomic

        over = np.flatnonzero(r.tilt["free"] > 90.0)
        k = int(over[0]) if over.size else n // 2
        buf = io.BytesIO()
        Image.fromarray(r.frame(k)).save(buf, format="PNG", optimize=True)
        write_bytes_atomic(poster, buf.getvalue())
        info["poster"] = Path(poster).name
    return info

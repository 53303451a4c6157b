"""An animation of the flip: the tumbling body, its six point masses and the fixed
angular-momentum vector, frames from the exact solution, time in a corner.

GIF through Pillow (always available with matplotlib), or MP4 through the ffmpeg binary
that the ``imageio-ffmpeg`` package ships (no system ffmpeg needed).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def render_frames(study, six_body_principal, box_half, *, n_frames: int = 48, size_px: int = 360):
    """RGB frames (n, H, W, 3) uint8 of the body at ``n_frames`` evenly spaced times."""
    from .._core.rotations import quat_to_matrix
    from ..dynamics.exact import exact_solution
    from .plots import box_wire, pyplot

    plt = pyplot()
    t = np.linspace(study.t[0], study.t[-1], n_frames)
    q, _ = exact_solution(study.moments, study.omega0_body, t)
    R = quat_to_matrix(q)
    L = study.L_world / np.linalg.norm(study.L_world)
    span = 1.25 * max(float(np.abs(six_body_principal).max()), float(np.max(box_half)))
    corners, edges = box_wire(box_half)
    dpi = 100
    fig = plt.figure(figsize=(size_px / dpi, size_px / dpi), dpi=dpi)
    ax = fig.add_subplot(projection="3d")
    frames = []
    for k in range(n_frames):
        ax.cla()
        pts = six_body_principal @ R[k].T
        cw = corners @ R[k].T
        for i, j in edges:
            ax.plot(*zip(cw[i], cw[j]), color="0.55", lw=0.8)
        ax.scatter(pts[:, 0], pts[:, 1], pts[:, 2], s=30, color="tab:orange")
        for a, col in zip(range(3), ("tab:red", "tab:green", "tab:blue")):
            ax.plot(*zip((0, 0, 0), span * 0.8 * R[k][:, a]), color=col, lw=1.5)
        ax.quiver(0, 0, 0, *(span * L), color="k", lw=2)
        ax.set_xlim(-span, span)
        ax.set_ylim(-span, span)
        ax.set_zlim(-span, span)
        ax.set_box_aspect((1, 1, 1))
        ax.set_axis_off()
        ax.text2D(0.02, 0.95, f"t = {t[k]:6.2f} s", transform=ax.transAxes, family="monospace")
        ax.text2D(0.02, 0.02, "black: L (fixed in space)", transform=ax.transAxes, fontsize=7)
        fig.canvas.draw()
        frames.append(np.asarray(fig.canvas.buffer_rgba())[..., :3].copy())
    plt.close(fig)
    return np.stack(frames), t


def write_animation(frames, path, *, fps: float = 12.0) -> dict:
    """Write frames as GIF (Pillow) or MP4 (imageio-ffmpeg) by the extension; atomic."""
    import io

    from .._core.atomic import write_bytes_atomic

    path = Path(path)
    if path.suffix.lower() == ".gif":
        from PIL import Image

        images = [Image.fromarray(f) for f in frames]
        buf = io.BytesIO()
        duration_ms = 10 * max(2, int(round(100 / fps)))  # GIF stores centiseconds; 20 ms is the browsers' floor
        images[0].save(buf, format="GIF", save_all=True, append_images=images[1:], duration=duration_ms, loop=0)
        write_bytes_atomic(path, buf.getvalue())
        return {"file": path.name, "frames": len(frames), "duration_s": len(frames) * duration_ms / 1000}
    if path.suffix.lower() == ".mp4":
        import os

        import imageio_ffmpeg

        from .._core.atomic import replace_with_temp, temp_beside

        h, w = frames.shape[1:3]
        tmp = temp_beside(path)   # ffmpeg picks the container from the name: .tmp then -f mp4
        try:
            writer = imageio_ffmpeg.write_frames(tmp, (w, h), fps=fps, macro_block_size=8, quality=7,
                                                 output_params=["-f", "mp4"])
            writer.send(None)
            for f in frames:
                writer.send(np.ascontiguousarray(f))
            writer.close()
            replace_with_temp(tmp, path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
        return {"file": path.name, "frames": len(frames), "duration_s": len(frames) / fps}
    from .._core.errors import InputError

    raise InputError(f"animation file {path}: format {path.suffix!r} is not supported; use .gif or .mp4")

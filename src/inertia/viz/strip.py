"""The video's lower strip: the body angular velocity against time, flips marked, a cursor.

Drawn once with Pillow at twice the size and halved (smooth lines); each frame then only
draws the cursor and the three current values on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Strip:
    """The plotted area (pixels) and the data, to place the cursor of each frame."""

    x0: float
    x1: float
    y0: float
    y1: float
    t_end: float
    w_max: float
    t: np.ndarray
    omega: np.ndarray
    colors: tuple
    text: tuple

    def x(self, t):
        return self.x0 + (self.x1 - self.x0) * np.asarray(t) / self.t_end

    def y(self, w):
        return 0.5 * (self.y0 + self.y1) - 0.5 * (self.y1 - self.y0) * np.asarray(w) / self.w_max

    def cursor(self, d, t: float) -> None:
        x = float(self.x(t))
        d.line((x, self.y0, x, self.y1), fill=self.text, width=1)
        for k in range(3):
            y = float(self.y(np.interp(t, self.t, self.omega[:, k])))
            d.ellipse((x - 4, y - 4, x + 4, y + 4), fill=self.colors[k], outline=self.text)


def draw_strip(img, box, t, omega, flips, t_end: float, *, fonts, colors, muted, text, accent) -> Strip:
    """Draw the strip into ``img`` inside ``box`` (x0, y0, x1, y1); returns its :class:`Strip`."""
    from PIL import Image, ImageDraw

    s = 2
    X0, Y0, X1, Y1 = box
    keep = t <= t_end + 1e-12
    t, omega = np.asarray(t)[keep], np.asarray(omega)[keep]
    w_max = 1.08 * float(np.abs(omega).max())
    small = fonts["small"]
    row = small.size + 6
    label_w = 1.0 * small.getlength("+00.0") + 8
    strip = Strip(X0 + label_w, X1, Y0 + row + 4, Y1 - row, t_end, w_max, t, omega, colors, text)
    big = Image.new("RGB", ((X1 - X0) * s, (Y1 - Y0) * s), img.getpixel((X0, Y0)))
    d = ImageDraw.Draw(big)

    def local(x, y):
        return (np.asarray(x) - X0) * s, (np.asarray(y) - Y0) * s

    xa, ya = local([strip.x0, strip.x1], [strip.y(0)] * 2)
    d.line((xa[0], ya[0], xa[1], ya[1]), fill=muted, width=s)
    for tf in flips:
        xf, _ = local(strip.x(tf), 0)
        for y in np.arange(strip.y0, strip.y1, 8.0):
            _, yy = local(0, [y, min(y + 4, strip.y1)])
            d.line((xf, yy[0], xf, yy[1]), fill=accent, width=s)
    for k in range(3):
        xs, ys = local(strip.x(t), strip.y(omega[:, k]))
        d.line(list(zip(xs.tolist(), ys.tolist())), fill=colors[k], width=2 * s, joint="curve")
    img.paste(big.reduce(s), (X0, Y0))
    d = ImageDraw.Draw(img)
    x = X0
    legend = (("body angular velocity [rad/s]:", text), ("\u03c9\u2081 minor axis", colors[0]),
              ("\u03c9\u2082 intermediate", colors[1]), ("\u03c9\u2083 major", colors[2]))
    for label, color in legend:
        d.text((x, Y0), label, font=small, fill=color)
        x += d.textlength(label, font=small) + 14
    d.text((X1 - d.textlength("dashed: predicted flips", font=small), Y0), "dashed: predicted flips",
           font=small, fill=accent)
    for v in (-w_max / 1.08, w_max / 1.08):
        label = f"{v:+.3g}"
        d.text((strip.x0 - 6 - d.textlength(label, font=small), float(strip.y(v)) - small.size / 2 - 1), label,
               font=small, fill=muted)
    for tick in _ticks(t_end):
        x = float(strip.x(tick))
        label = f"{tick:g} s"
        d.text((x - d.textlength(label, font=small) / 2, strip.y1 + 3), label, font=small, fill=muted)
    return strip


def _ticks(t_end: float) -> np.ndarray:
    """About five round tick values in [0, t_end]."""
    raw = t_end / 5
    mag = 10 ** np.floor(np.log10(raw))
    step = min((1, 2, 5, 10), key=lambda m: abs(m * mag - raw)) * mag
    return np.arange(0.0, t_end + 1e-9 * t_end, step)

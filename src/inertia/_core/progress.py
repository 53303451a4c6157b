"""One progress bar for every long command (``inertia batch``, ``inertia demo``'s report).

:class:`Progress` counts units of work (files, steps) and draws one line on stderr: a bar,
``done/total unit``, the rate and the time left.  On a terminal the line is redrawn in place
at most five times a second; into a file or a pipe a line is appended every ``log_every``
seconds (so logs stay short).  With ``delay``, nothing is drawn before that many seconds
have passed (a run that ends sooner stays silent).  Disabled, it prints nothing.  :class:`StepProgress` is the
same bar over named steps (``bar("plotting")``), drawn on a terminal only.
"""

from __future__ import annotations

import sys
import time

#: characters of the bar itself
BAR_WIDTH = 30


def bar_text(done: int, total: int, width: int = BAR_WIDTH) -> str:
    """``[#####.....]`` for ``done`` of ``total`` (clipped to the ends)."""
    filled = 0 if total <= 0 else max(0, min(width, width * done // total))
    return "[" + "#" * filled + "." * (width - filled) + "]"


class Progress:
    """A one-line progress bar on ``stream`` (default stderr): units done, rate, time left."""

    def __init__(self, total: int, *, unit: str = "files", enabled: bool = True, stream=None,
                 tty_only: bool = False, log_every: float = 5.0, delay: float = 0.0):
        self.total, self.done = int(total), 0
        self.unit = unit
        self.stream = stream or sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.enabled = enabled and self.total > 0 and (self.tty or not tty_only)
        self.log_every = log_every
        self.delay = delay
        self.t0 = self._last = time.perf_counter()
        self._width = 0

    def update(self, n: int = 1, label: str = "") -> None:
        """Count ``n`` more units done (``label``: what is being done now, shown after the counts)."""
        self.done += n
        now = time.perf_counter()
        if not self.enabled or now - self.t0 < self.delay or (
                now - self._last < (0.2 if self.tty else self.log_every) and self.done < self.total and not label):
            return
        self._last = now
        rate = self.done / max(now - self.t0, 1e-9)
        eta = (self.total - self.done) / rate if rate > 0 else float("inf")
        line = f"{bar_text(self.done, self.total)} {self.done}/{self.total} {self.unit}"
        line += f"  {label}..." if label else f"  {rate:.1f} {self.unit}/s  ETA {eta:.0f} s"
        if self.tty:
            self.stream.write("\r" + line.ljust(self._width))
            self._width = len(line)
            if self.done >= self.total and not label:
                self.stream.write("\n")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()

    def clear(self) -> None:
        """Erase the bar's line (terminal only): the command's own output follows cleanly."""
        if self.enabled and self.tty and self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0


class StepProgress(Progress):
    """:class:`Progress` over named steps, on a terminal only: ``bar("plotting")`` starts a step."""

    def __init__(self, steps, *, stream=None):
        super().__init__(len(steps), unit="steps", stream=stream, tty_only=True)

    def __call__(self, name: str) -> None:
        self.update(1, label=name)

    def done_all(self) -> None:
        self.clear()

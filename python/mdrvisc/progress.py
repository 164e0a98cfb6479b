"""Progress display of long solves: :class:`ProgressBar` is a solver's ``progress(stage, done,
total)`` callback that shows a bar with the time left in each stage.

``mv.solve(scene, progress=True)`` and the ``mdrvisc run`` command line use it. With tqdm
installed (``pip install 'mdrvisc[progress]'``) the bar is tqdm's (``tqdm.auto``: a text bar in
terminals, a widget in notebooks); without it, one self-overwriting line on stderr.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["ProgressBar"]

#: Characters of the plain bar.
_WIDTH = 24


def _tqdm_class():
    """tqdm's automatic bar class (terminal or notebook), or None when tqdm is not installed."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm


def _duration(seconds: float) -> str:
    """``seconds`` as ``12.3 s``, ``4 min 05 s`` or ``2 h 03 min``."""
    if seconds < 60:
        return f"{seconds:.1f} s"
    if seconds < 3600:
        return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"
    return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60):02d} min"


class ProgressBar:
    """A progress callback ``bar(stage, done, total)`` showing, per stage, a bar, the count, the
    time elapsed and the time left (estimated from the stage's mean rate so far).

    Parameters
    ----------
    file : text stream, optional
        Where the bar goes; default ``sys.stderr``.
    use_tqdm : bool, optional
        True: tqdm's bar (ImportError when tqdm is missing); False: the plain line; default:
        tqdm's when it is installed.
    interval : float
        Shortest time (s) between two redraws of the plain line; the end of a stage is always
        drawn.

    Examples
    --------
    >>> import io
    >>> bar = ProgressBar(file=io.StringIO(), use_tqdm=False)
    >>> bar("time steps", 50, 100); bar("time steps", 100, 100); bar.close()
    >>> bar
    ProgressBar(stage='time steps', done=100, total=100, tqdm=False)
    """

    def __init__(self, file: TextIO | None = None, use_tqdm: bool | None = None,
                 interval: float = 0.2) -> None:
        tqdm = _tqdm_class() if use_tqdm is not False else None
        if use_tqdm and tqdm is None:
            raise ImportError("ProgressBar(use_tqdm=True) needs tqdm: pip install 'mdrvisc[progress]'")
        self._tqdm_class, self._tqdm = tqdm, None
        self.file, self.interval = file, float(interval)
        self.stage: str | None = None
        self.done = self.total = 0
        self.inner = ""
        self._active = False
        self._start = self._drawn = 0.0
        self._open = False

    @property
    def _out(self) -> TextIO:
        return sys.stderr if self.file is None else self.file

    def __call__(self, stage: str, done: int, total: int) -> None:
        """Records that ``done`` of ``total`` units of ``stage`` are finished and redraws.

        A stage named ``... iterations`` counts towards a limit, not a known total: it is
        shown as a count after the current bar, without a time left."""
        now = time.perf_counter()
        if stage.endswith("iterations"):
            self.inner = f"{stage} {done}"
            if self._tqdm is not None:
                self._tqdm.set_postfix_str(self.inner, refresh=False)
            elif now - self._drawn >= self.interval:
                self._draw(now)
            return
        if not self._active or stage != self.stage or done < self.done:
            if self._active:
                self.close()
            self.stage, self._start, self._drawn, self._active = stage, now, 0.0, True
            if self._tqdm_class is not None:
                self._tqdm = self._tqdm_class(total=total, desc=stage, file=self.file, leave=True)
        self.done, self.total, self.inner = done, total, ""
        if self._tqdm is not None:
            self._tqdm.total = total
            self._tqdm.update(done - self._tqdm.n)
        elif done >= total or now - self._drawn >= self.interval:
            self._draw(now)
        if done >= total:
            self.close()

    def _draw(self, now: float) -> None:
        """Overwrites the plain line with the current bar and iteration count."""
        self._drawn = now
        parts = [self.line(now - self._start) if self._active else "", self.inner]
        self._out.write("\r" + "  ".join(p for p in parts if p).ljust(78))
        self._open = True
        self._out.flush()

    def line(self, elapsed: float) -> str:
        """The bar of the current stage after ``elapsed`` seconds in it."""
        fraction = min(self.done / self.total, 1.0) if self.total > 0 else 1.0
        filled = int(round(fraction * _WIDTH))
        left = (f", {_duration(elapsed * (self.total - self.done) / self.done)} left"
                if 0 < self.done < self.total else "")
        return (f"  {self.stage} [{'#' * filled}{'-' * (_WIDTH - filled)}] {self.done}/{self.total}"
                f" {_duration(elapsed)}{left}")

    def close(self) -> None:
        """Ends the current bar (a newline after the plain line)."""
        if self._tqdm is not None:
            self._tqdm.close()
            self._tqdm = None
        if self._open:
            self._out.write("\n")
            self._out.flush()
            self._open = False
        self._active, self.inner = False, ""

    def __repr__(self) -> str:
        return (f"ProgressBar(stage={self.stage!r}, done={self.done}, total={self.total}, "
                f"tqdm={self._tqdm_class is not None})")

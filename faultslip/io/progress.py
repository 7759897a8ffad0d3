"""Progress of long work, through one library (tqdm), wherever the user watches.

A long function takes ``progress``: ``None`` or ``False`` for silence, ``True`` for a bar, or a
callable ``(done, total)``. :func:`reporter` turns ``True`` into a tqdm bar that suits where the
output goes:

* a terminal: a live bar on stderr, shown after ``delay`` seconds so quick runs stay quiet;
* a notebook (an IPython kernel is running): ``tqdm.auto``'s widget, or its text bar without
  ipywidgets;
* stderr redirected to a file or a pipe: one plain log line every ``interval`` seconds, and a last
  line when the work ends, instead of carriage returns a log cannot show.

tqdm (MPL-2.0/MIT) is small, pure Python and kept; it is imported only when a bar is shown.
"""

from __future__ import annotations

import sys
import time


class _LogLines:
    """A text stream for tqdm that writes each refresh as one line (a log file has no carriage return)."""

    def __init__(self, stream):
        self.stream = stream
        self.last = ""

    def write(self, text):
        line = text.replace("\r", "").replace("\x1b[A", "").strip()
        count = line.split("[", 1)[0]  # label, bar and done/total: a refresh that moved nothing is not a line
        if line and count != self.last:
            self.last = count
            self.stream.write(time.strftime("%H:%M:%S ") + line + "\n")

    def flush(self):
        self.stream.flush()


def _in_notebook() -> bool:
    shell = sys.modules.get("IPython")
    try:
        return shell is not None and shell.get_ipython() is not None and \
            "IPKernelApp" in shell.get_ipython().config
    except Exception:  # an IPython without a kernel, or an unusual shell: not a notebook
        return False


class Progress:
    """A callable ``(done, total)`` over one tqdm bar; closes itself when ``done`` reaches ``total``."""

    def __init__(self, label: str, unit: str = "it", delay: float = 2.0, interval: float = 30.0, stream=None):
        self.label, self.unit, self.delay, self.interval = label, unit, delay, interval
        self.stream = stream if stream is not None else sys.stderr
        self.bar = None

    def _open(self, total):
        if _in_notebook():
            from tqdm.auto import tqdm  # heavy: imported where used (the widget or text bar)

            return tqdm(total=total, desc=self.label, unit=self.unit, delay=self.delay)
        from tqdm import tqdm  # heavy: imported where used

        if getattr(self.stream, "isatty", lambda: False)():
            return tqdm(total=total, desc=self.label, unit=self.unit, delay=self.delay, file=self.stream,
                        dynamic_ncols=True)
        return tqdm(total=total, desc=self.label, unit=self.unit, delay=self.delay, file=_LogLines(self.stream),
                    mininterval=self.interval, maxinterval=self.interval, ascii=True, ncols=80)

    def announce(self, text: str) -> None:
        """One line on the stream before the work starts (what it will cost), whatever the bar's delay."""
        print(f"faultslip: {text}", file=self.stream, flush=True)

    def __call__(self, done: int, total: int | None = None) -> None:
        if self.bar is None:
            self.bar = self._open(total)
        elif total is not None and self.bar.total != total:
            self.bar.total = total
        self.bar.update(done - self.bar.n)
        if total is not None and done >= total:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def reporter(progress, label: str, unit: str = "it"):
    """``progress`` as a callable ``(done, total)`` or None: True gives a :class:`Progress` bar."""
    if progress is None or progress is False:
        return None
    if progress is True:
        return Progress(label, unit)
    if callable(progress):
        return progress
    raise TypeError(f"progress must be True, False, None or a callable (done, total), got {progress!r}")


def duration(seconds: float) -> str:
    """A time as a person reads it: "40 s", "3.2 min", "1.4 h"."""
    if seconds < 90:
        return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.2g} min"
    return f"{seconds / 3600:.2g} h"


#: Work expected to take less than this (s) starts without a line saying so (its bar shows after two seconds).
ANNOUNCE_FROM = 10.0


def announce(progress, text: str, seconds: float | None = None) -> None:
    """Say ``text`` (what the work will cost) before it starts, through the reporter's ``announce`` where it has
    one (a :class:`Progress` bar: a line on its stream; a callable has nowhere to say it), when the work is expected
    to take ``seconds`` >= :data:`ANNOUNCE_FROM` (None: always)."""
    say = getattr(progress, "announce", None)
    if say is not None and (seconds is None or seconds >= ANNOUNCE_FROM):
        say(text)


def counted(progress, label: str, total: int, unit: str, what: str):
    """A reporter for ``total`` like pieces of work (fits of windows, candidate laws): after the first, it says
    what the rest will cost when that is 10 s or more (:data:`ANNOUNCE_FROM`), and it reports (done, total).
    Returns ``step(done, seconds_of_the_first)``, or None for silence."""
    report = reporter(progress, label, unit)
    if report is None:
        return None
    said = [False]

    def step(done: int, first_seconds: float | None = None) -> None:
        if first_seconds is not None and not said[0] and done == 1 and total > 1:
            said[0] = True
            rest = first_seconds * (total - 1)
            announce(report, f"{what}: {total} in all, about {duration(rest)} more (the first took "
                             f"{duration(first_seconds)})", rest)
        report(done, total)

    return step

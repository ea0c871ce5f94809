"""The batch's progress line: cases done / failed / running, elapsed time and an estimate.

Our own rather than Dask's dashboard, which needs bokeh (Debian 12 has none). On a terminal
the line is redrawn in place; into a file or a pipe a line is written whenever the counts
change, at most every `every` seconds, so that logs stay short.
"""
import sys
import time


def clock(seconds):
    seconds = int(round(seconds))
    return "%d:%02d:%02d" % (seconds // 3600, seconds // 60 % 60, seconds % 60)


class ProgressBar:
    def __init__(self, total, reused=0, stream=None, width=24, every=10.0):
        self.total, self.reused = total, reused
        self.stream = stream or sys.stderr
        self.width, self.every = width, every
        self.started = time.time()
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.printed, self.last_time = None, 0.0  # the counts last written, and when

    def text(self, ok, failed, running):
        """ok and failed include the reused cases; the estimate is from this run's cases."""
        elapsed = time.time() - self.started
        finished = ok + failed
        ran = finished - self.reused
        left = self.total - finished
        if left == 0:
            estimate = "done"
        elif ran > 0:
            estimate = "~%s left" % clock(elapsed / ran * left)
        else:
            estimate = "estimate after the first case"
        filled = int(self.width * finished / self.total) if self.total else self.width
        return "[%s%s] %d/%d done, %d failed, %d running | %s elapsed, %s" % (
            "#" * filled, "." * (self.width - filled), finished, self.total, failed, running,
            clock(elapsed), estimate)

    def update(self, ok, failed, running, force=False):
        counts = (ok, failed, running)
        now = time.time()
        if self.tty:
            self.stream.write("\r" + self.text(ok, failed, running) + "\033[K")
            self.stream.flush()
        elif force or (counts != self.printed and now - self.last_time >= self.every):
            self.stream.write(self.text(ok, failed, running) + "\n")
            self.stream.flush()
            self.printed, self.last_time = counts, now

    def close(self, ok, failed):
        if self.tty or self.printed != (ok, failed, 0):
            self.update(ok, failed, 0, force=True)
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()

"""Progress lines for long work: redrawn in place on a terminal, sparse in a log."""
import sys
import time


class Reporter:
    def __init__(self, what, unit="items", stream=None, interval=0.5):
        self.what, self.unit = what, unit
        self.stream = stream or sys.stderr
        self.interactive = self.stream.isatty()
        # Logs get a line every 10 s instead of a redraw twice a second.
        self.interval = interval if self.interactive else 10.0
        self.started = time.monotonic()
        self.last = 0.0

    def __call__(self, done, total, simulated_seconds=None):
        now = time.monotonic()
        if now - self.last < self.interval and done < total:
            return
        self.last = now
        rate = done / max(now - self.started, 1e-9)
        extra = f", {simulated_seconds:.1f} s of data" if simulated_seconds is not None else ""
        line = f"{self.what}: {done}/{total} {self.unit} ({rate:.0f}/s{extra})"
        if self.interactive:
            self.stream.write("\r" + line + "\x1b[K")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()

    def finish(self):
        if self.interactive:
            self.stream.write("\n")
            self.stream.flush()

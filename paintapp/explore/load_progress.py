"""Progress of a long load on the terminal: one line rewritten in place on stderr, and nothing
at all when stderr is not a terminal (redirected to a file or a pipe)."""

from __future__ import annotations

import sys
from typing import Any, TextIO


class Progress:
    """Reports the stages of loading ``source`` (``stream``: default stderr)."""

    def __init__(self, source: str, stream: TextIO | None = None) -> None:
        self.source = source
        self.stream = stream if stream is not None else sys.stderr
        try:
            self.enabled = bool(self.stream.isatty())
        except (AttributeError, ValueError):  # no isatty, or closed
            self.enabled = False
        self._shown = False

    def show(self, stage: str, fraction: float | None = None) -> None:
        """Rewrite the line: ``stage`` and, when known, how far it is (0..1)."""
        if not self.enabled:
            return
        percent = "" if fraction is None else f" {100.0 * min(max(fraction, 0.0), 1.0):3.0f} %"
        self.stream.write(f"\r{self.source}: {stage}{percent}\x1b[K")
        self.stream.flush()
        self._shown = True

    def watch(self, algorithm: Any, stage: str) -> None:
        """Show a VTK algorithm's own progress events under ``stage``."""
        if not self.enabled:
            return

        def report(caller: Any, _event: str) -> None:
            self.show(stage, float(caller.GetProgress()))

        algorithm.AddObserver("ProgressEvent", report)

    def done(self) -> None:
        """End the line (when one was shown)."""
        if self._shown:
            self.stream.write("\r\x1b[K")
            self.stream.flush()
            self._shown = False

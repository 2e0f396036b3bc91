"""The first run after an install: the numba kernels compile once, and the terminal says so.

Every kernel is compiled with ``cache=True`` (:mod:`solver.compiled.jit`): the first process that
calls it compiles it and writes the machine code to numba's cache (``__pycache__`` beside its
module, or under ``NUMBA_CACHE_DIR``); later processes load it in milliseconds. On a fresh
install the painting commands would otherwise sit silent for the minute that takes.

:func:`warm_up` runs before the replay of ``paintapp demo`` and ``paintapp replay``. When :func:`kernels_cold` finds no
cached code for the sentinel kernels (:data:`SENTINELS`, which every painting run calls), it
replays the first :data:`WARM_UP_RECORDS` records of the command's strokes with the command's
scene, fidelity and device (the same kernels with the same argument types as the real run), while
:class:`CompileProgress` counts the kernels numba compiles and the seconds spent on the terminal.
The real run then finds them compiled. On a warm cache it reads a few index files and returns
(well under a millisecond). Off a terminal (output redirected) it does nothing: the run compiles
its kernels as it goes, without a word. The painting window compiles its kernels in its own
warm-up (:mod:`paintapp.app.warmup`); ``paintapp paint`` only says so on the terminal.
"""

from __future__ import annotations

import dataclasses
import importlib
import sys
import threading
import time
from types import TracebackType
from typing import TYPE_CHECKING, Any, TextIO

if TYPE_CHECKING:
    from paintapp.paint.paint_scene import PaintScene
    from paintapp.strokes.files import StrokeFile

MESSAGE = "compiling the paint kernels (first run only; cached afterwards)"
#: Kernels (module, name) every painting run calls early; no cached code for one: a cold cache.
SENTINELS: tuple[tuple[str, str], ...] = (("brushes.tips_kernels", "tip_sdf"),)
#: Records of the command's strokes replayed to compile the kernels (the demo's first two strokes).
WARM_UP_RECORDS = 160
#: Seconds between refreshes of the elapsed time while one kernel compiles.
REFRESH_S = 0.5


def kernels_cold(sentinels: tuple[tuple[str, str], ...] = SENTINELS) -> bool:
    """Whether numba's cache holds no code for one of ``sentinels`` (for the kernels' current
    sources). A kernel that is no cached numba dispatcher (``NUMBA_DISABLE_JIT``, caching off)
    counts as warm: there is nothing to announce."""
    for module, name in sentinels:
        try:
            dispatcher = getattr(importlib.import_module(module), name)
            # numba's own reading of the index: empty when missing, stale or of another version
            index = dispatcher._cache._cache_file._load_index()
        except Exception:  # not a caching dispatcher (or another numba): nothing to warm
            continue
        if not index:
            return True
    return False


def is_terminal(stream: TextIO) -> bool:
    """Whether ``stream`` is an open terminal."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or closed
        return False


class CompileProgress:
    """Counts the kernels numba compiles while entered (its ``numba:compile`` events, numba's
    own helpers left out) and shows the count and elapsed time on ``stream`` when it is a
    terminal; quiet otherwise. Attributes after exit: ``kernels`` (count), ``seconds``."""

    def __init__(self, stream: TextIO | None = None, message: str = MESSAGE):
        self.stream = stream if stream is not None else sys.stderr
        self.message = message
        self.kernels = 0
        self.seconds = 0.0
        self._bar: Any = None
        self._stop = threading.Event()
        self._ticker: threading.Thread | None = None
        self._listener: Any = None
        self._start = 0.0

    def __enter__(self) -> CompileProgress:
        from numba.core import event as numba_event
        from tqdm import tqdm

        self._bar = tqdm(
            desc=self.message,
            file=self.stream,
            disable=None,
            bar_format="{desc}: {n} kernels, {elapsed}",
            leave=True,
        )
        progress = self

        class Listener(numba_event.Listener):
            def on_start(self, event: numba_event.Event) -> None:
                pass

            def on_end(self, event: numba_event.Event) -> None:
                progress._compiled(event.data["dispatcher"])

        self._listener = Listener()
        self._start = time.perf_counter()
        numba_event.register("numba:compile", self._listener)
        if not self._bar.disable:
            self._ticker = threading.Thread(target=self._tick, name="compile-progress", daemon=True)
            self._ticker.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        from numba.core import event as numba_event

        numba_event.unregister("numba:compile", self._listener)
        self._stop.set()
        if self._ticker is not None:
            self._ticker.join()
        self.seconds = time.perf_counter() - self._start
        self._bar.close()

    def _compiled(self, dispatcher: Any) -> None:
        """One kernel compiled (on any thread)."""
        module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
        if module.split(".")[0] != "numba":
            self.kernels += 1
            self._bar.update(1)

    def _tick(self) -> None:
        while not self._stop.wait(REFRESH_S):
            self._bar.refresh()


def warm_up(
    strokes: StrokeFile,
    scene: PaintScene | None = None,
    fidelity: str | None = None,
    device: str | None = None,
    *,
    stream: TextIO | None = None,
    records: int = WARM_UP_RECORDS,
) -> bool:
    """On a cold cache (:func:`kernels_cold`), compile the kernels a replay of ``strokes`` needs
    by replaying its first ``records`` records (``scene``, ``fidelity``, ``device`` as for
    :func:`~paintapp.session.playback.replay`), with :class:`CompileProgress` on ``stream``
    (default stderr). Only when ``stream`` is a terminal: off one, the run compiles its kernels
    as it goes, as fast and as quietly. Returns whether it ran."""
    stream = stream if stream is not None else sys.stderr
    if not is_terminal(stream) or not kernels_cold():
        return False
    from paintapp.session.playback import replay

    head = dataclasses.replace(
        strokes, records=strokes.records[:records], lines=strokes.lines[:records]
    )
    with CompileProgress(stream):
        replay(head, scene, fidelity=fidelity, device=device)
    return True

"""The options of ``paintapp paint`` as one typed object, and the canvas the app starts with."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from paintapp.app.haptic_link import DeviceSpec
from paintapp.app.recovery import default_recovery_dir
from paintapp.app.settings import PaintSettings
from paintapp.canvas.model import Canvas
from paintapp.canvas.sizes import canvas_size
from paintapp.paint.paint_scene import PaintScene

#: A new canvas: pixels and metres (A4 portrait at 0.1 mm texels: 2100 x 2970).
DEFAULT_PIXELS, DEFAULT_SIZE_M = canvas_size()


@dataclass(frozen=True)
class PaintOptions:
    """How the app starts.

    Attributes:
        canvas_path: the canvas file to open (None: a new canvas, or a recovered one).
        device: the input device.
        scene: a painting scene given on the command line (None: the bundled one for the model).
        record: the stroke journal file (None: no journal).
        overwrite_record: allow replacing an existing journal file.
        recovery_dir: where autosaves go.
        autosave_s: autosave interval, s (0 turns autosave off).
        recover: what to do with an autosave left by a crash: ``ask``, ``yes`` or ``no``.
        settings: the initial paint settings.
        pixels, size_m: size of a new canvas.
        frame_ms: the render timer's period, ms.
        servo: where the 1 kHz servo loop runs with a device: "process" (its own process, real
            time where the OS grants it) or "thread" (a thread of the app).
        simulation: where the simulation worker runs: "thread" or "process"
            (:mod:`paintapp.app.sim_process`; with a device only beside a servo process).
    """

    canvas_path: Path | None = None
    device: DeviceSpec = field(default_factory=lambda: DeviceSpec("none"))
    scene: PaintScene | None = None
    record: Path | None = None
    overwrite_record: bool = False
    recovery_dir: Path = field(default_factory=default_recovery_dir)
    autosave_s: float = 60.0
    recover: str = "ask"
    settings: PaintSettings = field(default_factory=PaintSettings)
    pixels: tuple[int, int] = DEFAULT_PIXELS
    size_m: tuple[float, float] = DEFAULT_SIZE_M
    frame_ms: int = 16
    servo: str = "process"
    simulation: str = "thread"


def blank_canvas(like: Canvas | None = None, options: PaintOptions | None = None) -> Canvas:
    """A blank canvas the size of ``like`` (or of the options' new canvas)."""
    if like is not None:
        return Canvas(like.pixels, like.size_m, surface=like.surface)
    opts = options or PaintOptions()
    return Canvas(opts.pixels, opts.size_m, surface=opts.settings.surface)

"""What the controls ask the simulation worker to do, as commands it runs in its own thread.

Each function returns a command (a callable taking the worker: a :func:`functools.partial` of a
module-level function, so that it pickles and can cross to a simulation process); the GUI queues
it with :meth:`SimulationWorker.submit`. Commands end the current stroke first where they change the
brush or the canvas, so every stroke lands in the undo history whole. Each one is journalled:
palette dips, brush switches and cleans as the stroke format's events, the rest as markers.
A load taken up from the mixing slab is journalled as a ``clean`` and one ``load_pigment`` per
pigment in the brush (see :func:`slab_dab`).
"""

from __future__ import annotations

from functools import partial
from typing import TYPE_CHECKING

from brushes import PaintReservoir
from common.errors import InputError
from paintapp.app.history import UndoHistory, copy_canvas
from paintapp.app.settings import PaintSettings
from paintapp.canvas.model import Canvas
from paintapp.strokes.records import CleanBrush, LoadPigment, SwitchBrush

if TYPE_CHECKING:
    from paintapp.app.worker import Command, SimulationWorker


def load_pigment(pigment: str) -> Command:
    """Dip the brush in ``pigment``, filling the settings' share of its capacity."""
    return partial(_load_pigment, pigment)


def _load_pigment(pigment: str, w: SimulationWorker) -> None:
    if pigment not in w.pigments:
        raise InputError(f"no pigment {pigment!r} on the palette", key="pigment")
    volume = w.settings.load_fraction * w.session.preset.capacity_m3
    event = LoadPigment(w.session_time(), pigment, volume)
    w.session.handle(event)
    w.journal.write(event)
    w.message = f"loaded {pigment}"


def clean_brush() -> Command:
    """Wipe the brush."""
    return partial(_clean_brush)


def _clean_brush(w: SimulationWorker) -> None:
    event = CleanBrush(w.session_time())
    w.session.handle(event)
    w.journal.write(event)
    w.message = "brush cleaned"


def apply_settings(settings: PaintSettings) -> Command:
    """Paint on with new settings (brush, size, fluid model, viscosity, load)."""
    return partial(_apply_settings, settings)


def _apply_settings(settings: PaintSettings, w: SimulationWorker) -> None:
    old = w.settings
    rebuild = (
        old.brush != settings.brush
        or old.brush_scale != settings.brush_scale
        or old.fluid_model != settings.fluid_model
        or old.viscosity_pa_s != settings.viscosity_pa_s
    )
    w.settings = settings
    if not rebuild:
        return
    w.end_stroke()
    t = w.session_time()
    if old.brush != settings.brush:
        w.session.clean()  # a brush switch starts clean, as in a replay
        w.journal.write(SwitchBrush(t, settings.brush))
    if old.brush_scale != settings.brush_scale:
        w.journal.marker(t, f"brush_scale {settings.brush_scale:g}")
    if old.fluid_model != settings.fluid_model:
        w.journal.marker(t, f"fluid_model {settings.fluid_model}")
    if old.viscosity_pa_s != settings.viscosity_pa_s:
        w.journal.marker(t, f"viscosity_pa_s {settings.viscosity_pa_s}")
    w.rebuild()
    w.message = f"{settings.brush} x{settings.brush_scale:.2g}, {w.session.scene.name}"


def undo() -> Command:
    """Undo the latest stroke."""
    return partial(_history_step, "undo")


def redo() -> Command:
    """Redo the latest undone stroke."""
    return partial(_history_step, "redo")


def _history_step(which: str, w: SimulationWorker) -> None:
    """``which``: "undo" or "redo"."""
    w.end_stroke()
    step = w.history.undo if which == "undo" else w.history.redo
    box = step(w.live)
    if box is not None:
        w.journal.marker(w.session_time(), which)
    w.message = (
        ("undone" if which == "undo" else "redone") if box is not None else f"nothing to {which}"
    )


def replace_canvas(canvas: Canvas, note: str) -> Command:
    """Paint on ``canvas`` from now on (new, opened or recovered); the undo history restarts and
    the journal moves on to a new file."""
    return partial(_replace_canvas, canvas, note)


def _replace_canvas(canvas: Canvas, note: str, w: SimulationWorker) -> None:
    w.end_stroke()
    w.live = canvas
    canvas.take_dirty()
    canvas.take_wet_dirty()
    w.history = UndoHistory(canvas, w.history.max_steps, w.history.max_bytes)
    w.shared.replace(copy_canvas(canvas))
    w.rebuild()
    w.journal.start(w.header())
    w.message = note


# --- the mixing slab ---------------------------------------------------------------------------
def slab_put(pigment: str) -> Command:
    """Put a blob of ``pigment`` on the mixing slab (journalled as a marker)."""
    return partial(_slab_put, pigment)


def _slab_put(pigment: str, w: SimulationWorker) -> None:
    if pigment not in w.pigments:
        raise InputError(f"no pigment {pigment!r} on the palette", key="pigment")
    w.slab.put(pigment)
    w.publish_slab()
    w.journal.marker(w.session_time(), f"slab put {pigment}")
    w.message = f"{pigment} put on the slab"


def slab_dab(x_m: float, y_m: float) -> Command:
    """Dab the brush on the slab at (x_m, y_m): it leaves part of its load, stirs the paint
    there and picks some up (see :mod:`paintapp.app.slab`)."""
    return partial(_slab_dab, x_m, y_m)


def _slab_dab(x_m: float, y_m: float, w: SimulationWorker) -> None:
    _mix_into_brush(w, lambda brush: w.slab.dab(brush, x_m, y_m), "slab dab")


def slab_mix() -> Command:
    """Knife all the paint on the slab together and load the brush from it."""
    return partial(_slab_mix)


def _slab_mix(w: SimulationWorker) -> None:
    _mix_into_brush(w, w.slab.mix_all, "slab mix")


def slab_clear() -> Command:
    """Scrape the slab clean (journalled as a marker)."""
    return partial(_slab_clear)


def _slab_clear(w: SimulationWorker) -> None:
    w.slab.clear()
    w.publish_slab()
    w.journal.marker(w.session_time(), "slab clear")
    w.message = "slab cleared"


def _mix_into_brush(w: SimulationWorker, work, label: str) -> None:
    """Work the brush on the slab, then give the session's brush the resulting load.

    The stroke format knows only ``clean`` and ``load_pigment``, so the new load is applied (and
    journalled) as a ``clean`` followed by one ``load_pigment`` per pigment the brush now
    carries, preceded by a marker. A replay thus gives the brush exactly the same paint, and the
    session's paint bookkeeping stays balanced; the slab itself is not replayed.
    """
    w.end_stroke()
    old = w.session.reservoir
    brush = PaintReservoir(old.capacity_m3, old.volumes_m3)
    work(brush)
    w.publish_slab()
    t = w.session_time()
    w.journal.marker(t, label)
    events: list[CleanBrush | LoadPigment] = [CleanBrush(t)]
    events += [LoadPigment(t, name, v) for name, v in brush.volumes_m3.items() if v > 0.0]
    for event in events:
        w.session.handle(event)  # adds pigments new to the canvas, as a palette dip does
        w.journal.write(event)
    mix = ", ".join(f"{name} {100 * f:.0f}%" for name, f in brush.fractions().items() if f > 0)
    w.message = f"brush: {mix or 'dry'}"

"""``paintapp figures gallery [--out DIR]``: before/after crops of painted strokes at 2x zoom.

Three pieces, each painted twice through the whole painting path (the 3D or depth-averaged paint
grid, the canvas, the lit impasto render) and cropped at two screen pixels per texel:

- ``demo``: the bundled demo (``paintapp demo``), the impasto with the white and the probe
  dragged through it;
- ``impasto``: one thick cadmium red stroke of the flat brush;
- ``glaze``: a thin ultramarine glaze of the large round brush (the ``thin_glaze`` scene) across
  a dry cadmium yellow layer.

*After* is the paint as it is now. *Before* is the same strokes without the bristle texture
(brush presets stripped of ``[bristles]``), without the paint closing over the tip's footprint
at lift-off (``settle_on_lift = false``) and with each step's change laid at its end pose
(``sweep = false``): the paint transfer as it was before those three. (The
box spread that the tent kernel replaced earlier is no longer selectable, so it is not shown.)
Writes ``<piece>-before.png`` and ``<piece>-after.png`` into DIR (default ``docs/gallery``).
"""

from __future__ import annotations

import argparse
import dataclasses
import re
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from common.errors import InputError

#: Screen pixels per texel in the crops.
ZOOM = 2
PIECES = ("demo", "impasto", "glaze")
#: The demo's crop, canvas metres: (x0, y0, x1, y1).
DEMO_CROP_M = (0.055, 0.015, 0.115, 0.045)
_BRISTLES = re.compile(r"^\[bristles\][^\[]*", re.MULTILINE)


def register(figs: argparse._SubParsersAction) -> None:
    p = figs.add_parser(
        "gallery",
        help="before/after crops (2x) of the demo, a thick impasto and a glazing stroke",
        description=__doc__.split("\n\n", 1)[1],
    )
    p.add_argument(
        "--out", type=Path, default=Path("docs/gallery"), metavar="DIR", help="output folder"
    )
    p.add_argument(
        "--only", choices=PIECES, action="append", help="paint only this piece (repeatable)"
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from paintapp.output_paths import prepare_outputs

    out: Path = args.out
    pieces = list(dict.fromkeys(args.only or PIECES))
    prepare_outputs(
        [("--out", out / f"{p}-{when}.png") for p in pieces for when in ("before", "after")],
        [("--out", out)],
    )
    for piece in pieces:
        for when in ("before", "after"):
            picture = paint_piece(piece, before=when == "before")
            path = out / f"{piece}-{when}.png"
            write_zoomed(path, picture)
            print(f"wrote {path} ({picture.shape[1] * ZOOM} x {picture.shape[0] * ZOOM} px)")
    return 0


def paint_piece(piece: str, *, before: bool) -> np.ndarray:
    """The lit picture (linear RGBA, row 0 = bottom) of ``piece``'s crop, before or after."""
    painters: dict[str, Callable[[bool], np.ndarray]] = {
        "demo": _demo,
        "impasto": _impasto,
        "glaze": _glaze,
    }
    if piece not in painters:
        raise InputError(f"expected one of {', '.join(PIECES)}, got {piece!r}", key="--only")
    return painters[piece](before)


def write_zoomed(path: Path, rgba: np.ndarray) -> None:
    """Write ``rgba`` (row 0 = bottom) as an sRGB PNG, each texel ``ZOOM`` x ``ZOOM`` pixels."""
    from paintapp.canvas.preview import write_preview_png

    write_preview_png(path, np.repeat(np.repeat(rgba, ZOOM, axis=0), ZOOM, axis=1))


def stripped_brushes(folder: Path) -> Path:
    """Copies of the bundled brush presets without their ``[bristles]`` tables, in ``folder``."""
    from paintapp.resources import asset_path

    for path in sorted(asset_path("brushes").glob("*.toml")):
        text = _BRISTLES.sub("", path.read_text(encoding="utf-8"))
        (folder / path.name).write_text(text, encoding="utf-8")
    return folder


def _scene(name: str, before: bool):
    from paintapp.paint.paint_scene import load_paint_scene

    scene = load_paint_scene(name)
    return dataclasses.replace(scene, settle_on_lift=False, sweep=False) if before else scene


def _brush_dir(before: bool, folder: Path) -> Path | None:
    return stripped_brushes(folder) if before else None


def _picture(canvas) -> np.ndarray:
    from paintapp.session.outputs import canvas_picture

    return canvas_picture(canvas, lit=True)


def _crop(canvas, rgba: np.ndarray, box_m: tuple[float, float, float, float]) -> np.ndarray:
    box = canvas.texel_box_m(*box_m)
    assert box is not None
    x0, y0, x1, y1 = box
    return rgba[y0:y1, x0:x1]


def _demo(before: bool) -> np.ndarray:
    from paintapp.resources import asset_path
    from paintapp.session.playback import replay
    from paintapp.strokes.files import read_strokes

    strokes = read_strokes(asset_path("strokes", "demo.jsonl"))
    with tempfile.TemporaryDirectory() as tmp:
        result = replay(
            strokes,
            _scene(strokes.header.scene or "default", before),
            brush_dir=_brush_dir(before, Path(tmp)),
            device="tablet",
        )
    return _crop(result.canvas, _picture(result.canvas), DEMO_CROP_M)


def _session(canvas, brush: str, scene_name: str, before: bool, folder: Path):
    from paintapp.session.painting import PaintingSession

    return PaintingSession(
        canvas, brush, _scene(scene_name, before), brush_dir=_brush_dir(before, folder)
    )


def _stroke(session, start_m, end_m, duration_s: float, pressure: float, t0: float = 0.0):
    """A straight stroke: pressure up over 0.12 s, held, down again, 60 samples a second."""
    from brushes import StylusSample

    n = round(duration_s * 60) + 1
    for i in range(n):
        s = i / (n - 1)
        t = s * duration_s
        ramp = min(t, duration_s - t) / 0.12
        p = 0.0 if i in (0, n - 1) else pressure * np.sin(0.5 * np.pi * min(ramp, 1.0))
        x = start_m[0] + s * (end_m[0] - start_m[0])
        y = start_m[1] + s * (end_m[1] - start_m[1])
        session.sample(StylusSample(t0 + t, np.array([x, y, 0.0]), float(p)))


def _impasto(before: bool) -> np.ndarray:
    from paintapp.canvas.model import Canvas

    canvas = Canvas((200, 120), (0.05, 0.03), ("cadmium_red",))
    with tempfile.TemporaryDirectory() as tmp:
        session = _session(canvas, "flat_wide", "default", before, Path(tmp))
        session.load_pigment("cadmium_red", 1.2e-7)
        _stroke(session, (0.008, 0.015), (0.042, 0.016), 1.2, 0.95)
    return _picture(canvas)


def _glaze(before: bool) -> np.ndarray:
    from paintapp.canvas.model import Canvas

    names = ("cadmium_yellow", "ultramarine_blue")
    layer = np.zeros((2, 120, 200), np.float32)
    layer[0, 20:100, 60:140] = 1.5e-4  # a dry yellow square
    canvas = Canvas((200, 120), (0.05, 0.03), names, layer, np.zeros((120, 200), np.float32))
    with tempfile.TemporaryDirectory() as tmp:
        session = _session(canvas, "round_large", "thin_glaze", before, Path(tmp))
        session.load_pigment("ultramarine_blue", 2.5e-8)
        _stroke(session, (0.006, 0.014), (0.044, 0.016), 1.2, 0.6)
    return _picture(canvas)

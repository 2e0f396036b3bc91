"""Golden replays: short recorded strokes with the canvas and force trace they must produce.

Regenerate after an intended change of the painting physics::

    python -m tests.support.goldens tests/paintapp/session/golden

replays every ``*.jsonl`` in the folder and writes ``<name>.exr`` (32-bit, unlit colour: no
OpenGL needed) and ``<name>.forces.csv`` beside it. ``--strokes`` first rewrites the golden stroke
files themselves from :func:`golden_recordings`. Tests replay the strokes again and compare with
tolerances (:func:`compare_canvas`, :func:`compare_forces`), not bit for bit, so that harmless
round-off differences between machines pass while a change of behaviour does not.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from paintapp.canvas.model import Canvas
from paintapp.session.outputs import write_canvas_outputs, write_forces_csv
from paintapp.session.playback import replay
from paintapp.strokes.files import (
    CanvasSpec,
    CleanBrush,
    LoadPigment,
    StrokeHeader,
    StrokeRecord,
    SwitchBrush,
    read_strokes,
)
from tests.support.demo_strokes import StrokeSpec, stroke_samples, write_recording


def _header(scene: str | None, pigments: tuple[str, ...]) -> StrokeHeader:
    return StrokeHeader(
        canvas=CanvasSpec((160, 160), (0.04, 0.04)),
        brush="round_small",
        pigments=pigments,
        scene=scene,
        device={"kind": "tablet", "name": "golden", "rate_hz": 60},
        seed=1,
    )


def golden_recordings() -> dict[str, tuple[StrokeHeader, list[StrokeRecord]]]:
    """The golden strokes by name: a 3D-grid stroke with a probe dragged through it, and two
    crossing strokes in the depth-averaged (thin glaze) scene."""
    blue, yellow = "ultramarine_blue", "cadmium_yellow"
    a: list[StrokeRecord] = [LoadPigment(0.0, blue, 1.5e-8)]
    a += stroke_samples(StrokeSpec((0.008, 0.019), (0.032, 0.022), 0.5, 0.8, (0.2, 0.0)), 0.0)
    a += [CleanBrush(0.6), SwitchBrush(0.6, "square_probe")]
    a += stroke_samples(StrokeSpec((0.019, 0.008), (0.021, 0.032), 0.5, 1.0), 0.6)
    b: list[StrokeRecord] = [LoadPigment(0.0, yellow, 1.5e-8)]
    b += stroke_samples(StrokeSpec((0.008, 0.02), (0.032, 0.02), 0.4, 0.8), 0.0)
    b += [CleanBrush(0.5), LoadPigment(0.5, blue, 1.5e-8)]
    b += stroke_samples(StrokeSpec((0.02, 0.008), (0.02, 0.032), 0.4, 0.8, (0.0, 0.2)), 0.5)
    return {
        "grid3d_drag": (_header(None, (blue,)), a),
        "glaze_cross": (_header("thin_glaze", (blue, yellow)), b),
    }


def regenerate(folder: Path, *, strokes: bool = False) -> list[Path]:
    """Write the golden outputs for every stroke file in ``folder``; returns the files written."""
    folder.mkdir(parents=True, exist_ok=True)
    if strokes:
        for name, (header, records) in golden_recordings().items():
            write_recording(folder / f"{name}.jsonl", header, records)
    written = []
    for path in sorted(folder.glob("*.jsonl")):
        result = replay(read_strokes(path))
        exr, csv = path.with_suffix(".exr"), path.with_suffix(".forces.csv")
        write_canvas_outputs(result.canvas, exr, lit=False, half=False)
        write_forces_csv(csv, result.forces)
        written += [exr, csv]
    return written


def compare_canvas(actual: Canvas, expected: Canvas, rel_tol: float = 0.05) -> list[str]:
    """Differences beyond tolerance (empty when they match): same size and pigments; each
    pigment's total volume within ``rel_tol``; every texel's paint within ``rel_tol`` of the
    thickest paint; wetness within ``rel_tol``."""
    if actual.pixels != expected.pixels or actual.pigment_names != expected.pigment_names:
        return [f"canvas {actual.pixels} {actual.pigment_names} != {expected.pixels} "
                f"{expected.pigment_names}"]  # fmt: skip
    problems = []
    got = actual.paint_m.astype(np.float64)
    want = expected.paint_m.astype(np.float64)
    scale = max(float(want.sum(axis=0).max()), 1e-12)
    for p, name in enumerate(expected.pigment_names):
        a, b = got[p].sum(), want[p].sum()
        if abs(a - b) > rel_tol * max(abs(b), 1e-12 * got.size):
            problems.append(f"{name}: total {a:.6g} != {b:.6g}")
    worst = float(np.abs(got - want).max())
    if worst > rel_tol * scale:
        problems.append(f"paint differs by up to {worst:.3g} m (tolerance {rel_tol * scale:.3g})")
    wet = float(np.abs(actual.wetness - expected.wetness).max())
    if wet > rel_tol:
        problems.append(f"wetness differs by up to {wet:.3g}")
    return problems


def compare_forces(actual: np.ndarray, expected: np.ndarray, rel_tol: float = 0.05) -> list[str]:
    """Differences beyond tolerance between force traces (ticks, 7): same ticks and times, and
    force and torque within ``rel_tol`` of the largest expected magnitude."""
    if actual.shape != expected.shape:
        return [f"trace shape {actual.shape} != {expected.shape}"]
    problems = []
    if not np.allclose(actual[:, 0], expected[:, 0], atol=1e-9):
        problems.append("tick times differ")
    for cols, what in ((slice(1, 4), "force"), (slice(4, 7), "torque")):
        scale = max(float(np.linalg.norm(expected[:, cols], axis=1).max()), 1e-12)
        worst = float(np.linalg.norm(actual[:, cols] - expected[:, cols], axis=1).max())
        if worst > rel_tol * scale:
            problems.append(
                f"{what} differs by up to {worst:.3g} (tolerance {rel_tol * scale:.3g})"
            )
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Regenerate the golden replay outputs.")
    parser.add_argument("folder", type=Path, help="folder of golden stroke files")
    parser.add_argument("--strokes", action="store_true", help="rewrite the stroke files first")
    args = parser.parse_args(argv)
    for path in regenerate(args.folder, strokes=args.strokes):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

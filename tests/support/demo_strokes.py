"""Synthetic stroke recordings: the bundled demo (``assets/strokes/demo.jsonl``) and test strokes.

``python -m tests.support.demo_strokes OUT.jsonl`` writes the demo recording: five brushes' worth of
painting on a 12 cm canvas -- a wavy ultramarine stroke; a cadmium yellow stroke across it (they
mix to green where they meet); a thick cadmium red impasto stroke laid twice with a flat brush; a
titanium white stroke with a small round brush dragged through the wet paint; and a clean square
probe dragged through the wet red impasto (the paper's probe: a pure force trace).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from brushes import StylusSample
from paintapp.strokes.files import (
    CanvasSpec,
    CleanBrush,
    LoadPigment,
    Marker,
    StrokeHeader,
    StrokeRecord,
    SwitchBrush,
)
from paintapp.strokes.recorder import StrokeRecorder

DEMO_PIGMENTS = ("ultramarine_blue", "cadmium_yellow", "cadmium_red", "titanium_white")


@dataclass(frozen=True)
class StrokeSpec:
    """A straight (optionally wavy) stroke from ``start_m`` to ``end_m`` (canvas metres).

    Pressure rises from 0 over ``ramp_s``, holds ``pressure`` and falls back to 0 at the end; the
    first and last samples have zero pressure (brush in the air). ``wave_m`` is the amplitude of
    one sine wave across the stroke.
    """

    start_m: tuple[float, float]
    end_m: tuple[float, float]
    duration_s: float
    pressure: float = 0.8
    tilt_rad: tuple[float, float] = (0.0, 0.0)
    twist_rad: float = 0.0
    wave_m: float = 0.0
    ramp_s: float = 0.12
    rate_hz: float = 60.0


def stroke_samples(spec: StrokeSpec, t0_s: float) -> list[StylusSample]:
    """The stylus samples of ``spec`` starting at ``t0_s``."""
    n = max(2, round(spec.duration_s * spec.rate_hz) + 1)
    a, b = np.array(spec.start_m), np.array(spec.end_m)
    along = b - a
    normal = np.array([-along[1], along[0]]) / max(float(np.linalg.norm(along)), 1e-12)
    out = []
    for i in range(n):
        s = i / (n - 1)
        t = s * spec.duration_s
        ramp = min(t, spec.duration_s - t) / spec.ramp_s
        pressure = (
            0.0 if i in (0, n - 1) else spec.pressure * math.sin(0.5 * math.pi * min(ramp, 1.0))
        )
        xy = a + s * along + spec.wave_m * math.sin(2.0 * math.pi * s) * normal
        out.append(
            StylusSample(
                t_s=round(t0_s + t, 6),
                position_m=np.array([round(xy[0], 7), round(xy[1], 7), 0.0]),
                pressure=round(pressure, 5),
                tilt_rad=np.array(spec.tilt_rad),
                twist_rad=spec.twist_rad,
                buttons=1,
            )
        )
    return out


def _stroke(records: list[StrokeRecord], spec: StrokeSpec, label: str, gap_s: float = 0.3) -> None:
    t0 = round(records[-1].t_s + gap_s, 6) if records else 0.0
    records.append(Marker(t0, label))
    records.extend(stroke_samples(spec, t0))


def demo_recording() -> tuple[StrokeHeader, list[StrokeRecord]]:
    """The demo's header and records (see the module docstring)."""
    header = StrokeHeader(
        canvas=CanvasSpec((480, 480), (0.12, 0.12)),
        brush="round_large",
        pigments=DEMO_PIGMENTS,
        scene=None,
        device={"kind": "tablet", "name": "synthetic demo", "rate_hz": 60},
        seed=7,
    )
    r: list[StrokeRecord] = [LoadPigment(0.0, "ultramarine_blue", 1.2e-7)]
    _stroke(
        r,
        StrokeSpec((0.02, 0.085), (0.10, 0.085), 1.2, 0.7, (0.25, 0.0), wave_m=0.008),
        "blue wave",
    )
    t = round(r[-1].t_s + 0.1, 6)
    r += [CleanBrush(t), LoadPigment(t, "cadmium_yellow", 1.2e-7)]
    _stroke(
        r, StrokeSpec((0.03, 0.105), (0.09, 0.06), 1.2, 0.75, (0.2, -0.2)), "yellow across blue"
    )
    t = round(r[-1].t_s + 0.1, 6)
    r += [SwitchBrush(t, "flat_wide"), LoadPigment(t, "cadmium_red", 1.2e-7)]
    impasto = StrokeSpec((0.025, 0.03), (0.095, 0.035), 1.4, 0.95, (0.0, -0.3), twist_rad=0.0)
    _stroke(r, impasto, "impasto, first pass")
    t = round(r[-1].t_s + 0.1, 6)
    r.append(LoadPigment(t, "cadmium_red", 1.2e-7))
    _stroke(
        r, StrokeSpec(impasto.end_m, impasto.start_m, 1.4, 0.95, (0.0, 0.3)), "impasto, second pass"
    )
    t = round(r[-1].t_s + 0.1, 6)
    r += [SwitchBrush(t, "round_small"), LoadPigment(t, "titanium_white", 2.0e-8)]
    _stroke(
        r,
        StrokeSpec((0.062, 0.012), (0.055, 0.11), 1.4, 0.9, (0.0, -0.3)),
        "white through wet paint",
    )
    t = round(r[-1].t_s + 0.1, 6)
    r.append(SwitchBrush(t, "square_probe"))
    _stroke(
        r, StrokeSpec((0.015, 0.026), (0.105, 0.038), 1.2, 1.0), "clean probe dragged through red"
    )
    return header, r


def write_recording(
    path: str | Path, header: StrokeHeader, records: Sequence[StrokeRecord]
) -> None:
    """Write a stroke file (overwriting ``path``)."""
    with StrokeRecorder(path, header, overwrite=True) as rec:
        for record in records:
            rec.write(record)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Write the demo stroke recording.")
    parser.add_argument("out", type=Path, help="output .jsonl (e.g. assets/strokes/demo.jsonl)")
    args = parser.parse_args(argv)
    header, records = demo_recording()
    write_recording(args.out, header, records)
    print(f"wrote {args.out}: {len(records)} records")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""How strongly each stroke of a replay carries its own step: the teeth along the stroke's path.

A tip that jumps from one pose to the next, instead of sweeping, can print one tooth per step
along a fast stroke. Per stroke (the in-contact samples between two markers of the stroke file,
its first and last two steps left out), the paint height is read (on the cubic spline through the
texels) at :data:`PHASES` points along each step, on the centre line and 2 texels to either side;
the *tooth depth* is the peak-to-peak of the mean over the steps at each phase, over the mean
height, the largest of the three lines. Its *floor*, what the path's own relief gives by chance,
is the same with each step's phases rolled at random (the median of :data:`DEALS` deals).

Anything else that recurs every few steps (a grid re-centring, a beat between a sub-step's travel
and the cell) prints its own period: :func:`period_scan` folds the same lines at periods
:data:`SCAN_RATIO` apart from :data:`SCAN_MIN_TEXELS` texels to :data:`SCAN_STEPS` steps, and at
the step's sub-multiples :data:`SUB_STEPS` exactly (the scan is too coarse for them on a long
stroke), with the same floor; the period standing highest over its floor is the stroke's worst.

A fast tip's sides can carry its steps where its middle does not (the ridges it pushes up at
each step): :func:`across_width` folds lines across the brush's whole width at the step.

``python -m paintapp.session.comb DIR [STROKES]`` prints all three for every stroke of ``STROKES``
(default: ``DIR/strokes.jsonl``, else the bundled demo strokes) painted in ``DIR/canvas.exr``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.ndimage import map_coordinates, spline_filter

from brushes import StylusSample
from paintapp.strokes.files import StrokeFile
from paintapp.strokes.records import Marker, SwitchBrush

#: Points read along each step; steps left out at each end of a stroke; random deals of the floor.
PHASES = 20
END_STEPS = 2
DEALS = 50
#: Lateral offsets of the lines read, texels.
OFFSETS_TEXELS = (-2.0, 0.0, 2.0)
#: Lines read across a stroke's width by :func:`across_width`: this many over the width, and the
#: least mean height a line must hold, as a share of the fullest line's.
ACROSS_LINES = 16
ACROSS_MIN_SHARE = 0.1
#: The period scan: shortest period (texels), longest (steps), ratio between scanned periods.
SCAN_MIN_TEXELS = 3.0
SCAN_STEPS = 4.0
SCAN_RATIO = 1.02
#: The step is also folded at step / n for each of these n (sub-steps of a sample).
SUB_STEPS = (2, 3, 4)
#: Texels of canvas kept round the lines read for the cubic spline's prefilter.
SPLINE_MARGIN_TEXELS = 12

#: Reads the paint height at texel index coordinates (..., 2).
Reader = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class StrokePath:
    """One stroke's in-contact path: its label (the marker before it), positions (n, 2) m, and
    the brush preset it was painted with (the one in use at its first sample)."""

    label: str
    points_m: np.ndarray
    brush: str = ""


def stroke_paths(strokes: StrokeFile) -> list[StrokePath]:
    """The in-contact paths of ``strokes``, one per marker (at least two samples each)."""
    paths: list[StrokePath] = []
    label, brush = "stroke 1", strokes.header.brush
    painted_with = brush
    points: list[np.ndarray] = []
    for record in strokes.records:
        if isinstance(record, Marker):
            if len(points) >= 2:
                paths.append(StrokePath(label, np.array(points), painted_with))
            label, points = record.label, []
        elif isinstance(record, SwitchBrush):
            brush = record.preset
        elif isinstance(record, StylusSample) and record.pressure > 0.0:
            if not points:
                painted_with = brush
            points.append(np.asarray(record.position_m, dtype=float)[:2])
    if len(points) >= 2:
        paths.append(StrokePath(label, np.array(points), painted_with))
    return paths


def tooth_depth(
    height_m: np.ndarray, texel_m: float, points_m: np.ndarray, seed: int = 0
) -> tuple[float, float]:
    """(tooth depth, floor) of the path ``points_m`` (n, 2) m on the paint height ``height_m``
    (H, W) of square ``texel_m`` texels (module docstring); NaN for a path too short or bare."""
    chunks = _step_chunks(points_m, texel_m)
    if chunks is None:
        return float("nan"), float("nan")
    points, normal = chunks
    read = _spline_reader(height_m, points)
    return _fold(read, points, normal, seed)


def _step_chunks(points_m: np.ndarray, texel_m: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The points read along each step of the path ``points_m`` (n, 2) m (its first and last
    :data:`END_STEPS` left out), (steps, PHASES, 2) texel index coordinates, and the unit normal
    to the path at each (same shape); None for a path of fewer than four steps."""
    p = np.asarray(points_m, dtype=float) / texel_m - 0.5  # texel index coordinates
    a, b = p[END_STEPS : -END_STEPS - 1], p[END_STEPS + 1 : -END_STEPS]
    along = b - a
    length = np.hypot(along[:, 0], along[:, 1])
    keep = length > 1e-6
    if keep.sum() < 4:
        return None
    a, along, length = a[keep], along[keep], length[keep]
    normal = np.stack([-along[:, 1], along[:, 0]], axis=1) / length[:, None]
    f = (np.arange(PHASES) + 0.5) / PHASES
    points = a[:, None, :] + f[None, :, None] * along[:, None, :]
    return points, np.broadcast_to(normal[:, None, :], points.shape)


def _fold(read: Reader, points: np.ndarray, normal: np.ndarray, seed: int) -> tuple[float, float]:
    """(depth, floor) of the chunks ``points`` (chunks, PHASES, 2) texel index coordinates, read
    by ``read`` on lines offset along ``normal`` (same shape) by :data:`OFFSETS_TEXELS`: the
    largest depth and the largest floor of the lines."""
    rng = np.random.default_rng(seed)
    folds = [_fold_line(read(points + off * normal), rng) for off in OFFSETS_TEXELS]
    found = [f for f in folds if f is not None]
    if not found or max(d for d, _ in found) == 0.0:
        return float("nan"), float("nan")
    return max(d for d, _ in found), max(f for _, f in found)


def _fold_line(lines: np.ndarray, rng: np.random.Generator) -> tuple[float, float] | None:
    """(depth, floor) of one line's heights read at each step's phases (steps, PHASES); None
    where the line holds no paint."""
    mean = float(lines.mean())
    if mean <= 0.0:
        return None
    depth = float(np.ptp(lines.mean(axis=0))) / mean
    rolled = []
    for _ in range(DEALS):
        shift = rng.integers(0, PHASES, size=len(lines))
        idx = (np.arange(PHASES)[None, :] + shift[:, None]) % PHASES
        rolled.append(float(np.ptp(np.take_along_axis(lines, idx, 1).mean(axis=0))) / mean)
    return depth, float(np.median(rolled))


@dataclass(frozen=True)
class AcrossDepth:
    """The tooth depth and floor of the line across a stroke that stands highest over its
    floor, and that line's offset from the path (texels, to its left)."""

    offset_texels: float
    depth: float
    floor: float


def across_width(
    height_m: np.ndarray, texel_m: float, points_m: np.ndarray, width_texels: float
) -> AcrossDepth | None:
    """The step's teeth read across a stroke of ``width_texels``: :func:`tooth_depth` on lines
    parallel to the path every :data:`ACROSS_LINES`-th of the width (at least 2 texels apart),
    from one edge of the width to the other, lines holding under :data:`ACROSS_MIN_SHARE` of the
    fullest line's mean height left out; the line whose depth stands highest over its own floor,
    or None for a path too short or bare. Where the centre lines read nothing, a stroke's sides
    can still carry its steps (the ridges a fast tip pushes up at each step)."""
    chunks = _step_chunks(points_m, texel_m)
    if chunks is None:
        return None
    points, normal = chunks
    spacing = max(2.0, width_texels / ACROSS_LINES)
    offsets = np.arange(-0.5 * width_texels, 0.5 * width_texels + 1e-9, spacing)
    read = _spline_reader(height_m, points, float(np.abs(offsets).max()))
    rng = np.random.default_rng(0)
    lines = [read(points + off * normal) for off in offsets]
    fullest = max(float(line.mean()) for line in lines)
    found: list[AcrossDepth] = []
    for off, line in zip(offsets, lines, strict=True):
        fold = _fold_line(line, rng) if line.mean() >= ACROSS_MIN_SHARE * fullest else None
        if fold is not None:
            found.append(AcrossDepth(float(off), *fold))
    return max(found, key=lambda d: d.depth - d.floor) if found else None


def _spline_reader(height_m: np.ndarray, points: np.ndarray, reach: float | None = None) -> Reader:
    """A reader of ``height_m`` at texel index coordinates (..., 2) near ``points``: the cubic
    spline through the texels (of a crop round the points wide enough that the spline's
    prefilter does not feel its edges). Not bilinear: read bilinearly, a streak along a
    diagonal stroke, even, sampled by the texels, swells and thins every time the line read
    crosses a texel row or column, a comb that the paint does not have (along a 3-4-5 diagonal,
    teeth every 2.5 and 3.3 texels). ``reach``: the farthest the lines read lie from ``points``
    (texels; default, :data:`OFFSETS_TEXELS`'s)."""
    if reach is None:
        reach = max(abs(o) for o in OFFSETS_TEXELS)
    pad = reach + SPLINE_MARGIN_TEXELS
    flat = points.reshape(-1, 2)
    h, w = height_m.shape
    x0 = int(np.clip(np.floor(flat[:, 0].min() - pad), 0, w))
    x1 = int(np.clip(np.ceil(flat[:, 0].max() + pad) + 1, x0, w))
    y0 = int(np.clip(np.floor(flat[:, 1].min() - pad), 0, h))
    y1 = int(np.clip(np.ceil(flat[:, 1].max() + pad) + 1, y0, h))
    coeffs = spline_filter(np.asarray(height_m[y0:y1, x0:x1], dtype=float), 3, mode="nearest")

    def read(xy: np.ndarray) -> np.ndarray:
        at = [xy[..., 1] - y0, xy[..., 0] - x0]
        return map_coordinates(coeffs, at, order=3, mode="nearest", prefilter=False)

    return read


@dataclass(frozen=True)
class PeriodDepth:
    """The tooth depth and floor of a path folded at ``period_texels``."""

    period_texels: float
    depth: float
    floor: float


def period_depths(
    height_m: np.ndarray, texel_m: float, points_m: np.ndarray, periods_texels: np.ndarray
) -> list[PeriodDepth]:
    """The tooth depth and floor of the path ``points_m`` (n, 2) m folded at each of
    ``periods_texels`` along its arc length (module docstring); periods with fewer than four
    whole chunks on the path (or a bare path) are left out."""
    p = np.asarray(points_m, dtype=float) / texel_m - 0.5
    p = p[END_STEPS : len(p) - END_STEPS]
    if len(p) < 2:
        return []
    seg = np.diff(p, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    keep = length > 1e-6
    p = np.concatenate([p[:1], p[1:][keep]])
    seg, length = seg[keep], length[keep]
    arc = np.concatenate([[0.0], np.cumsum(length)])
    if len(seg) == 0:
        return []
    normal = np.stack([-seg[:, 1], seg[:, 0]], axis=1) / length[:, None]
    read = _spline_reader(height_m, p)
    out: list[PeriodDepth] = []
    for period in np.asarray(periods_texels, dtype=float):
        chunks = int(arc[-1] // period)
        if chunks < 4:
            continue
        s = (np.arange(chunks * PHASES) + 0.5) * (period / PHASES)
        xy = np.stack([np.interp(s, arc, p[:, 0]), np.interp(s, arc, p[:, 1])], axis=1)
        which = np.clip(np.searchsorted(arc, s, side="right") - 1, 0, len(seg) - 1)
        shape = (chunks, PHASES, 2)
        depth, floor = _fold(read, xy.reshape(shape), normal[which].reshape(shape), 0)
        if np.isfinite(depth):
            out.append(PeriodDepth(float(period), depth, floor))
    return out


def scan_periods(step_texels: float) -> np.ndarray:
    """The periods (texels) :func:`period_scan` folds at for a stroke of ``step_texels`` steps."""
    top = max(SCAN_STEPS * step_texels, SCAN_MIN_TEXELS)
    count = int(np.log(top / SCAN_MIN_TEXELS) / np.log(SCAN_RATIO)) + 1
    return SCAN_MIN_TEXELS * SCAN_RATIO ** np.arange(count)


def period_scan(height_m: np.ndarray, texel_m: float, points_m: np.ndarray) -> PeriodDepth | None:
    """The period at which the path ``points_m`` (n, 2) m is most strongly combed: of
    :func:`scan_periods` of its median step, the one with the largest depth over floor; None for
    a path too short or bare."""
    pts = np.asarray(points_m, dtype=float)
    step = float(np.median(np.hypot(*np.diff(pts, axis=0).T))) / texel_m if len(pts) > 1 else 0.0
    subs = [step / n for n in SUB_STEPS if step / n >= SCAN_MIN_TEXELS]
    found = period_depths(height_m, texel_m, pts, np.concatenate([scan_periods(step), subs]))
    found = [d for d in found if d.floor > 0.0]
    if not found:
        return None
    best = max(found, key=lambda d: d.depth / d.floor)
    # the scan's periods are SCAN_RATIO apart: refine between the best one's neighbours
    near = best.period_texels * SCAN_RATIO ** np.linspace(-1.0, 1.0, 21)
    found = [d for d in period_depths(height_m, texel_m, pts, near) if d.floor > 0.0]
    return max([best, *found], key=lambda d: d.depth / d.floor)


def main(argv: list[str]) -> int:
    """Print the tooth depth of each stroke of a stroke file painted in a demo folder."""
    from common.errors import InputError
    from paintapp.canvas.exr import read_canvas_exr
    from paintapp.resources import asset_path
    from paintapp.strokes.files import read_strokes

    folder = Path(argv[0]) if argv else Path("paintapp-demo")
    painted = folder / "strokes.jsonl"  # the strokes as the demo placed them on its canvas
    default = painted if painted.is_file() else asset_path("strokes", "demo.jsonl")
    source = Path(argv[1]) if len(argv) > 1 else default
    try:
        canvas = read_canvas_exr(folder / "canvas.exr")
        strokes = read_strokes(source)
    except (OSError, InputError) as err:
        print(
            f"comb: error: {err} (expected a paintapp demo folder and its strokes)", file=sys.stderr
        )
        return 2
    texel = canvas.texel_size_m[0]
    height = canvas.height_m.astype(np.float64)
    print(
        f"{'stroke':32s} step (texels)  tooth depth  floor  worst period  depth  floor"
        "  across: depth  floor  at"
    )
    for path in stroke_paths(strokes):
        seg = np.hypot(*np.diff(path.points_m, axis=0).T) / texel
        depth, floor = tooth_depth(height, texel, path.points_m)
        worst = period_scan(height, texel, path.points_m)
        scan = (
            f"{worst.period_texels:12.1f}  {worst.depth:5.3f}  {worst.floor:5.3f}"
            if worst
            else f"{'-':>24s}"
        )
        width = brush_width_texels(path.brush, texel)
        side = None if width is None else across_width(height, texel, path.points_m, width)
        across = (
            f"{side.depth:15.3f}  {side.floor:5.3f} {side.offset_texels:+4.0f}"
            if side
            else f"{'-':>15s}"
        )
        print(
            f"{path.label[:32]:32s} {np.median(seg):13.2f}  {depth:11.3f}  {floor:5.3f}  {scan}"
            f"{across}"
        )
    print("tooth depth: peak-to-peak of the paint height over a step's phase (mean over the")
    print("steps), over the mean height; floor: the same with each step's phase rolled at random;")
    print(
        f"worst period: of periods {SCAN_MIN_TEXELS:g} texels to {SCAN_STEPS:g} steps and the step's"
    )
    print("halves, thirds and quarters, the one whose depth stands highest over its floor;")
    print("across: the step's tooth depth on lines across the brush's width, the line standing")
    print("highest over its floor, and its offset from the path (texels, to its left)")
    return 0


def brush_width_texels(name: str, texel_m: float) -> float | None:
    """The widest extent of the bundled brush preset ``name`` at full splay, in texels of
    ``texel_m``; None for a preset that is not bundled."""
    from brushes import load_preset_named
    from common.errors import InputError
    from paintapp.paint.paint_model import brush_width_m
    from paintapp.resources import asset_path

    try:
        preset = load_preset_named(name, asset_path("brushes"))
    except (InputError, OSError, ValueError, KeyError):
        return None
    return brush_width_m(preset) / texel_m


if __name__ == "__main__":
    from common.pipes import run_tool

    run_tool(main, sys.argv[1:])

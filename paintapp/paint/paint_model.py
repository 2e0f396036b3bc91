"""What every paint model shares: following the tip, the canvas window, split steps, the result.

A paint model (3D grid, depth-averaged grid, or no fluid) is driven by tip poses
(:meth:`PaintModel.touch_down`, :meth:`PaintModel.step` in contact, :meth:`PaintModel.lift`).
A step reads the wet paint under the window from the canvas, lets the model move it (and trade
it with the brush), and writes the change back; the grid keeps only its velocity between steps.

Gaps longer than ``scene.max_step_s``, or with more travel than ``scene.max_travel_cells`` cells,
are split into equal sub-steps (the travel into at most ``scene.max_travel_substeps``) along the
straight line between the poses, so the brush touches every column along its path and its
deposits add up to an even band (:mod:`paintapp.paint.trail` says what a fast tip leaves).

A model builds no more than is read: :class:`ForceNeeds` says whether anyone reads the force
(without, the solver does no force work) and the torque (without, none is published); with
``scene.choose.used_pigments`` only the pigment channels in the window or in the brush go
through the grid (the others are zero and stay so); and a model may have fewer columns than
``scene.cells`` (``cells_xy`` below ``reference_cells``: the same cell size over a smaller
footprint, :mod:`paintapp.paint.fit`).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.ndimage import binary_dilation

from brushes import BrushPreset, PaintReservoir, Section, TipPose, voxelize
from common.tilt import yaw_angle
from common.timing import PhaseTimer
from paintapp.canvas.model import Canvas
from paintapp.paint.bristles import BristleTexture
from paintapp.paint.columns import (
    SWEEP_MIN_TEXELS,
    ColumnWindow,
    TexelWeights,
    cell_texels,
    square_texel_m,
)
from paintapp.paint.contact import contact_radius_m
from paintapp.paint.exchange import ExchangeReport, plough_weights
from paintapp.paint.paint_scene import PaintScene
from paintapp.paint.tooth import ToothTexture
from solver import Grid, SolverSettings

#: Lift-off: the paint round the tip's last footprint flows back into the hole it leaves, by
#: sweeps of a conservative neighbour exchange (each column trades this share of the difference
#: with each neighbour) over the footprint and this many cells around it, until every footprint
#: column holds at least this share of the region's mean paint (at most this many sweeps).
SETTLE_SHARE = 0.2
SETTLE_REACH_CELLS = 2
SETTLE_LEVEL = 0.5
SETTLE_MAX_SWEEPS = 64


def brush_width_m(preset: BrushPreset) -> float:
    """Widest lateral extent (m) of the preset's tip at full splay."""
    tip = preset.tip(preset.splay_for_depth(preset.pressure.depth_m))
    widths = []
    for axis in range(2):
        d = np.zeros(3)
        d[axis] = 1.0
        widths.append(tip.support(d) + tip.support(-d))
    return float(max(widths))


@dataclass(frozen=True)
class ForceNeeds:
    """What reads a paint model's output: the force (N) and the torque (N m) on the tip."""

    force: bool = True
    torque: bool = True

    def describe(self) -> str:
        """``force and torque``, ``force only`` or ``nothing``."""
        if not self.force:
            return "nothing"
        return "force and torque" if self.torque else "force only"


@dataclass(frozen=True)
class PaintStep:
    """The outcome of one :meth:`PaintModel.step`.

    Attributes:
        force_n: (3,) force of the paint on the brush tip, canvas frame, N.
        torque_nm: (3,) torque about the tip's apex, canvas frame, N m.
        solver_steps: fluid solver steps taken (0 without a fluid).
        transport_substeps: upwind sub-steps of the paint transport, summed.
        exchange: paint moved between brush and grid, summed over the sub-steps.
        step_ms: wall time of the step, ms.
        phase_ms: wall time by phase (``follow``: the window re-centred on the tip, with the
            fluid's state; ``read``: canvas to grid, ``solver``, ``exchange``, ``transport``,
            ``write``: grid to canvas), ms.
        channels: pigment channels carried through the grid (the most over the sub-steps).
        stokes_steps: solver steps taken as Stokes flow, without momentum advection
            (:meth:`PaintModel.step_settings`).
    """

    force_n: np.ndarray = field(default_factory=lambda: np.zeros(3))
    torque_nm: np.ndarray = field(default_factory=lambda: np.zeros(3))
    solver_steps: int = 0
    transport_substeps: int = 0
    exchange: ExchangeReport = field(default_factory=ExchangeReport)
    step_ms: float = 0.0
    phase_ms: dict[str, float] = field(default_factory=dict)
    channels: int = 0
    stokes_steps: int = 0


def add_reports(a: ExchangeReport, b: ExchangeReport) -> ExchangeReport:
    """Sum of two exchange reports."""
    return ExchangeReport(*(x + y for x, y in zip(vars(a).values(), vars(b).values(), strict=True)))


class PaintModel(ABC):
    """Base of the paint models (see the module docstring).

    Args:
        scene: the painting scene.
        canvas: the canvas painted on (square texels).
        preset: the brush.
        cells_xy: lateral cells of the model's grid.
        reference_cells: lateral cells that set the cell size (``span`` brush widths over this
            many cells); default ``cells_xy[0]``. A fitted grid passes its full size here.
        needs: which outputs are read (default: force and torque).
    """

    name = "model"
    #: Whether this model's grid can follow the tip continuously (:class:`PaintScene`'s
    #: ``follow``).
    follows_continuously = False
    #: Whether the paint closes over the tip's footprint at lift-off (a fluid does, a stamp not).
    settles_on_lift = True

    def __init__(
        self,
        scene: PaintScene,
        canvas: Canvas,
        preset: BrushPreset,
        cells_xy: tuple[int, int],
        *,
        reference_cells: int | None = None,
        needs: ForceNeeds | None = None,
    ) -> None:
        self.scene = scene
        self.canvas = canvas
        self.preset = preset
        self.needs = needs or ForceNeeds()
        ref = reference_cells or cells_xy[0]
        k = cell_texels(brush_width_m(preset), square_texel_m(canvas), ref, scene.span)
        self.window = ColumnWindow(
            canvas, cells_xy, k, scene.transfer, continuous=self._continuous(scene, k)
        )
        self.margin_cells = scaled_margin(scene.margin_cells, ref, cells_xy)
        self.pose: TipPose | None = None
        #: Direction of the tip's last lateral motion (canvas plane): the bristles' streaks
        #: run along it.
        self.heading = np.array([0.0, 1.0])
        #: The tip's travel (m, x and y) during the current sub-step (zero without ``sweep``).
        self.travel_m = np.zeros(2)
        #: The length of the tip's path in the canvas plane since it last touched down (m).
        self.travelled_m = 0.0
        #: The paint's Reynolds number at the tip during the current step (kept at 0 unless
        #: ``choose.stokes_below_re`` asks for it).
        self.reynolds = 0.0

    def solver_settings(self) -> SolverSettings:
        """The scene's solver settings, with no force work when nothing reads the force."""
        if self.needs.force:
            return self.scene.solver
        return replace(self.scene.solver, probe_forces=False)

    def step_settings(self) -> SolverSettings:
        """The solver settings for the current step: :meth:`solver_settings`, as a Stokes flow
        (no momentum advection) while :attr:`reynolds` is below ``choose.stokes_below_re``.

        In creeping paint the advection term is ``Re`` times the viscous one, but the paint-free
        cells above the paint (``air_viscosity_ratio``) are not creeping, and a tip that jumps
        cells between steps leaves behind it the velocity that advection would have carried
        along: leaving it out saves solver time but roughens a fast tip's trail, so only the
        ``draft`` preset takes it by default."""
        settings = self.solver_settings()
        if self.reynolds < self.scene.choose.stokes_below_re and settings.advection != "none":
            return replace(settings, advection="none")
        return settings

    def tip_reynolds(self, start: TipPose, pose: TipPose, dt_s: float) -> float:
        """The paint's Reynolds number ``rho U L / mu`` for the tip moving from ``start`` to
        ``pose`` in ``dt_s`` seconds (L: its footprint's width)."""
        speed = float(np.linalg.norm(pose.position_m - start.position_m)) / dt_s
        width = 2.0 * self.footprint_radius_m(pose)
        return self.scene.density_kg_m3 * speed * width / self.scene.viscosity_pa_s

    def used_channels(self, columns: np.ndarray, reservoir: PaintReservoir) -> np.ndarray:
        """Indices of the pigment channels to carry: those with wet paint in ``columns``
        (P, nx, ny) or in the brush (all of them unless ``scene.choose.used_pigments``)."""
        names = self.canvas.pigment_names
        if not self.scene.choose.used_pigments:
            return np.arange(len(names))
        held = reservoir.volumes_m3
        used = [p for p, n in enumerate(names) if held.get(n, 0.0) > 0.0 or columns[p].any()]
        return np.array(used, dtype=np.intp)

    def tip_output(
        self, force_n: np.ndarray, torque_nm: np.ndarray | float
    ) -> tuple[np.ndarray, ...]:
        """Force and torque as published: zero where nothing reads them."""
        force = np.asarray(force_n, dtype=float).copy() if self.needs.force else np.zeros(3)
        keep = self.needs.force and self.needs.torque
        return force, np.asarray(torque_nm, dtype=float).copy() if keep else np.zeros(3)

    @property
    def cell_size_m(self) -> float:
        """Cell edge (m)."""
        return self.window.cell_size_m

    def touch_down(self, pose: TipPose) -> None:
        """The brush enters the paint at ``pose``: centre the window there, fluid at rest."""
        self.window.place(float(pose.position_m[0]), float(pose.position_m[1]))
        self.pose = pose
        self.travelled_m = 0.0
        yaw = yaw_angle(pose.orientation)
        self.heading = np.array([-math.sin(yaw), math.cos(yaw)])  # body y: a flat brush's stroke
        self._reset(pose)

    def lift(self, settle: bool = True) -> None:
        """The brush leaves the paint; with ``settle`` (a real lift-off, not a change of model
        under a brush still in the paint) the wet paint flows back into its footprint."""
        if settle and self.settles_on_lift and self.scene.settle_on_lift and self.pose is not None:
            self.settle(self.pose)
        self.pose = None

    def settle(self, pose: TipPose) -> None:
        """Let the wet paint round the tip's footprint at ``pose`` flow back into it.

        The tip pushed the paint out of its footprint (into a ridge round it); lifted, it leaves
        a hole down to the bare canvas, which viscous paint closes over. Over the footprint's
        columns and :data:`SETTLE_REACH_CELLS` around them (on the canvas), each pigment's wet
        paint is exchanged between neighbouring columns, :data:`SETTLE_SHARE` of the difference
        per sweep, until the footprint's emptiest column holds :data:`SETTLE_LEVEL` of the
        region's mean (at most :data:`SETTLE_MAX_SWEEPS` sweeps): conserved exactly, never
        negative, dry paint untouched, and nothing moves beyond that region."""
        h = self.cell_size_m
        shape = Section(self.preset.tip(pose.splay), section_height_m(pose, h))
        origin, cells = self.window.origin_m, self.window.cells
        foot = voxelize(shape, pose.position_m[:2], yaw_angle(pose.orientation), origin, h, cells)
        region = binary_dilation(foot, iterations=SETTLE_REACH_CELLS) & self.window.on_canvas()
        if not (foot & region).any():
            return
        columns = self.wet_columns()
        q = columns.copy()
        inside = foot & region
        for _ in range(SETTLE_MAX_SWEEPS):
            total = q.sum(axis=0)
            if total[inside].min() >= SETTLE_LEVEL * total[region].mean():
                break
            for axis in (1, 2):
                lo = [slice(None)] * 3
                hi = [slice(None)] * 3
                lo[axis], hi[axis] = slice(None, -1), slice(1, None)
                pair = region[tuple(lo[1:])] & region[tuple(hi[1:])]
                flow = SETTLE_SHARE * (q[tuple(hi)] - q[tuple(lo)]) * pair
                q[tuple(lo)] += flow
                q[tuple(hi)] -= flow
        self.window.write_back(self.canvas, np.maximum(q, 0.0) - columns, gathered=columns)

    def step(self, pose: TipPose, dt_s: float, reservoir: PaintReservoir) -> PaintStep:
        """Move the tip to ``pose`` over ``dt_s`` seconds, exchanging paint with ``reservoir``."""
        if self.pose is None:
            self.touch_down(pose)
        assert self.pose is not None
        start = self.pose
        move = np.asarray(pose.position_m[:2] - start.position_m[:2], dtype=float)
        travel = float(np.hypot(*move))
        if travel > 1e-3 * self.window.texel_m:
            self.heading = move / travel
        scene = self.scene
        by_travel = math.ceil(travel / (scene.max_travel_cells * self.cell_size_m) - 1e-9)
        n = max(
            1,
            math.ceil(dt_s / scene.max_step_s - 1e-9),
            min(by_travel, scene.max_travel_substeps),
        )
        result = PaintStep()
        # each sub-step laid along its path once it starts clear of the touch-down print
        sweep_from = self.sweep_start_m(start) if scene.sweep else math.inf
        travelled, self.travelled_m = self.travelled_m, self.travelled_m + travel
        if scene.choose.stokes_below_re > 0.0 and dt_s > 0.0:  # no work when it cannot apply
            self.reynolds = self.tip_reynolds(start, pose, dt_s)
        for s in range(n):
            f = (s + 1) / n
            centre = (1.0 - f) * start.position_m + f * pose.position_m
            clear = travelled + s * travel / n >= sweep_from
            self.travel_m = move / n if clear else np.zeros(2)
            clock = PhaseTimer()
            self.follow(centre)
            clock.mark("follow")
            moved = PaintStep(step_ms=clock.total_ms, phase_ms=clock.ms)
            result = self._merge(result, moved)
            result = self._merge(result, self._advance(pose, centre, dt_s / n, reservoir))
        self.pose = pose
        return result

    def _merge(self, total: PaintStep, part: PaintStep) -> PaintStep:
        return PaintStep(
            force_n=part.force_n,
            torque_nm=part.torque_nm,
            solver_steps=total.solver_steps + part.solver_steps,
            transport_substeps=total.transport_substeps + part.transport_substeps,
            exchange=add_reports(total.exchange, part.exchange),
            step_ms=total.step_ms + part.step_ms,
            channels=max(total.channels, part.channels),
            stokes_steps=total.stokes_steps + part.stokes_steps,
            phase_ms={
                k: total.phase_ms.get(k, 0.0) + part.phase_ms.get(k, 0.0)
                for k in {**total.phase_ms, **part.phase_ms}
            },
        )

    def _continuous(self, scene: PaintScene, k: int) -> bool:
        """Whether the window of ``k``-texel cells follows the tip continuously
        (:class:`PaintScene`'s ``follow``, where this model can). Not with fewer than
        ``SWEEP_MIN_TEXELS`` texels a cell: nothing lays a step's change along the tip's path
        there, and the window's corner between texels left the square probe's fast trail on
        one texel a cell combed at its sample period (0.31 of its height, against 0.12 by whole
        cells: ``tests/paintapp/paint/test_trail.py``)."""
        return self.follows_continuously and scene.follow == "continuous" and k >= SWEEP_MIN_TEXELS

    def follow(self, centre_m: np.ndarray) -> tuple[float, float]:
        """Re-centre the window (and the fluid state) on the tip at ``centre_m``: exactly, when
        it follows continuously; else by whole cells once the tip is within ``margin_cells`` (the
        scene's, scaled to a fitted grid) of a side. Returns the shift (di, dj) in cells."""
        di, dj = self.window.recentre_offset(
            float(centre_m[0]), float(centre_m[1]), self.margin_cells
        )
        if di or dj:
            self.window.shift(di, dj)
            self._shifted(di, dj)
        return di, dj

    def sweep_texels(self) -> tuple[float, float] | None:
        """The tip's travel during the current sub-step in texels (x, y), which the write-back
        lays the step's change along; None without travel (or with the scene's ``sweep`` off)."""
        if not self.travel_m.any():
            return None
        t = self.window.texel_m
        return float(self.travel_m[0] / t), float(self.travel_m[1] / t)

    def texture(self, pose: TipPose, centre_m: np.ndarray) -> TexelWeights | None:
        """The texel weights of a step with the apex at ``centre_m``: the brush's bristle
        texture (None for a preset without bristles), within the canvas tooth's
        (:class:`paintapp.paint.tooth.ToothTexture`) on a canvas with tooth."""
        bristles = self.bristle_texture(pose, centre_m)
        if self.canvas.has_tooth:
            return ToothTexture(self.canvas, pose.pressure, bristles)
        return bristles

    def bristle_texture(self, pose: TipPose, centre_m: np.ndarray) -> BristleTexture | None:
        """The brush's bristle texture for a step with the apex at ``centre_m``, or None for a
        preset without bristles."""
        bristles = self.preset.bristles
        if bristles is None:
            return None
        h = self.cell_size_m
        depth = max(pose.press_depth_m + pose.compression_m, section_height_m(pose, h))
        tip = self.preset.tip(pose.splay)
        lateral = self.footprint_radius_m(pose) / math.sqrt(2.0)
        return BristleTexture(
            bristles,
            Section(tip, depth),
            np.asarray(centre_m, dtype=float)[:2],
            yaw_angle(pose.orientation),
            self.heading,
            self.window.texel_m,
            h,
            math.sqrt(2.0) * lateral,
        )

    def sweep_start_m(self, pose: TipPose) -> float:
        """How far (m, along its path) the tip travels from where it touched down before its
        sub-steps are laid along the path (those that start that far out or farther): twice the
        reach of its touch-down print, the contact's radius at ``pose``
        (:func:`paintapp.paint.contact.contact_radius_m`, at the height the bristle texture cuts
        the tip) and a cell beyond it, which the print's displaced paint reaches. Sweeping a
        sub-step whose change still holds that print moves it behind the touch-down point, where
        the tip never was (a hole behind the stroke's start)."""
        h, reach = self.cell_size_m, self.footprint_radius_m(pose)
        if self.travelled_m >= 2.0 * (reach + h):
            return 0.0  # past any contact's reach: no need to measure it
        height = max(pose.press_depth_m + pose.compression_m, section_height_m(pose, h))
        return 2.0 * (contact_radius_m(self.preset.tip(pose.splay), height, reach) + h)

    def footprint_radius_m(self, pose: TipPose) -> float:
        """The largest distance from the apex the tip (splayed as at ``pose``) reaches in the
        canvas plane, at most: its extent along body x and y, times sqrt(2)."""
        tip = self.preset.tip(pose.splay)
        lateral = max(tip.support(d) for d in np.vstack([np.eye(3)[:2], -np.eye(3)[:2]]))
        return math.sqrt(2.0) * lateral

    def plough(
        self, grid: Grid, centre_m: np.ndarray, velocity_m_s: np.ndarray, dt_s: float
    ) -> np.ndarray:
        """(nx, ny) share of each of ``grid``'s columns' room open to the paint the tip pushes,
        with the tip at ``centre_m`` after moving at ``velocity_m_s`` for ``dt_s``
        (:func:`plough_weights`)."""
        h = grid.cell_size_m
        centre = (np.asarray(centre_m, dtype=float)[:2] - np.asarray(grid.origin_m)[:2]) / h
        travel = np.asarray(velocity_m_s, dtype=float)[:2] * dt_s / h
        return plough_weights((grid.cells[0], grid.cells[1]), centre, travel)

    def wet_columns(self) -> np.ndarray:
        """Wet paint per column under the window, (P, nx, ny) metres."""
        return self.window.gather(self.canvas)

    @abstractmethod
    def _reset(self, pose: TipPose) -> None:
        """Start a stroke at ``pose`` with the window already placed."""

    @abstractmethod
    def _shifted(self, di: float, dj: float) -> None:
        """The window moved by (di, dj) cells (whole cells unless it follows continuously); move
        the model's grid with it."""

    @abstractmethod
    def _advance(
        self, pose: TipPose, centre_m: np.ndarray, dt_s: float, reservoir: PaintReservoir
    ) -> PaintStep:
        """One step to ``pose`` with the apex at ``centre_m`` (m, canvas frame)."""


def scaled_margin(margin: int, reference_cells: int, cells_xy: tuple[int, int]) -> int:
    """The re-centring margin (cells) of a grid of ``cells_xy`` columns: the scene's ``margin``
    on a full grid; on a smaller one, in proportion to ``reference_cells`` and under half of it."""
    if cells_xy[0] >= reference_cells:
        return margin
    scaled = round(margin * cells_xy[0] / reference_cells)
    return max(0, min(scaled, (min(cells_xy) - 1) // 2))


def section_height_m(pose: TipPose, cell_m: float) -> float:
    """Body height (m) of the tip cut used as its footprint in the canvas plane: half the depth
    the stylus commands (paint depth plus the part pressed flat on the canvas), at least h/2."""
    return max(0.5 * (pose.press_depth_m + pose.compression_m), 0.5 * cell_m)


def unwrap_angle(target_rad: float, current_rad: float) -> float:
    """``target_rad`` shifted by whole turns to lie within pi of ``current_rad``."""
    return current_rad + math.remainder(target_rad - current_rad, 2.0 * math.pi)

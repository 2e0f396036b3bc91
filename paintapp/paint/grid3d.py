"""The 3D paint grid: a viscous-fluid box over the brush footprint that rides with the tip.

Geometry: ``scene.cells`` (or fewer, ``cells``: a grid fitted to the brush) cubes of edge ``h`` (a
whole number of canvas texels, the grid spanning ``scene.span`` brush widths); the bottom face is
the canvas plane ``z = 0``, a no-slip wall. The lateral sides are free-slip walls (the paint
around the window at rest) or, with ``sides = "open"``, zero pressure, the paint crossing them
traded with a band of canvas beyond (:mod:`paintapp.paint.far_field`); the top is open, so the tip
can push down into the box. Columns not wholly on the canvas are solid.

Fluid: the paint's density, viscosity ``mu = mu_air + phi (mu_paint - mu_air)`` per cell (``phi``
its paint fraction; ``mu_air`` is ``air_viscosity_ratio`` of the paint's); the implicit solver
needs no scaling of real paint viscosities. The brush force is the stress integral over the tip.

Each step: fill the cells from the canvas's wet paint (:func:`paintapp.paint.cell_kernels.fill_columns`),
set the viscosity field, drive the probe to the tip pose and take one solver step, trade paint with
the brush (:mod:`paintapp.paint.exchange`), transport the paint conservatively with the new
velocity (:func:`solver.advection.scalars.transport`), and write the change back to the canvas
(less the creep of the paint far from the brush, :mod:`paintapp.paint.still`).
The floor cuts off the tip below the canvas (bristles pressed flat): the footprint grows with depth.
"""

from __future__ import annotations

import time

import numpy as np

from brushes import BrushPreset, PaintReservoir, TipPose, probe_motion
from common.timing import PhaseTimer
from paintapp.canvas.model import Canvas
from paintapp.paint.cell_kernels import fill_columns
from paintapp.paint.columns import ColumnWindow, TexelWeights
from paintapp.paint.exchange import (
    CellSpace,
    ExchangeReport,
    cell_caps,
    deposit_volume,
    exchange_with_brush,
)
from paintapp.paint.far_field import band_change, padded_transport, side_faces
from paintapp.paint.nearest_room import tip_distance
from paintapp.paint.paint_model import ForceNeeds, PaintModel, PaintStep
from paintapp.paint.paint_scene import PaintScene
from paintapp.paint.still import keep_still
from paintapp.paint.texel_velocity import column_face_velocity
from paintapp.paint.tooth import bristles_only
from paintapp.paint.trail import lay_trail, paint_faces, vacated_share
from paintapp.paint.wet_flow import flow_wet_paint
from solver import BesideJob, DomainBoundary, Fluid, Grid, Probe, Side, Simulation, transport

PROBE = "brush"
LATERAL = ("x_min", "x_max", "y_min", "y_max")
#: The grid's sides with slip lateral walls (see the module docstring).
SIDES = {
    **{name: Side("slip") for name in LATERAL},
    "z_min": Side("wall"),
    "z_max": Side("outflow"),
}


def grid_sides(open_sides: bool) -> dict[str, Side]:
    """The grid's sides: :data:`SIDES`, or with its lateral sides open (``outflow``)."""
    if not open_sides:
        return dict(SIDES)
    return {**SIDES, **{name: Side("outflow") for name in LATERAL}}


def pressed_centre(pose: TipPose, centre_m: np.ndarray) -> np.ndarray:
    """Apex position (m) with the tip lowered by the stylus's compression into the canvas."""
    return np.asarray(centre_m, dtype=float) - np.array([0.0, 0.0, pose.compression_m])


class PaintGrid3D(PaintModel):
    """The 3D paint grid (see the module docstring).

    Args:
        scene, canvas, preset: as :class:`PaintModel`.
        cells: (nx, ny, nz) cells, at most ``scene.cells`` (default: ``scene.cells``); the cell
            size is always the one ``scene.cells`` gives.
        needs: which outputs are read.
    """

    name = "grid3d"
    follows_continuously = True

    def __init__(
        self,
        scene: PaintScene,
        canvas: Canvas,
        preset: BrushPreset,
        *,
        cells: tuple[int, int, int] | None = None,
        needs: ForceNeeds | None = None,
    ) -> None:
        self.cells = cells or scene.cells
        super().__init__(
            scene,
            canvas,
            preset,
            (self.cells[0], self.cells[1]),
            reference_cells=scene.cells[0],
            needs=needs,
        )
        self.sim: Simulation | None = None
        self.probe: Probe | None = None
        #: Width of the far-field band beyond each open side (0: slip sides).
        self.far = scene.far_field_cells if scene.sides == "open" else 0
        w, b = self.window, self.far
        self.outer = ColumnWindow(canvas, (w.cells[0] + 2 * b, w.cells[1] + 2 * b), w.k, w.kernel)
        #: The canvas's columns read beside the last re-centring, with the window's origin
        #: (texels) they were read at; the step that follows takes them (:meth:`_shifted`).
        self._read_ahead: tuple[tuple[float, float], np.ndarray] | None = None

    def band_columns(self) -> np.ndarray:
        """Wet paint per column under the window and, with open sides, the band around it:
        (P, nx + 2 b, ny + 2 b) metres for a band of ``b`` columns."""
        o, k, b = self.window.origin_texel, self.window.k, self.far
        self.outer.origin_texel = (o[0] - b * k, o[1] - b * k)
        return self.outer.gather(self.canvas)

    def _grid(self) -> Grid:
        ox, oy = self.window.origin_m
        return Grid(3, self.cells, self.cell_size_m, (ox, oy, 0.0))

    def _reset(self, pose: TipPose) -> None:
        s = self.scene
        probe = probe_motion(pose, self.preset, name=PROBE).to_probe()
        probe.centre_m = pressed_centre(pose, pose.position_m)
        probe.velocity_m_s = np.zeros(3)
        probe.angular_velocity_rad_s = np.zeros(3)
        grid = self._grid()
        self.probe = probe
        self.sim = Simulation(
            grid,
            Fluid(s.density_kg_m3, s.viscosity_pa_s / s.density_kg_m3),
            DomainBoundary(grid, grid_sides(self.far > 0)),
            [probe],
            self.solver_settings(),
        )

    def _shifted(self, di: float, dj: float) -> None:
        if self.sim is None:
            return
        # the canvas under the moved window is read beside the fluid's move (which reads and
        # writes only the simulation's state), for the step that follows
        origin = self.window.origin_texel
        job = BesideJob(self.band_columns, self.sim.component_threads())
        try:
            self.sim.shift((di, dj, 0))
        except BaseException:
            job.settle()
            raise
        self._read_ahead = (origin, job.result())

    def _columns(self) -> np.ndarray:
        """:meth:`band_columns`, as read beside the re-centring when the window has not moved
        since (nothing writes the canvas between a re-centring and its step)."""
        ahead, self._read_ahead = self._read_ahead, None
        if ahead is not None and ahead[0] == self.window.origin_texel:
            return ahead[1]
        return self.band_columns()

    def viscosity_field(self, q: np.ndarray) -> np.ndarray:
        """Cell viscosities (Pa s) from paint fields (P, nx, ny, nz)."""
        s = self.scene
        phi = np.clip(q.sum(axis=0), 0.0, 1.0)
        return s.air_viscosity_pa_s + phi * (s.viscosity_pa_s - s.air_viscosity_pa_s)

    def _advance(
        self, pose: TipPose, centre_m: np.ndarray, dt_s: float, reservoir: PaintReservoir
    ) -> PaintStep:
        assert self.sim is not None and self.probe is not None
        clock = PhaseTimer()
        sim, probe, h = self.sim, self.probe, self.cell_size_m
        b, nx, ny = self.far, self.cells[0], self.cells[1]
        outer = self._columns()
        all_columns = outer[:, b : b + nx, b : b + ny]
        used = self.used_channels(all_columns, reservoir)
        columns = all_columns[used]
        q = np.zeros((len(used), *self.cells))
        fill_columns(columns, h, q)
        before = q.copy()
        sim.static_solid[:] = ~self.window.on_canvas()[:, :, None]
        sim.set_viscosity(self.viscosity_field(q))
        probe.shape = self.preset.tip(pose.splay)
        probe.drive_to(pressed_centre(pose, centre_m), pose.orientation, dt_s)
        before_step = (
            sim.state.label.copy(),
            None if sim.cut is None else sim.cut.fluid_frac.copy(),
        )
        clock.mark("read")
        band = np.zeros((len(used), *outer.shape[1:]))  # the far field's change
        sim.settings = self.step_settings()
        names = [self.canvas.pigment_names[p] for p in used]
        exchanged: list[tuple[CellSpace, ExchangeReport, TexelWeights | None, float]] = []

        def exchange() -> None:
            # the brush's exchange needs the step's geometry, not its flow, and its bristle
            # texture neither: they run beside the pressure solve
            # (:meth:`solver.simulation.Simulation.step`'s ``beside``)
            start = time.perf_counter()
            space = self._cell_space(sim.state.label)
            report = self._exchange(q, pose, dt_s, reservoir, names, space)
            texture = self.texture(pose, centre_m)
            exchanged.append((space, report, texture, 1e3 * (time.perf_counter() - start)))

        try:
            sim.step(dt_s, beside=exchange)
            clock.mark("solver")
            space, report, texture, exchange_ms = exchanged[0]
            clock.ms["exchange"] = exchange_ms  # within the solver's wall time
            if self.scene.texel_flow:
                flow = column_face_velocity(q.sum(axis=0), sim.state.comps, sim.state.face_types)
                if not all(np.isfinite(f).all() for f in flow):
                    raise FloatingPointError("non-finite velocity in the paint grid")
            else:
                substeps = self._transport(q, dt_s, space, outer[used], band, *before_step)
            clock.mark("transport")
        except FloatingPointError:
            self._reset(pose)  # a blown-up step: drop it, start the fluid again at rest
            return PaintStep(step_ms=clock.total_ms)
        delta = np.zeros_like(outer)
        delta[used] = band
        delta[used, b : b + nx, b : b + ny] += (q - before).sum(axis=3) * h
        delta = keep_still(outer, delta, self.scene.still_rate_per_s * dt_s)
        self.outer.write_back(
            self.canvas, delta, texture, gathered=outer, sweep_texels=self.sweep_texels()
        )
        if self.scene.texel_flow:  # the brush's exchange went through the columns; now the flow
            try:
                bristles = bristles_only(texture)  # the tooth shapes the exchange, not the flow
                substeps = flow_wet_paint(self.canvas, self.window, *flow, dt_s, bristles)
            except FloatingPointError:
                self._reset(pose)
                return PaintStep(step_ms=clock.total_ms, exchange=report)
        clock.mark("write")
        found = sim.forces.get(PROBE)
        force, torque = (
            (np.zeros(3), np.zeros(3))
            if found is None
            else self.tip_output(found.force, found.torque)
        )
        return PaintStep(
            force_n=force,
            torque_nm=torque,
            solver_steps=1,
            stokes_steps=int(sim.settings.advection == "none"),
            transport_substeps=substeps,
            exchange=report,
            step_ms=clock.total_ms,
            phase_ms=clock.ms,
            channels=len(used),
        )

    def _transport(
        self,
        q: np.ndarray,
        dt_s: float,
        space: CellSpace,
        outer: np.ndarray,
        band: np.ndarray,
        label_before: np.ndarray,
        fluid_before: np.ndarray | None,
    ) -> int:
        """Move the paint with the step's velocity through the faces' open parts, then lay what
        piled up against the tip in the room it vacated (:mod:`paintapp.paint.trail`); returns
        the transport's sub-steps. ``space`` holds this step's cell capacities. With open sides,
        ``outer`` is the wet paint per column of the window and its far-field band (the used
        channels), and ``band`` receives the band's change (:mod:`paintapp.paint.far_field`)."""
        assert self.sim is not None
        sim = self.sim
        label, cut = sim.state.label, sim.cut
        open_frac = None if cut is None else cut.open_frac
        fluid = None if cut is None else cut.fluid_frac
        vel, types = paint_faces(sim.state.comps, sim.state.face_types, label, open_frac, fluid)
        threads = sim.component_threads()  # the pigments' fields on the solver's threads
        scheme = self.scene.transport
        if self.far == 0:
            substeps = transport(q, vel, types, 3, self.cell_size_m, dt_s, threads, scheme)
        else:
            b = self.far
            on_canvas = self.outer.on_canvas()
            faces = side_faces(sim.state.comps, sim.state.face_types, open_frac, on_canvas, b)
            ring = outer[:, b - 1 : outer.shape[1] - b + 1, b - 1 : outer.shape[2] - b + 1]
            substeps, gains = padded_transport(
                q, vel, types, *faces, ring, self.cell_size_m, dt_s, threads, scheme
            )
            band += band_change(gains, outer, on_canvas, b)
        share = vacated_share(label_before, label, fluid_before, fluid)
        lay_trail(q, label, share, space)
        return substeps

    def _cell_space(self, label: np.ndarray) -> CellSpace:
        """Cell volume and each cell's capacity (its fluid fraction of a full cell); deposits go
        into the layer above the tip's lowest; with cut cells (and the scene's ``push`` =
        ``"distance"``) the tip's distance at each cell, which pushed paint fills by."""
        assert self.sim is not None
        layers = np.flatnonzero((label >= 0).any(axis=(0, 1)))
        lowest = int(layers[0]) if layers.size else 0
        cut = self.sim.cut
        caps = cell_caps(1.0, label, None if cut is None else cut.fluid_frac)
        distance = None
        if cut is not None and self.scene.push == "distance":
            distance = tip_distance(cut.phi_cell, self.cell_size_m)
        return CellSpace(self.cell_size_m**3, caps, lowest + 1, 1.0, distance)

    def _exchange(
        self,
        q: np.ndarray,
        pose: TipPose,
        dt_s: float,
        reservoir: PaintReservoir,
        names: list[str],
        space: CellSpace,
    ) -> ExchangeReport:
        assert self.sim is not None and self.probe is not None
        label = self.sim.state.label
        if not (label >= 0).any():
            return ExchangeReport()
        speed = float(np.hypot(*self.probe.velocity_m_s[:2]))
        offer = deposit_volume(reservoir, speed, pose.pressure, dt_s, self.scene.deposit_length_m)
        return exchange_with_brush(
            q,
            label,
            reservoir,
            names,
            space,
            self.scene.pickup_fraction,
            offer,
            self.plough(self.sim.grid, self.probe.centre_m, self.probe.velocity_m_s, dt_s),
        )

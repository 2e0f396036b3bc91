"""The depth-averaged paint grid (Baxter & Lin, section 5.2): a 2D grid in the canvas plane.

For thin paint the layer moves with the same velocity at every depth, so a 2D incompressible
fluid in the canvas plane carries the paint *thickness* (metres per pigment in each cell). The tip
is the cut of its (splayed) shape at half the commanded depth, turned by its yaw. The four sides
are free-slip walls, and the grid re-centres on the tip at every step (the scene's
``margin_cells``), so they stay half a grid from it.

Viscosity: a layer of thickness ``H`` has the depth-integrated stress ``mu H`` times the in-plane
strain rate, so each cell gets ``mu_air + (mu - mu_air) H / H_ref`` (``H`` clipped to
``H_ref = max_height_m``), and bare canvas barely moves. The no-slip canvas under a
half-parabolic profile gives the drag rate ``3 mu_cell / (rho H_ref^2)`` on the depth-averaged
velocity, so the paint moves only within about ``H_ref`` of the tip, while the nearly free air
lets the displaced fluid go round it.

Force: the 2D stress integral is per unit depth (N/m, N m/m for the torque about the canvas
normal); times ``H_ref`` it gives newtons: thicker paint pushes back harder, and a tip in no paint
feels (almost) nothing. The z force and the tilting torques are zero in this model.
"""

from __future__ import annotations

import numpy as np

from brushes import BrushPreset, PaintReservoir, Section, TipPose
from common.tilt import yaw_angle
from common.timing import PhaseTimer
from paintapp.canvas.model import Canvas
from paintapp.paint.exchange import (
    CellSpace,
    ExchangeReport,
    cell_caps,
    deposit_volume,
    exchange_with_brush,
)
from paintapp.paint.paint_model import (
    ForceNeeds,
    PaintModel,
    PaintStep,
    section_height_m,
    unwrap_angle,
)
from paintapp.paint.paint_scene import PaintScene
from paintapp.paint.still import keep_still
from solver import DomainBoundary, Fluid, Grid, Probe, Side, Simulation, transport

PROBE = "brush"
SIDES = {name: Side("slip") for name in ("x_min", "x_max", "y_min", "y_max")}


class PaintGridDepthAveraged(PaintModel):
    """The depth-averaged 2D paint grid (see the module docstring).

    Args:
        scene, canvas, preset: as :class:`PaintModel`.
        cells: (nx, ny, nz) of which (nx, ny) are used, at most ``scene.cells`` (default:
            ``scene.cells``); the cell size is always the one ``scene.cells`` gives.
        needs: which outputs are read.
    """

    name = "depth_averaged"

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

    def _shape(self, pose: TipPose) -> Section:
        return Section(self.preset.tip(pose.splay), section_height_m(pose, self.cell_size_m))

    def _reset(self, pose: TipPose) -> None:
        s, h = self.scene, self.cell_size_m
        ox, oy = self.window.origin_m
        grid = Grid(2, (self.cells[0], self.cells[1], 1), h, (ox, oy, 0.0))
        self.probe = Probe(
            PROBE, self._shape(pose), 2, pose.position_m[:2], yaw_angle(pose.orientation)
        )
        self.sim = Simulation(
            grid,
            Fluid(s.density_kg_m3, s.viscosity_pa_s / s.density_kg_m3),
            DomainBoundary(grid, dict(SIDES)),
            [self.probe],
            self.solver_settings(),
        )

    def _shifted(self, di: float, dj: float) -> None:
        if self.sim is not None:
            self.sim.shift((di, dj))

    def viscosity_field(self, q: np.ndarray) -> np.ndarray:
        """Effective cell viscosities (Pa s) from paint thicknesses (P, nx, ny, 1) in metres."""
        s = self.scene
        fill = np.clip(q.sum(axis=0) / s.max_height_m, 0.0, 1.0)
        return s.air_viscosity_pa_s + fill * (s.viscosity_pa_s - s.air_viscosity_pa_s)

    def _advance(
        self, pose: TipPose, centre_m: np.ndarray, dt_s: float, reservoir: PaintReservoir
    ) -> PaintStep:
        assert self.sim is not None and self.probe is not None
        clock = PhaseTimer()
        sim, probe, h = self.sim, self.probe, self.cell_size_m
        all_columns = self.wet_columns()
        used = self.used_channels(all_columns, reservoir)
        q = all_columns[used][..., None]
        before = q.copy()
        sim.static_solid[:] = ~self.window.on_canvas()[:, :, None]
        mu = self.viscosity_field(q)
        sim.set_viscosity(mu)
        sim.set_drag(3.0 * mu / (self.scene.density_kg_m3 * self.scene.max_height_m**2))
        probe.shape = self._shape(pose)
        yaw = unwrap_angle(yaw_angle(pose.orientation), float(probe.orientation))
        probe.drive_to(np.asarray(centre_m[:2], dtype=float), yaw, dt_s)
        clock.mark("read")
        sim.settings = self.step_settings()
        try:
            sim.step(dt_s)
            clock.mark("solver")
            names = [self.canvas.pigment_names[p] for p in used]
            report = self._exchange(q, pose, dt_s, reservoir, names)
            clock.mark("exchange")
            threads, scheme = sim.component_threads(), self.scene.transport
            substeps = transport(
                q, sim.state.comps, sim.state.face_types, 2, h, dt_s, threads, scheme
            )
            clock.mark("transport")
        except FloatingPointError:
            self._reset(pose)
            return PaintStep(step_ms=clock.total_ms)
        delta = np.zeros_like(all_columns)
        delta[used] = (q - before)[..., 0]
        delta = keep_still(all_columns, delta, self.scene.still_rate_per_s * dt_s)
        self.window.write_back(
            self.canvas,
            delta,
            self.texture(pose, centre_m),
            gathered=all_columns,
            sweep_texels=self.sweep_texels(),
        )
        clock.mark("write")
        force, torque = self._tip_force()
        return PaintStep(
            force,
            torque,
            1,
            substeps,
            report,
            clock.total_ms,
            clock.ms,
            channels=len(used),
            stokes_steps=int(sim.settings.advection == "none"),
        )

    def _tip_force(self) -> tuple[np.ndarray, ...]:
        """Force (N) and torque (N m) on the tip: the per-depth 2D values times ``H_ref``."""
        assert self.sim is not None
        f, depth = self.sim.forces.get(PROBE), self.scene.max_height_m
        if f is None:
            return np.zeros(3), np.zeros(3)
        force = np.array([f.force[0] * depth, f.force[1] * depth, 0.0])
        return self.tip_output(force, np.array([0.0, 0.0, float(f.torque) * depth]))

    def _exchange(
        self,
        q: np.ndarray,
        pose: TipPose,
        dt_s: float,
        reservoir: PaintReservoir,
        names: list[str],
    ) -> ExchangeReport:
        assert self.sim is not None and self.probe is not None
        s, h = self.scene, self.cell_size_m
        label, cut = self.sim.state.label, self.sim.cut
        caps = cell_caps(s.max_height_m, label, None if cut is None else cut.fluid_frac)
        space = CellSpace(h * h, caps, 0, s.max_height_m)
        speed = float(np.hypot(*self.probe.velocity_m_s))
        offer = deposit_volume(reservoir, speed, pose.pressure, dt_s, s.deposit_length_m)
        plough = self.plough(self.sim.grid, self.probe.centre_m, self.probe.velocity_m_s, dt_s)
        return exchange_with_brush(
            q, label, reservoir, names, space, s.pickup_fraction, offer, plough
        )

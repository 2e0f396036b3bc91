"""No fluid (``fluid_model = "none"``): the brush soaks and stamps paint under its footprint.

The footprint is the tip's cut at half the commanded depth (as in the depth-averaged grid). Each
step the brush soaks up ``pickup_fraction`` of the wet paint under it (as far as it has room) and
lays down its deposit (:func:`paintapp.paint.exchange.deposit_volume`) evenly over the footprint's
free room (up to ``max_height_m`` per column). Nothing flows, and the brush feels no force.
"""

from __future__ import annotations

import time

import numpy as np

from brushes import BrushPreset, PaintReservoir, Section, TipPose
from brushes.probe import voxelize
from common.tilt import yaw_angle
from paintapp.canvas.model import Canvas
from paintapp.paint.exchange import ExchangeReport, deposit_volume
from paintapp.paint.paint_model import ForceNeeds, PaintModel, PaintStep, section_height_m
from paintapp.paint.paint_scene import PaintScene


class StampModel(PaintModel):
    """The fluid-free paint model (see the module docstring)."""

    name = "none"
    settles_on_lift = False  # nothing flows

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
        self._last_xy = np.zeros(2)

    def _reset(self, pose: TipPose) -> None:
        self._last_xy = np.array(pose.position_m[:2], dtype=float)

    def _shifted(self, di: float, dj: float) -> None:
        pass

    def footprint(self, pose: TipPose, centre_m: np.ndarray) -> np.ndarray:
        """(nx, ny) bool: columns under the tip's footprint (and on the canvas)."""
        h = self.cell_size_m
        shape = Section(self.preset.tip(pose.splay), section_height_m(pose, h))
        mask = voxelize(
            shape,
            centre_m[:2],
            yaw_angle(pose.orientation),
            self.window.origin_m,
            h,
            self.window.cells,
        )
        return mask & self.window.on_canvas()

    def _advance(
        self, pose: TipPose, centre_m: np.ndarray, dt_s: float, reservoir: PaintReservoir
    ) -> PaintStep:
        start = time.perf_counter()
        names = self.canvas.pigment_names
        columns = self.wet_columns()
        q = columns.copy()
        mask = self.footprint(pose, centre_m)
        area = self.cell_size_m**2
        under = q[:, mask].sum(axis=1) * area
        offer = {
            n: self.scene.pickup_fraction * v for n, v in zip(names, under, strict=True) if v > 0
        }
        taken = reservoir.pick_up(offer) if offer else {}
        for p, n in enumerate(names):
            if taken.get(n, 0.0) > 0.0:
                q[p, mask] *= max(1.0 - taken[n] / under[p], 0.0)
        speed = float(np.linalg.norm(np.asarray(centre_m[:2]) - self._last_xy)) / dt_s
        self._last_xy = np.array(centre_m[:2], dtype=float)
        room = np.maximum(self.scene.max_height_m - q.sum(axis=0), 0.0) * mask
        want = deposit_volume(reservoir, speed, pose.pressure, dt_s, self.scene.deposit_length_m)
        request = min(want, (1.0 - 1e-9) * float(room.sum()) * area)
        released = reservoir.deposit(request) if request > 0.0 else {}
        deposited = np.array([released.get(n, 0.0) for n in names])
        if deposited.sum() > 0.0:
            q += deposited[:, None, None] / area * (room / room.sum())[None]
        self.window.write_back(
            self.canvas,
            q - columns,
            self.texture(pose, centre_m),
            gathered=columns,
            sweep_texels=self.sweep_texels(),
        )
        report = ExchangeReport(
            swept_m3=float(under.sum()),
            picked_up_m3=float(sum(taken.values())),
            deposited_m3=float(deposited.sum()),
        )
        return PaintStep(exchange=report, step_ms=1e3 * (time.perf_counter() - start))

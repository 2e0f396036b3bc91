"""The model selector: applies the rules of :mod:`paintapp.paint.choice` sample by sample.

The painting session asks :meth:`ModelSelector.engage` for every sample in contact; it returns
the :class:`~paintapp.paint.choice.Plan` and leaves :attr:`ModelSelector.model` built and touched
down for it (unless the plan is dry). :meth:`ModelSelector.record` counts each step, and every
decision (touch-down, switch, refit, and the solver's own choices the first time a model runs)
goes to :attr:`ModelSelector.decisions` with its reason.
"""

from __future__ import annotations

from brushes import BrushPreset, PaintReservoir, TipPose
from paintapp.canvas.model import Canvas
from paintapp.paint.choice import (
    ChoiceStats,
    Plan,
    TimedDecision,
    layer_thickness_m,
    window_is_dry,
)
from paintapp.paint.columns import square_texel_m
from paintapp.paint.depth_averaged import PaintGridDepthAveraged
from paintapp.paint.fit import GridFit, fit_grid, full_grid, lean_rad, section_radius_m
from paintapp.paint.grid3d import PaintGrid3D
from paintapp.paint.paint_model import ForceNeeds, PaintModel, PaintStep
from paintapp.paint.paint_scene import PaintScene
from paintapp.paint.stamp import StampModel
from solver import Decision, explain

MODEL_CLASSES: dict[str, type[PaintModel]] = {
    "grid3d": PaintGrid3D,
    "depth_averaged": PaintGridDepthAveraged,
    "none": StampModel,
}
#: Solver decisions worth repeating in a painting session's log.
SOLVER_TOPICS = ("grid", "advection", "viscosity", "pressure", "probe forces", "torque")
#: Decisions kept in the log at most (a long live session stops logging, and counts on).
MAX_DECISIONS = 10_000


def build_model(
    scene: PaintScene,
    canvas: Canvas,
    preset: BrushPreset,
    fluid: str,
    fit: GridFit,
    needs: ForceNeeds,
) -> PaintModel:
    """A paint model of kind ``fluid`` with the grid ``fit``."""
    return MODEL_CLASSES[fluid](scene, canvas, preset, cells=fit.cells, needs=needs)  # type: ignore[call-arg]


class ModelSelector:
    """Chooses and builds the paint model for each sample (see :mod:`paintapp.paint.choice`).

    Args:
        scene: the painting scene (its ``choose`` table says what may be left out).
        canvas: the canvas.
        preset: the brush.
        needs: which outputs are read (default: force and torque).
    """

    def __init__(
        self,
        scene: PaintScene,
        canvas: Canvas,
        preset: BrushPreset,
        needs: ForceNeeds | None = None,
    ) -> None:
        self.scene = scene
        self.canvas = canvas
        self.needs = needs or ForceNeeds()
        self.texel_m = square_texel_m(canvas)
        self.decisions: list[TimedDecision] = []
        self.dropped_decisions = 0
        self.stats = ChoiceStats()
        self._explained: set[str] = set()
        self.set_preset(preset)
        for d in self.setup_decisions():
            self.log(None, d)

    # --- set-up -----------------------------------------------------------------------------
    def set_preset(self, preset: BrushPreset) -> None:
        """Paint on with ``preset`` (the brush is in the air)."""
        self.preset = preset
        fluid = "grid3d" if self.scene.fluid_model == "auto" else self.scene.fluid_model
        self.plan: Plan | None = None
        self.model = build_model(
            self.scene, self.canvas, preset, fluid, self._fit(fluid, 0.0), self.needs
        )

    def setup_decisions(self) -> list[Decision]:
        """The session-wide decisions (before any stroke)."""
        s, c = self.scene, self.scene.choose
        out = [
            Decision("air", "no steps", "a brush in the air moves no paint: no solver steps"),
            Decision("outputs", self.needs.describe(), _needs_reason(self.needs)),
        ]
        if s.fluid_model == "auto":
            out.append(
                Decision(
                    "fluid model",
                    "auto: depth_averaged or grid3d per paint layer",
                    f"depth-averaged below {c.thin_below_m * 1e3:.3g} mm of wet paint under the "
                    f"brush, 3D above {c.thick_above_m * 1e3:.3g} mm (hysteresis in between)",
                )
            )
        else:
            out.append(Decision("fluid model", s.fluid_model, "the scene's fluid_model"))
        out.append(
            Decision(
                "dry brush",
                "no fluid" if c.dry_brush else "fluid anyway",
                "an empty brush over dry canvas moves no paint"
                if c.dry_brush
                else "choose.dry_brush = false",
            )
        )
        out.append(
            Decision(
                "grid size",
                "fitted to the brush" if c.fit_grid else "the scene's cells",
                "choose.fit_grid: the contact height and footprint set the cells (same h)"
                if c.fit_grid
                else f"choose.fit_grid = false: {'x'.join(map(str, s.cells))}",
            )
        )
        out.append(
            Decision(
                "pigment channels",
                "only those in use" if c.used_pigments else "all of the canvas's",
                "unused channels are all zero and stay so"
                if c.used_pigments
                else "choose.used_pigments = false",
            )
        )
        return out

    def _fit(self, fluid: str, lean: float) -> GridFit:
        if fluid == "none" or not self.scene.choose.fit_grid:
            return full_grid(self.scene)
        return fit_grid(self.scene, self.preset, self.texel_m, fluid, lean)

    def log(self, t_s: float | None, decision: Decision) -> None:
        """Add a decision to the log (up to :data:`MAX_DECISIONS`)."""
        if len(self.decisions) < MAX_DECISIONS:
            self.decisions.append(TimedDecision(t_s, decision))
        else:
            self.dropped_decisions += 1

    # --- per sample -------------------------------------------------------------------------
    def engage(self, pose: TipPose, reservoir: PaintReservoir, entry: TipPose) -> Plan:
        """Choose the plan for ``pose`` (in contact) and make :attr:`model` ready for it; a
        model that (re)starts touches down at ``entry``. Returns the plan."""
        old = self.plan
        plan, why = self._choose(pose, reservoir)
        self.plan = plan
        same_grid = old is not None and (old.fluid, old.fit.cells) == (plan.fluid, plan.fit.cells)
        if not same_grid:
            self.model.lift(settle=False)  # the brush stays in the paint
            self.model = build_model(
                self.scene, self.canvas, self.preset, plan.fluid, plan.fit, self.needs
            )
        if plan.dry:  # nothing runs; keep the window over the tip (for overlays)
            self.model.window.place(float(pose.position_m[0]), float(pose.position_m[1]))
        elif self.model.pose is None:
            self.model.touch_down(entry)
        self._log_change(pose.t_s, old, plan, why)
        return plan

    def lift(self) -> None:
        """The brush left the paint."""
        self.model.lift()
        self.plan = None

    def _choose(self, pose: TipPose, reservoir: PaintReservoir) -> tuple[Plan, str]:
        old = self.plan
        x, y = float(pose.position_m[0]), float(pose.position_m[1])
        fluid, why = self._fluid_kind(pose, old)
        keep_fit = old is not None and old.fluid == fluid
        keep_fit = keep_fit and lean_rad(pose) <= old.fit.lean_limit_rad  # type: ignore[union-attr]
        fit = old.fit if keep_fit else self._fit(fluid, lean_rad(pose))  # type: ignore[union-attr]
        dry = False
        if self.scene.choose.dry_brush and (old is None or old.dry) and reservoir.is_empty:
            half = 0.5 * max(fit.cells[:2]) * self.model.cell_size_m
            dry = window_is_dry(self.canvas, x, y, half)
            if dry:
                why = f"empty brush, no wet paint within {half * 1e3:.3g} mm: nothing to move"
        elif old is not None and old.dry:
            why = "the brush holds paint" if not reservoir.is_empty else "wet paint in the window"
        return Plan(fluid, fit, dry), why

    def _fluid_kind(self, pose: TipPose, old: Plan | None) -> tuple[str, str]:
        s = self.scene
        if s.fluid_model != "auto":
            return s.fluid_model, "the scene's fluid_model"
        c = s.choose
        radius = section_radius_m(self.preset, s.max_height_m + self.preset.pressure.depth_m)
        x, y = map(float, pose.position_m[:2])
        layer = layer_thickness_m(self.canvas, x, y, radius)
        mm = f"paint layer {layer * 1e3:.3g} mm"
        current = None if old is None or old.dry else old.fluid
        if current == "grid3d" and layer >= c.thin_below_m:
            return "grid3d", f"{mm} >= thin_below {c.thin_below_m * 1e3:.3g} mm"
        if current == "depth_averaged" and layer <= c.thick_above_m:
            return "depth_averaged", f"{mm} <= thick_above {c.thick_above_m * 1e3:.3g} mm"
        if layer < c.thin_below_m:
            return "depth_averaged", f"{mm} < thin_below {c.thin_below_m * 1e3:.3g} mm"
        limit = c.thick_above_m if current else c.thin_below_m
        name = "thick_above" if current else "thin_below"
        return "grid3d", f"{mm} > {name} {limit * 1e3:.3g} mm"

    def _log_change(self, t_s: float, old: Plan | None, plan: Plan, why: str) -> None:
        if old is None:
            reason = why if plan.dry else f"{why}; {plan.fit.reason}"
            self.log(t_s, Decision("touch-down", f"{plan.label} ({self.preset.name})", reason))
        elif old.label != plan.label:
            if old.fluid == plan.fluid and not old.dry and not plan.dry:
                self.stats.refits += 1
                self.log(t_s, Decision("refit", f"{old.label} -> {plan.label}", plan.fit.reason))
            else:
                self.stats.switches += 1
                self.log(t_s, Decision("switch", f"{old.label} -> {plan.label}", why))

    def record(self, plan: Plan, step: PaintStep, t_s: float, dt_s: float) -> None:
        """Count a step taken under ``plan`` at ``t_s`` over ``dt_s`` seconds."""
        kind = "dry" if plan.dry else plan.fluid
        st = self.stats
        st.steps[kind] += 1
        st.grids[plan.label] += 1
        st.solver_steps[kind] += step.solver_steps
        st.stokes_steps[kind] += step.stokes_steps
        # A Counter of float milliseconds: typeshed types Counter values as int only.
        st.step_ms[kind] += step.step_ms  # type: ignore[assignment]
        if not plan.dry and plan.fluid != "none":
            st.channels[step.channels] += 1
            if plan.fluid not in self._explained and getattr(self.model, "sim", None) is not None:
                self._explained.add(plan.fluid)
                for d in explain(self.model.sim, min(dt_s, self.scene.max_step_s)):  # type: ignore[attr-defined]
                    if d.topic in SOLVER_TOPICS:
                        self.log(t_s, Decision(f"{plan.fluid} {d.topic}", d.chosen, d.reason))


def _needs_reason(needs: ForceNeeds) -> str:
    if not needs.force:
        return "the device outputs no force: the solver skips all force work"
    if not needs.torque:
        return "the device outputs no torque: none is published (the servo filters force only)"
    return "the device outputs force and torque"

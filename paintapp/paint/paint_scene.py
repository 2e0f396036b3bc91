"""Painting scenes: which paint model runs and with what paint, as TOML files under
``assets/painting/`` (named by the file stem; a stroke file's header names one, ``null`` is
``default``).

A scene file::

    description = "Oil paint, full 3D paint grid"
    fluid_model = "grid3d"          # grid3d | depth_averaged | none | auto

    [grid]
    cells = [32, 32, 12]            # 3D cells; depth_averaged uses the first two
    span = 2.0                      # the grid spans this many brush widths (sets the cell size)
    margin_cells = 15               # re-centre once the tip is this close to a side (15 of
                                    # 32: every step, see the default scene)
    sides = "slip"                  # grid3d's lateral sides: "slip" walls, or "open" with the
    far_field_cells = 8             # paint through them laid on a band this many columns wide
    max_step_s = 0.05               # longest single solver step; longer gaps are split

    [paint]
    density_kg_m3 = 1400.0
    viscosity_pa_s = 20.0           # oil paint is ~10-100 Pa s (water: 0.001)
    air_viscosity_ratio = 1e-3      # the air above the paint, relative to the paint
    drying_rate_per_s = 0.01        # wetness decays as exp(-rate t)
    max_height_m = 0.002            # depth_averaged: tallest wet column a cell holds
    settle_on_lift = true           # the paint flows back into the tip's footprint at lift-off
    texel_flow = false              # grid3d: true lets the grid's flow move the canvas's texels
                                    # (false: the columns' transported change is spread to them)
    sweep = true                    # a step's change is laid along the path the tip swept
    transfer = "bspline"            # columns <-> texels: "bspline" (no cell lattice) or "tent"
                                    # (half a cell less reach, a faint lattice)
    transport = "fct"               # the paint's transport in the grid: "fct" (flux-corrected:
                                    # fronts a few cells wide) or "upwind" (first order)
    still_rate_per_s = 0.3          # a column changing by less than this share of its paint a
                                    # second holds still (the creep far from the brush); 0: none

    [brush]
    pickup_fraction = 0.3           # share of the wet paint the bristles meet that they soak up
    push = "distance"               # pushed paint: the room nearest the tip's surface, or
                                    # "rings" of cells round it (lumps along drifting ridges)
    deposit_length_m = 0.04         # a loaded brush lays 1/e of its load over this stroke length

    [solver]                        # optional
    pressure_tolerance = 1e-5
    viscosity_tolerance = 1e-4      # forces within 5e-6 (relative) of a 1e-10 solve's
    max_iterations = 400
    boundary_method = "cutcell"     # cutcell | staircase; also pressure_scheme, preconditioner,
                                    # viscosity_preconditioner as in a solver scene

    [choose]                        # optional: what the app may leave out (paintapp.paint.choice)
    thin_below_m = 2e-4             # auto: depth-averaged while the paint layer is thinner...
    thick_above_m = 3e-4            # ...and the 3D grid again once it is thicker (hysteresis)
    dry_brush = true                # no fluid for an empty brush over dry canvas
    fit_grid = false                # size the grid to the brush's footprint, not [grid] cells
    used_pigments = true            # carry only the pigments in use through the grid
    stokes_below_re = 0.0           # no momentum advection while the tip's Reynolds number is
                                    # below this (creeping paint, e.g. 0.1); 0 always advects
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, TypeVar, cast, get_args

from common.errors import InputError
from common.limits import MAX_TOML_BYTES, check_nesting, read_text_capped
from common.tables import Table
from paintapp.resources import asset_path
from solver import SolverSettings, method_keys

#: Kernels that trade paint between the grid's columns and the canvas texels
#: (:func:`paintapp.paint.columns.transfer_weights`).
TransferKernel = Literal["bspline", "tent"]
#: How the grid's flow transports the paint (:func:`solver.advection.scalars.transport`).
TransportScheme = Literal["fct", "upwind"]
#: What the 3D grid's lateral sides are (:mod:`paintapp.paint.far_field`).
SideKind = Literal["slip", "open"]
#: How the paint grid follows the tip (:class:`PaintScene`'s ``follow``).
FollowKind = Literal["cells", "continuous"]
#: How pushed paint finds room round the tip (:mod:`paintapp.paint.nearest_room`).
PushFill = Literal["distance", "rings"]
#: The paint models.
FluidModel = Literal["grid3d", "depth_averaged", "none"]
#: What a scene's ``fluid_model`` may say: a model, or ``auto`` (chosen per sample).
SceneFluidModel = Literal[FluidModel, "auto"]

TRANSFER_KERNELS: tuple[TransferKernel, ...] = get_args(TransferKernel)
TRANSPORT_SCHEMES: tuple[TransportScheme, ...] = get_args(TransportScheme)
SIDE_KINDS: tuple[SideKind, ...] = get_args(SideKind)
FOLLOW_KINDS: tuple[FollowKind, ...] = get_args(FollowKind)
PUSH_FILLS: tuple[PushFill, ...] = get_args(PushFill)
FLUID_MODELS: tuple[FluidModel, ...] = get_args(FluidModel)
SCENE_FLUID_MODELS: tuple[SceneFluidModel, ...] = get_args(SceneFluidModel)
#: :class:`PaintScene`'s string-valued fields: the field, its key in a scene file, its values.
_CHOICES: tuple[tuple[str, str, tuple[str, ...]], ...] = (
    ("fluid_model", "fluid_model", SCENE_FLUID_MODELS),
    ("follow", "grid.follow", FOLLOW_KINDS),
    ("sides", "grid.sides", SIDE_KINDS),
    ("transfer", "paint.transfer", TRANSFER_KERNELS),
    ("transport", "paint.transport", TRANSPORT_SCHEMES),
    ("push", "brush.push", PUSH_FILLS),
)
DEFAULT_SCENE = "default"
MAX_CELLS = 200_000


@dataclass(frozen=True)
class ModelChoice:
    """What the app may leave out of the model (see :mod:`paintapp.paint.choice`).

    Attributes:
        thin_below_m: ``fluid_model = "auto"``: the depth-averaged grid runs while the wet paint
            layer under the brush is thinner than this (m)...
        thick_above_m: ...and the 3D grid again once it is thicker than this (m, >= thin).
        dry_brush: an empty brush over a window with no wet paint takes no fluid steps.
        fit_grid: size the grid to the brush's footprint (fewer cells than ``cells``, same
            cell size) instead of always using ``cells``.
        used_pigments: move only the pigment channels in use (in the window or the brush).
        stokes_below_re: a solver step leaves out the fluid's momentum advection (Stokes flow)
            while the paint's Reynolds number at the tip, ``rho U L / mu`` (U the tip's speed, L
            its footprint's width), is below this; 0 always advects.
    """

    thin_below_m: float = 2e-4
    thick_above_m: float = 3e-4
    dry_brush: bool = True
    fit_grid: bool = False
    used_pigments: bool = True
    stokes_below_re: float = 0.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.thin_below_m <= self.thick_above_m:
            raise InputError(
                "expected 0 <= thin_below_m <= thick_above_m, got "
                f"{self.thin_below_m:g} and {self.thick_above_m:g}",
                key="choose",
            )


#: Everything modelled everywhere: no choice left to the app (the baseline of the savings).
FULL_MODEL = ModelChoice(dry_brush=False, fit_grid=False, used_pigments=False)


@dataclass(frozen=True)
class PaintScene:
    """A validated painting scene (see the module docstring for the file; SI units).

    Attributes:
        name: the scene's name (file stem).
        fluid_model: ``"grid3d"`` (3D paint grid riding with the tip), ``"depth_averaged"``
            (2D grid in the canvas plane, paper section 5.2), ``"none"`` (no fluid: the brush
            stamps and soaks paint directly, and feels no fluid force) or ``"auto"`` (grid3d or
            depth_averaged by the paint layer's thickness, see ``choose``).
        cells: (nx, ny, nz) cells of the 3D grid; the depth-averaged grid uses (nx, ny).
        span: lateral grid extent in brush widths; with the canvas texel size it sets the cell
            size (a whole number of texels, see :func:`paintapp.paint.columns.cell_texels`).
        margin_cells: the grid re-centres when the tip is closer than this to a lateral side
            (a scene file's default: half the grid less one, so every step; the grid's sides
            are slip walls, and a tip whose leading face closes in on one between shifts pushes
            a bow wave that prints a tooth in its trail at every shift).
        follow: how the grid follows the tip: ``"cells"`` (by whole cells, as ``margin_cells``
            says; a scene file without the key) or ``"continuous"`` (the bundled ``default``
            and ``auto`` scenes: the tip at the centre of its middle cell at every step, its
            corner anywhere between texels: the tip keeps its place in its cell, and
            ``margin_cells`` does not apply; the 3D grid with slip sides and the columns'
            transfer only; a fluid model chosen by ``"auto"`` that turns out depth-averaged
            follows by cells, and so does a grid whose cells are a single texel).
        max_step_s: longest solver step, s; a longer gap between stylus samples is split.
        sides: the 3D grid's lateral sides: ``"slip"`` walls (the paint round the window at
            rest), or ``"open"`` (zero pressure; the paint that crosses them is laid on, or taken
            from, a band of ``far_field_cells`` canvas columns beyond each side,
            :mod:`paintapp.paint.far_field`).
        far_field_cells: width of that band, columns (``sides = "open"`` only).
        max_travel_cells: longest lateral travel of the tip in one step, cells; a longer move
            between samples is split into sub-steps, at most ``max_travel_substeps`` of them.
        max_travel_substeps: the most sub-steps a move's travel adds (a live session that falls
            behind must not slow itself down further by sub-stepping ever longer moves).
        density_kg_m3, viscosity_pa_s: the paint's density and dynamic viscosity.
        air_viscosity_ratio: viscosity of the paint-free cells relative to the paint (3D grid).
        drying_rate_per_s: wetness decay rate, 1/s.
        max_height_m: tallest wet paint column a depth-averaged cell accepts from the brush, m.
        settle_on_lift: at lift-off the wet paint flows back into the tip's footprint
            (:meth:`paintapp.paint.paint_model.PaintModel.settle`); False leaves its print.
        texel_flow: the 3D grid's depth-averaged flow moves the canvas's wet paint on the
            texels (:mod:`paintapp.paint.wet_flow`); False transports the paint in the grid's
            columns and spreads each column's change over its texels.
        sweep: a step's change of the canvas paint is laid along the path the tip swept during
            the step, not at its end pose alone (:func:`paintapp.paint.columns_kernels.sweep_change`,
            or :func:`paintapp.paint.share_sweep.sweep_shares` for small cells); False prints one
            tooth per step along a fast stroke.
        transfer: the kernel that trades paint between the grid's columns and the texels
            (:mod:`paintapp.paint.columns`): ``"bspline"`` (quadratic B-spline: no cell lattice)
            or ``"tent"`` (reaches half a cell less beyond a column, but its slope jumps at
            column centres and prints a faint lattice where thin films turn colour).
        transport: how the fluid models' flow transports the paint in their cells
            (:func:`solver.advection.scalars.transport`): ``"fct"`` (flux-corrected: the upwind
            step, then as much of its numerical diffusion taken back as keeps each cell within
            its neighbourhood's range, so a stroke's edge stays a few cells wide as the flow
            pushes it out) or ``"upwind"`` (first order: the edge smears further every step
            the paint moves).
        still_rate_per_s: a fluid model's column whose every pigment changes in a step by less
            than this share of its wet paint per second (times the step) holds still, its change
            given to the columns the brush moves (:mod:`paintapp.paint.still`); 0 writes every
            change, however slow.
        pickup_fraction: share (0..1) of the wet paint met by the bristles that they soak up per
            step (limited by the brush's free room); the rest is pushed aside.
        push: where pushed paint goes: ``"distance"`` (the free room nearest the tip's surface,
            by its signed distance at the cells, continuous as the tip moves through the cells;
            cut-cell tips of the 3D grid, :mod:`paintapp.paint.nearest_room`; the depth-averaged
            grid and voxelized tips push by rings) or ``"rings"`` (rings of cells round the
            tip's cells, which jump by a cell as a face passes a cell centre: lumps along the
            ridges of a tip drifting sideways).
        deposit_length_m: stroke length over which a loaded brush lays down 1 - 1/e of its load.
        solver: solver settings.
        description: free text.
        choose: what the app may leave out (:class:`ModelChoice`).
    """

    name: str = DEFAULT_SCENE
    fluid_model: SceneFluidModel = "grid3d"
    cells: tuple[int, int, int] = (32, 32, 12)
    span: float = 2.0
    margin_cells: int = 15
    follow: FollowKind = "cells"
    sides: SideKind = "slip"
    far_field_cells: int = 8
    max_step_s: float = 0.05
    max_travel_cells: float = 2.0
    max_travel_substeps: int = 2
    density_kg_m3: float = 1400.0
    viscosity_pa_s: float = 20.0
    air_viscosity_ratio: float = 1e-3
    drying_rate_per_s: float = 0.01
    max_height_m: float = 0.002
    settle_on_lift: bool = True
    texel_flow: bool = False
    sweep: bool = True
    transfer: TransferKernel = "bspline"
    transport: TransportScheme = "fct"
    still_rate_per_s: float = 0.3
    pickup_fraction: float = 0.3
    push: PushFill = "distance"
    deposit_length_m: float = 0.04
    solver: SolverSettings = field(
        default_factory=lambda: SolverSettings(
            pressure_tolerance=1e-5, viscosity_tolerance=1e-4, max_iterations=400, warm_start=True
        )
    )
    description: str = ""
    choose: ModelChoice = field(default_factory=ModelChoice)

    def __post_init__(self) -> None:
        for name, key, allowed in _CHOICES:
            value = getattr(self, name)
            if value not in allowed:
                raise InputError(f"expected one of {', '.join(allowed)}, got {value!r}", key=key)
        nx, ny, nz = self.cells
        too_flat = self.fluid_model in ("grid3d", "auto") and nz < 3
        if min(nx, ny) < 8 or too_flat or nx * ny * nz > MAX_CELLS:
            raise InputError(
                f"expected at least 8x8 (3D: 8x8x3) and at most {MAX_CELLS} cells, got {self.cells}",
                key="grid.cells",
            )
        if not 0 <= self.margin_cells < min(nx, ny) // 2:
            raise InputError(
                f"expected 0 <= margin_cells < half the grid ({min(nx, ny) // 2}), "
                f"got {self.margin_cells}",
                key="grid.margin_cells",
            )
        if self.follow == "continuous" and (
            self.fluid_model not in ("grid3d", "auto") or self.sides != "slip" or self.texel_flow
        ):
            if self.sides != "slip":
                why = 'sides = "open"'
            elif self.texel_flow:
                why = "texel_flow = true"
            else:
                why = f"fluid_model = {self.fluid_model!r}"
            raise InputError(
                f'expected follow = "cells" with {why} (only the 3D grid with slip sides and '
                "the columns' transfer follows the tip continuously)",
                key="grid.follow",
            )
        if self.sides == "open" and self.fluid_model not in ("grid3d", "auto"):
            raise InputError(
                f'expected sides = "slip" with fluid_model = {self.fluid_model!r} (only the 3D '
                "grid has open sides)",
                key="grid.sides",
            )
        if self.sides == "open" and self.texel_flow:
            raise InputError(
                'expected sides = "slip" with texel_flow = true (the texels\' flow has no open '
                "sides)",
                key="grid.sides",
            )
        if not 1 <= self.far_field_cells <= max(nx, ny):
            raise InputError(
                f"expected 1 <= far_field_cells <= the grid's cells ({max(nx, ny)}), "
                f"got {self.far_field_cells}",
                key="grid.far_field_cells",
            )

    @property
    def air_viscosity_pa_s(self) -> float:
        """Dynamic viscosity of the paint-free cells, Pa s."""
        return self.viscosity_pa_s * self.air_viscosity_ratio


def parse_paint_scene(data: dict, name: str, source: str = "<scene>") -> PaintScene:
    """Validate a parsed scene table; :class:`InputError` names the file and key."""
    top = Table(data, source, "")
    description = top.string("description", "")
    model = _choice(top, "fluid_model", "grid3d", SCENE_FLUID_MODELS)
    grid, paint = top.table("grid", {}), top.table("paint", {})
    brush, solver = top.table("brush", {}), top.table("solver", {})
    choose = top.table("choose", {})
    cells = grid.raw("cells", [32, 32, 12])
    if not (
        isinstance(cells, list) and len(cells) == 3 and all(type(c) is int and c > 0 for c in cells)
    ):
        raise grid.error("cells", f"expected three positive integers, got {cells!r}")
    scene = PaintScene(
        name=name,
        fluid_model=model,
        cells=(cells[0], cells[1], cells[2]),
        span=grid.number("span", 2.0, minimum=1.0, maximum=8.0),
        margin_cells=grid.integer(
            "margin_cells", max(0, min(cells[0], cells[1]) // 2 - 1), minimum=0
        ),
        follow=_choice(grid, "follow", "cells", FOLLOW_KINDS),
        sides=_choice(grid, "sides", "slip", SIDE_KINDS),
        far_field_cells=grid.integer("far_field_cells", 8, minimum=1),
        max_step_s=grid.number("max_step_s", 0.05, minimum=1e-4, maximum=1.0),
        max_travel_cells=grid.number("max_travel_cells", 2.0, minimum=0.1, maximum=100.0),
        max_travel_substeps=grid.integer("max_travel_substeps", 2, minimum=1, maximum=64),
        density_kg_m3=paint.number("density_kg_m3", 1400.0, minimum=1.0, maximum=1e5),
        viscosity_pa_s=paint.number("viscosity_pa_s", 20.0, minimum=1e-4, maximum=1e4),
        air_viscosity_ratio=paint.number("air_viscosity_ratio", 1e-3, minimum=1e-6, maximum=1.0),
        drying_rate_per_s=paint.number("drying_rate_per_s", 0.01, minimum=0.0, maximum=100.0),
        max_height_m=paint.number(
            "max_height_m", 0.002, minimum=1e-5, exclusive=True, maximum=0.05
        ),
        settle_on_lift=paint.boolean("settle_on_lift", True),
        texel_flow=paint.boolean("texel_flow", False),
        sweep=paint.boolean("sweep", True),
        transfer=_choice(paint, "transfer", "bspline", TRANSFER_KERNELS),
        transport=_choice(paint, "transport", "fct", TRANSPORT_SCHEMES),
        still_rate_per_s=paint.number("still_rate_per_s", 0.3, minimum=0.0, maximum=10.0),
        pickup_fraction=brush.number("pickup_fraction", 0.3, minimum=0.0, maximum=1.0),
        push=_choice(brush, "push", "distance", PUSH_FILLS),
        deposit_length_m=brush.number("deposit_length_m", 0.04, minimum=1e-3, maximum=10.0),
        solver=SolverSettings(
            pressure_tolerance=solver.number("pressure_tolerance", 1e-5, minimum=1e-12),
            viscosity_tolerance=solver.number("viscosity_tolerance", 1e-4, minimum=1e-12),
            max_iterations=solver.integer("max_iterations", 400, minimum=1),
            **method_keys(solver),
            warm_start=solver.boolean("warm_start", True),
        ),
        description=description,
        choose=parse_choice(choose),
    )
    for table in (grid, paint, brush, solver, choose, top):
        table.finish()
    return scene


Mode = TypeVar("Mode", bound=str)


def _choice(t: Table, key: str, default: str, choices: tuple[Mode, ...]) -> Mode:
    """The string at ``key`` (``default`` when absent), one of ``choices``: the table's error
    names the file, the key and the choices otherwise."""
    value = t.string(key, default, choices=choices)
    return cast(Mode, value)  # one of ``choices``: checked just above


def parse_choice(table: Table) -> ModelChoice:
    """The scene's ``[choose]`` table (every key optional)."""
    thin = table.number("thin_below_m", 2e-4, minimum=0.0, maximum=0.05)
    thick = table.number("thick_above_m", max(thin, 3e-4), minimum=0.0, maximum=0.05)
    if thick < thin:
        raise table.error("thick_above_m", f"expected >= thin_below_m ({thin:g}), got {thick:g}")
    return ModelChoice(
        thin_below_m=thin,
        thick_above_m=thick,
        dry_brush=table.boolean("dry_brush", True),
        fit_grid=table.boolean("fit_grid", False),
        used_pigments=table.boolean("used_pigments", True),
        stokes_below_re=table.number("stokes_below_re", 0.0, minimum=0.0, maximum=1.0),
    )


def load_paint_scene_file(path: str | Path) -> PaintScene:
    """Read and validate a scene file; its name is the file stem."""
    path = Path(path)
    source = str(path)
    try:
        text = read_text_capped(path, MAX_TOML_BYTES, "painting scene file", encoding="utf-8")
        check_nesting(text, source, toml=True)
        data = tomllib.loads(text)
    except FileNotFoundError:
        raise InputError("no such painting scene file", source) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the painting scene: {exc}", source) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML: {exc}", source) from None
    try:
        return parse_paint_scene(data, path.stem, source)
    except InputError as exc:
        raise InputError(exc.message, exc.source or source, exc.key, exc.line) from None


def scene_directory() -> Path:
    """Where the bundled painting scenes live."""
    return asset_path("painting")


def list_paint_scenes() -> list[str]:
    """Names of the bundled painting scenes."""
    return sorted(p.stem for p in scene_directory().glob("*.toml"))


def load_paint_scene(name_or_path: str | Path | None = None) -> PaintScene:
    """A bundled scene by name (None: ``default``), or a scene file when given a ``.toml`` path."""
    if name_or_path is None:
        name_or_path = DEFAULT_SCENE
    text = str(name_or_path)
    if text.endswith(".toml"):
        return load_paint_scene_file(text)
    path = scene_directory() / f"{text}.toml"
    if not path.is_file():
        known = ", ".join(list_paint_scenes()) or "none"
        raise InputError(f"unknown painting scene {text!r}; known scenes: {known}", key="scene")
    return load_paint_scene_file(path)

"""Scene files (TOML, schema version 1): domain, fluid, boundaries, probes, run, outputs.

The schema is a contract shared with other tools; see the README for the full description.
Every problem is reported as an :class:`~common.errors.InputError` naming the file and key.
"""

from __future__ import annotations

import itertools
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypedDict, TypeVar, cast

import numpy as np

from common import quaternion
from common.errors import InputError
from common.limits import MAX_TOML_BYTES, check_nesting, read_bytes_capped
from common.tables import Table
from solver.boundary import KIND_NAMES, SIDE_NAMES, DomainBoundary, Side
from solver.compiled.threads import MAX_THREADS
from solver.grid import Grid
from solver.probes import PATH_INTERPOLATIONS, Probe
from solver.settings import (
    ADVECTION_CHOICES,
    BOUNDARY_METHODS,
    FORCE_MODELS,
    MAX_CORNER_RADIUS_CELLS,
    PRECONDITIONERS,
    PRESSURE_SCHEMES,
    VISCOSITY_PRECONDITIONERS,
    VISCOSITY_TOLERANCE,
    BoundaryMethod,
    Preconditioner,
    PressureScheme,
    ViscosityPreconditioner,
)
from solver.shapes import Ball, Box
from solver.simulation import Fluid, Simulation, SolverSettings

SCHEMA_VERSION = 1
MAX_CELLS = 64_000_000
MAX_STEPS = 1_000_000_000
#: Smallest time step, seconds: below it the step's arithmetic (1/dt, CFL numbers) overflows
#: long before a run could mean anything.
MIN_DT_S = 1e-9
#: Most points an output line may sample, and most iterations a solve may be allowed.
MAX_LINE_POINTS = 100_000
MAX_ITERATIONS = 1_000_000
CELL_SIZE_RANGE_M = (1e-9, 1e9)  # beyond it h^2 and h^3 leave floating point's safe range


@dataclass(frozen=True)
class RunSpec:
    """Time step (s) and the number of steps to take."""

    dt_s: float
    steps: int


@dataclass(frozen=True)
class LineOutput:
    name: str
    start_m: tuple[float, ...]
    end_m: tuple[float, ...]
    points: int


@dataclass(frozen=True)
class PointOutput:
    name: str
    at_m: tuple[float, ...]


@dataclass
class Scene:
    """A parsed scene: everything needed to build and run a :class:`Simulation`."""

    source: str
    name: str
    grid: Grid
    fluid: Fluid
    boundary: DomainBoundary
    probes: list[Probe]
    settings: SolverSettings
    run: RunSpec
    lines: list[LineOutput] = field(default_factory=list)
    points: list[PointOutput] = field(default_factory=list)

    def build(self) -> Simulation:
        """A fresh simulation of this scene (probes are copied, so a scene can be run twice)."""
        probes = [
            Probe(
                p.name,
                p.shape,
                p.dim,
                p.centre_m,
                p.orientation,
                p.velocity_m_s,
                p.angular_velocity_rad_s,
                p.path,
                p.reference_m,
                p.path_interpolation,
            )
            for p in self.probes
        ]
        return Simulation(self.grid, self.fluid, self.boundary, probes, self.settings)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file."""
    source = str(path)
    try:
        raw = read_bytes_capped(path, MAX_TOML_BYTES, "scene file")
    except OSError as exc:
        raise InputError(f"cannot read scene file: {exc.strerror}", source) from None
    try:
        text = raw.decode("utf-8-sig")  # a byte order mark (Windows editors write one) is skipped
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InputError("scene file is not UTF-8 text", source, line=line) from None
    check_nesting(text, source, toml=True)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        at = re.search(r"at line (\d+)", str(exc))
        line = int(at.group(1)) if at else text.count("\n") + 1  # "at end of document"
        raise InputError(f"not valid TOML: {exc}", source, line=line) from None
    return parse_scene(data, source)


def parse_scene(data: dict, source: str = "<scene>") -> Scene:
    """Validate a scene given as nested dicts (as TOML loads it)."""
    top = Table(data, source, "")
    version = top.integer("version", SCHEMA_VERSION, minimum=1)
    if version != SCHEMA_VERSION:
        raise top.error("version", f"expected schema version {SCHEMA_VERSION}, got {version}")
    name = top.string("name", Path(source).stem)
    top.string("description", "")
    grid = _grid(top.table("domain"))
    fluid = _fluid(top.table("fluid"), grid.dim)
    boundary = _boundary(top.table("boundary", {}), grid)
    probes = [_probe(t, grid) for t in top.tables("probes")]
    names = [p.name for p in probes]
    if len(set(names)) != len(names):
        raise top.error("probes", f"probe names must be unique, got {names}")
    settings = _settings(top.table("solver", {}))
    run = _run(top.table("run"))
    out = top.table("output", {})
    line_tables, point_tables = out.tables("lines"), out.tables("points")
    lines = [_line(t, grid) for t in line_tables]
    points = [PointOutput(t.string("name"), _point(t, "at", grid)) for t in point_tables]
    for t in [*line_tables, *point_tables]:
        t.finish()
    out.finish()
    top.finish()
    return Scene(source, name, grid, fluid, boundary, probes, settings, run, lines, points)


def _grid(t: Table) -> Grid:
    size = t.raw("size")
    if not isinstance(size, list) or len(size) not in (2, 3):
        raise t.error("size", f"expected 2 (2D) or 3 (3D) numbers in metres, got {size!r}")
    dim = len(size)
    size_m = t.vector("size", dim, positive=True)
    cells = t.raw("cells")
    if (
        not isinstance(cells, list)
        or len(cells) != dim
        or any(isinstance(c, bool) or not isinstance(c, int) or c < 1 for c in cells)
    ):
        raise t.error("cells", f"expected {dim} integers >= 1 (one per axis), got {cells!r}")
    if any(c < 3 for c in cells):
        raise t.error("cells", f"expected at least 3 cells per axis, got {cells}")
    if math.prod(cells) > MAX_CELLS:
        raise t.error("cells", f"expected at most {MAX_CELLS} cells in all, got {math.prod(cells)}")
    hs = [s / c for s, c in zip(size_m, cells, strict=True)]
    if max(hs) - min(hs) > 1e-6 * max(hs):
        sizes = ", ".join(f"{h:.6g}" for h in hs)
        raise t.error("cells", f"cell size must be equal on every axis; size/cells gives {sizes} m")
    lo, hi = CELL_SIZE_RANGE_M
    if not lo <= hs[0] <= hi:
        raise t.error("size", f"cell size size/cells = {hs[0]:.3g} m is outside [{lo:g}, {hi:g}] m")
    t.finish()
    return Grid.from_size(size_m, tuple(cells))


def _fluid(t: Table, dim: int) -> Fluid:
    rho = t.number("density", minimum=0.0, exclusive=True)
    nu = t.number("viscosity", minimum=0.0)
    body = t.vector("body_force", dim, (0.0,) * dim)
    t.finish()
    return Fluid(rho, nu, tuple(body) + (0.0,) * (3 - dim))  # type: ignore[arg-type]


def _boundary(t: Table, grid: Grid) -> DomainBoundary:
    sides = {}
    allowed = SIDE_NAMES[: 2 * grid.dim]
    for name in list(t.data):
        if name not in allowed:
            raise t.error(
                name, f"is not a side of a {grid.dim}D domain; expected one of {', '.join(allowed)}"
            )
        s = t.table(name)
        kind = s.string("kind", "wall", choices=list(KIND_NAMES))
        vel = s.vector("velocity", grid.dim, (0.0,) * grid.dim)
        profile = s.string("profile", "uniform", choices=["uniform", "parabolic"])
        axis = allowed.index(name) // 2
        if kind in ("wall", "slip") and vel[axis] != 0.0:
            raise s.error(
                "velocity",
                f"a {kind} cannot move along its normal (component "
                f'{axis} must be 0); use kind = "inflow" to push fluid in',
            )
        if kind != "inflow" and s.has("profile"):
            raise s.error("profile", "only an inflow side has a profile")
        s.finish()
        sides[name] = Side(kind, vel, profile)
    return DomainBoundary(grid, sides)


def _probe(t: Table, grid: Grid) -> Probe:
    dim = grid.dim
    name = t.string("name")
    shapes = ("circle", "box") if dim == 2 else ("sphere", "box")
    kind = t.string("shape", choices=shapes)
    shape: Ball | Box
    orientation: float | np.ndarray
    omega: float | np.ndarray
    if kind == "box":
        shape = Box(t.vector("size", dim, positive=True))
    else:
        shape = Ball(t.number("radius", minimum=0.0, exclusive=True))
    centre = np.array(_point(t, "center", grid))
    if dim == 2:
        orientation = t.number("angle", 0.0)
        omega = t.number("angular_velocity", 0.0)
    else:
        q = np.array(t.vector("orientation", 4, (1.0, 0.0, 0.0, 0.0)))
        if not _normable(q):
            raise t.error("orientation", "expected a non-zero quaternion [w, x, y, z]")
        orientation = q / np.linalg.norm(q)
        omega = np.array(t.vector("angular_velocity", 3, (0.0, 0.0, 0.0)))
    _check_fluid_left(t, grid, shape, centre, orientation, "size" if kind == "box" else "radius")
    velocity = np.array(t.vector("velocity", dim, (0.0,) * dim))
    reference = np.array(t.vector("reference", dim, (0.0,) * dim))
    path = _path(t, grid) if t.has("path") else None
    interpolation = _choice(t, "path_interpolation", "linear", PATH_INTERPOLATIONS)
    t.finish()
    return Probe(
        name, shape, dim, centre, orientation, velocity, omega, path, reference, interpolation
    )


def _check_fluid_left(
    t: Table,
    grid: Grid,
    shape: Ball | Box,
    centre: np.ndarray,
    orientation: float | np.ndarray,
    key: str,
) -> None:
    """Refuse a probe that covers the whole domain: with every corner inside the (convex) probe,
    no fluid cell is left and every force would read 0."""
    lo = np.asarray(grid.origin_m[: grid.dim], dtype=float)
    corners = np.array(list(itertools.product(*zip(lo, lo + grid.size_m, strict=True))))
    rotation = quaternion.rotation_matrix(grid.dim, orientation)
    with np.errstate(over="ignore", invalid="ignore"):
        inside = shape.sdf_numpy((corners - centre) @ rotation) <= 0.0
    if np.all(inside):
        raise t.error(key, "the probe covers the whole domain: no fluid is left")


def _path(t: Table, grid: Grid) -> np.ndarray:
    dim = grid.dim
    width = 1 + dim + (1 if dim == 2 else 4)
    rows = t.raw("path")
    layout = "t, x, y, angle" if dim == 2 else "t, x, y, z, qw, qx, qy, qz"
    if not isinstance(rows, list) or not rows:
        raise t.error("path", f"expected a list of keyframes [{layout}]")
    out = np.zeros((len(rows), width))
    for n, row in enumerate(rows):
        if (
            not isinstance(row, list)
            or len(row) != width
            or not all(_finite_number(v) for v in row)
        ):
            raise t.error(f"path[{n}]", f"expected {width} finite numbers [{layout}], got {row!r}")
        out[n] = row
        if not _inside(out[n, 1 : 1 + dim], grid):
            raise t.error(f"path[{n}]", "keyframe position lies outside the domain")
        if dim == 3 and not _normable(out[n, 4:]):
            raise t.error(f"path[{n}]", "expected a non-zero quaternion")
    if np.any(np.diff(out[:, 0]) <= 0):
        raise t.error("path", "keyframe times must increase strictly")
    return out


def _normable(q: np.ndarray) -> bool:
    """Whether ``q`` has a finite, non-zero length (huge components overflow it)."""
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(q))
    return math.isfinite(norm) and norm > 0.0


def _finite_number(value: object) -> bool:
    """A finite int or float (an integer too large for a float is not)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _inside(p: np.ndarray | tuple[float, ...], grid: Grid) -> bool:
    p = np.asarray(p)
    return bool(np.all(p >= 0.0) and np.all(p <= grid.size_m))


def _point(t: Table, key: str, grid: Grid) -> tuple[float, ...]:
    p = t.vector(key, grid.dim)
    if not _inside(p, grid):
        size = ", ".join(f"{s:g}" for s in grid.size_m)
        raise t.error(key, f"point {list(p)} lies outside the domain [0, ({size})] m")
    return p


def _line(t: Table, grid: Grid) -> LineOutput:
    return LineOutput(
        t.string("name"),
        _point(t, "start", grid),
        _point(t, "end", grid),
        t.integer("points", 17, minimum=2, maximum=MAX_LINE_POINTS),
    )


def _settings(t: Table) -> SolverSettings:
    s = SolverSettings(
        advection=_choice(t, "advection", "linear", ADVECTION_CHOICES),
        pressure_tolerance=t.number(
            "pressure_tolerance", 1e-6, minimum=0.0, exclusive=True, maximum=1.0
        ),
        viscosity_tolerance=t.number(
            "viscosity_tolerance", VISCOSITY_TOLERANCE, minimum=0.0, exclusive=True, maximum=1.0
        ),
        max_iterations=t.integer("max_iterations", 1000, minimum=1, maximum=MAX_ITERATIONS),
        force_model=_choice(t, "force_model", "stress", FORCE_MODELS),
        drag_coefficient=t.number("drag_coefficient", 1.0, minimum=0.0),
        **method_keys(t),
        warm_start=t.boolean("warm_start", False),
    )
    t.finish()
    return s


class MethodKeys(TypedDict):
    """Keyword arguments of :class:`SolverSettings` for its boundary method, pressure scheme and
    preconditioners."""

    boundary_method: BoundaryMethod
    corner_radius_cells: float
    pressure_scheme: PressureScheme
    preconditioner: Preconditioner
    viscosity_preconditioner: ViscosityPreconditioner
    threads: int


def method_keys(t: Table) -> MethodKeys:
    """The ``boundary_method``, ``corner_radius_cells``, ``pressure_scheme``, ``preconditioner``,
    ``viscosity_preconditioner`` and ``threads`` keys of a ``[solver]`` table (a scene's or a
    paint scene's), defaults filled in, choices and ranges checked."""
    return MethodKeys(
        boundary_method=_choice(
            t, "boundary_method", SolverSettings.boundary_method, BOUNDARY_METHODS
        ),
        corner_radius_cells=t.number(
            "corner_radius_cells",
            SolverSettings.corner_radius_cells,
            minimum=0.0,
            maximum=MAX_CORNER_RADIUS_CELLS,
            hint=" (cells)",
        ),
        pressure_scheme=_choice(
            t, "pressure_scheme", SolverSettings.pressure_scheme, PRESSURE_SCHEMES
        ),
        preconditioner=_choice(t, "preconditioner", SolverSettings.preconditioner, PRECONDITIONERS),
        viscosity_preconditioner=_choice(
            t,
            "viscosity_preconditioner",
            SolverSettings.viscosity_preconditioner,
            VISCOSITY_PRECONDITIONERS,
        ),
        threads=t.integer("threads", SolverSettings.threads, minimum=0, maximum=MAX_THREADS),
    )


Mode = TypeVar("Mode", bound=str)


def _choice(t: Table, key: str, default: str, choices: tuple[Mode, ...]) -> Mode:
    """The string at ``key`` (``default`` when absent), one of ``choices``: the table's error
    names the file, the key and the choices otherwise."""
    value = t.string(key, default, choices=choices)
    return cast(Mode, value)  # one of ``choices``: checked just above


def _run(t: Table) -> RunSpec:
    dt = t.number("dt", minimum=0.0, exclusive=True)
    if dt < MIN_DT_S:
        raise t.error("dt", f"expected a time step of at least {MIN_DT_S:g} s, got {dt:g}")
    if t.has("steps") and t.has("duration"):
        raise t.error("steps", "give either duration or steps, not both")
    if t.has("steps"):
        steps = t.integer("steps", minimum=1)
        if steps > MAX_STEPS:
            raise t.error("steps", f"expected at most {MAX_STEPS} steps, got {steps}")
    else:
        duration = t.number("duration", minimum=0.0, exclusive=True)
        ratio = duration / dt
        if not ratio <= MAX_STEPS:
            raise t.error(
                "duration", f"duration / dt = {ratio:.3g} steps; expected at most {MAX_STEPS}"
            )
        steps = max(1, round(ratio))
    t.finish()
    return RunSpec(dt, steps)

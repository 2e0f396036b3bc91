"""What a run will cost before it starts: memory against what the machine has, and time per step.

Both are rough estimates, calibrated from peak resident memory and median step times of 2D and
3D scenes (the calibration is in ``docs/performance.md``).

Memory is :data:`BYTES_PER_CELL` per cell (the field arrays, labels, probe masks and the solvers'
work vectors, with a margin) plus the recorded results (a time and each probe's force, torque and
its parts per step). What is available is the least of ``MemAvailable``, a cgroup's limit and an
address-space limit (``ulimit -v``). A step costs a fixed amount per cell plus one PCG iteration
per cell per pressure iteration, and the MIC(0)-preconditioned pressure solve needs a number of
iterations that grows with the cells along the longest axis. :func:`check_memory` refuses a scene
whose estimate exceeds the memory available now; :func:`slow_step_warning` says so before a run
whose steps will take more than :data:`SLOW_STEP_S` each.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

from common.errors import InputError

if TYPE_CHECKING:
    from solver.grid import Grid
    from solver.scenes.scene import Scene

#: Bytes per cell while a scene runs (the calibration's largest, rounded up).
BYTES_PER_CELL = 200
#: Bytes of recorded results per step, and per probe per step.
BYTES_PER_STEP = 40
BYTES_PER_PROBE_STEP = 700
#: Seconds per cell per step outside the pressure solve (2D, 3D), and per cell per PCG iteration.
CELL_STEP_S = {2: 0.5e-6, 3: 2.0e-6}
CELL_ITERATION_S = 40e-9
#: Pressure iterations per cell along the longest axis (2D, 3D).
ITERATIONS_PER_AXIS_CELL = {2: 0.55, 3: 0.9}
#: A step estimated to take longer than this (s) is announced before the run.
SLOW_STEP_S = 5.0


def _cells(grid: Grid) -> tuple[int, ...]:
    return tuple(int(c) for c in grid.cells[: grid.dim])


def estimate_bytes(grid: Grid, steps: int = 0, probes: int = 0) -> int:
    """Bytes a run of ``steps`` steps with ``probes`` probes on ``grid`` needs, roughly."""
    cells = math.prod(_cells(grid))
    return BYTES_PER_CELL * cells + steps * (BYTES_PER_STEP + BYTES_PER_PROBE_STEP * probes)


def estimate_step_s(grid: Grid) -> float:
    """Seconds one step on ``grid`` takes, roughly (see the module docstring)."""
    cells = _cells(grid)
    dim = len(cells)
    iterations = ITERATIONS_PER_AXIS_CELL[dim] * max(cells)
    return math.prod(cells) * (CELL_STEP_S[dim] + CELL_ITERATION_S * iterations)


def _read_int(path: str) -> int | None:
    try:
        text = Path(path).read_text().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def available_memory_bytes() -> int | None:
    """Memory available to this process now (bytes), or None when it cannot be told."""
    found: list[int] = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                found.append(int(line.split()[1]) * 1024)
                break
    except (OSError, ValueError, IndexError):
        pass
    if not found:
        try:
            found.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (AttributeError, OSError, ValueError):
            pass
    limit = _read_int("/sys/fs/cgroup/memory.max")  # cgroup v2; "max" when unlimited
    used = _read_int("/sys/fs/cgroup/memory.current")
    if limit is not None and used is not None:
        found.append(max(limit - used, 0))
    address_space = _address_space_left()
    if address_space is not None:
        found.append(address_space)
    return min(found) if found else None


def _address_space_left() -> int | None:
    """What an address-space limit (``ulimit -v``) leaves this process, if one is set."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, OSError, ValueError):
        return None
    if soft == resource.RLIM_INFINITY:
        return None
    size = 0
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmSize:"):
                size = int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return max(soft - size, 0)


def size_text(n_bytes: float) -> str:
    """``n_bytes`` in MB or GB for a message."""
    return f"{n_bytes / 1e9:.1f} GB" if n_bytes >= 1e9 else f"{n_bytes / 1e6:.0f} MB"


def grid_text(grid: Grid) -> str:
    """E.g. ``2D 128x128 grid (16,384 cells)``."""
    cells = _cells(grid)
    return f"{grid.dim}D {'x'.join(map(str, cells))} grid ({math.prod(cells):,} cells)"


def check_memory(scene: Scene, available: int | None = None) -> int:
    """Raise :class:`InputError` (file, ``domain.cells``) when ``scene`` needs more memory than
    is ``available`` (default: what the machine has now); returns the estimate in bytes."""
    need = estimate_bytes(scene.grid, scene.run.steps, len(scene.probes))
    have = available_memory_bytes() if available is None else available
    if have is not None and need > have:
        results = need - estimate_bytes(scene.grid) > 0.1 * need
        steps = f" with the results of {scene.run.steps:,} steps" if results else ""
        raise InputError(
            f"a {grid_text(scene.grid)} needs about {size_text(need)} of memory{steps}; this "
            f"machine has {size_text(have)} available; use fewer cells"
            + (" or steps" if results else ""),
            scene.source,
            "run" if results else "domain.cells",
        )
    return need


def slow_step_warning(scene: Scene) -> str | None:
    """A warning to print before running ``scene`` when its steps will be slow, else None."""
    step_s = estimate_step_s(scene.grid)
    if step_s <= SLOW_STEP_S:
        return None
    total = step_s * scene.run.steps
    return (
        f"warning: {scene.source}: a {grid_text(scene.grid)} takes roughly "
        f"{_duration(step_s)} per step on a 2-core machine, {_duration(total)} for "
        f"{scene.run.steps:,} step{'s' if scene.run.steps != 1 else ''}; fewer cells (or "
        "--steps N for a quick look) run sooner"
    )


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"

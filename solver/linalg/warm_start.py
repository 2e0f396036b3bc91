"""A linear solve started from the solution it found a step before (``SolverSettings.warm_start``).

On a grid that rides with its probe (the painting grid follows the brush's tip), the flow round the
probe changes little from one step to the next: each velocity component's viscosity solve and the
pressure increment's start nearer their solutions from the last step's solutions, moved with the
grid, than from the advected velocity and a zero increment. Where a probe crosses a fixed grid the
advected velocity is the better start, so it is off unless a scene asks.

The pressure starts warm only where the domain has an outflow side: a closed domain's pressure is
fixed only up to a constant, and a start carried over from step to step carries its constant into
the incremental pressure, which the next step's gradient takes against the entries held at 0.

The solve and its tolerance are unchanged: the result meets the same residual test from another
start, so it differs from a cold start's within that tolerance.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from solver.linalg.pcg import LinearSolve, SolveReport, StencilSystem


class WarmStart:
    """One solve's last solution, which the next solve starts from on its unknowns."""

    def __init__(self) -> None:
        self.last: np.ndarray | None = None

    def solve(
        self,
        linear_solve: LinearSolve,
        system: StencilSystem,
        b: np.ndarray,
        x: np.ndarray,
        tol: float,
        max_iter: int,
    ) -> SolveReport:
        """``linear_solve(system, b, x, tol, max_iter)`` with ``x`` taking the last solution on
        the system's unknowns first (its other entries, a caller's boundary values, stay as
        they are); keeps this solution for the next solve."""
        if self.last is not None and self.last.shape == x.shape:
            # an active entry with an empty row is no unknown either: solves leave it as it is
            np.copyto(x, self.last, where=system.active & (system.diag > 0.0))
        report = linear_solve(system, b, x, tol, max_iter)
        if self.last is None or self.last.shape != x.shape:
            self.last = np.empty_like(x)
        np.copyto(self.last, x)
        return report

    def move(self, shift: Callable[[np.ndarray], np.ndarray]) -> None:
        """Move the kept solution with the grid (``shift`` does to it what the grid's move does
        to the fields)."""
        if self.last is not None:
            self.last = shift(self.last)

    def forget(self) -> None:
        """Start the next solve from the caller's start alone."""
        self.last = None

"""A simulation whose dynamic viscosity is a field over the cells (for example paint and air).

Every :class:`~solver.simulation.Simulation` carries a per-cell viscosity field
(``set_viscosity``) and an optional linear drag (``set_drag``); this name is kept for the
painting grid, which uses both.
"""

from __future__ import annotations

from solver.simulation import Simulation


class VariableViscositySimulation(Simulation):
    """A :class:`Simulation` whose viscosity field the caller sets between steps."""

"""Between ways of doing the same work, the one that has been cheapest lately, by measurement.

The pressure solve of a large 3D grid can run its multigrid's passes on two threads or on one,
with the same bits (:mod:`solver.compiled.parallel`). On two free cores the threads win; with the
other core busy, each of the solve's many short parallel loops waits for a thread the OS has not
scheduled yet, and one thread wins. Which holds depends on what else the machine runs at the
moment, so the automatic setting measures (:class:`TimedChoice`): every option is tried first;
then the one whose last few costs have the lowest median runs, and every ``probe_every``-th
choice runs the other (cheapest of the rest) once more, so that a change of circumstances is
noticed. A best option that turns slow loses its place as soon as its median says so.
"""

from __future__ import annotations

import math
import statistics
from collections import deque

#: Every this many choices, an option that is not the cheapest is run again.
PROBE_EVERY = 25
#: Costs kept per option (their median is its cost).
WINDOW = 3


class TimedChoice:
    """Chooses among ``options`` ways of doing the same work by their recent costs (module
    docstring). Call :meth:`pick`, do the work that way, then :meth:`record` its cost (seconds
    per unit of work: the units make choices of different sizes comparable)."""

    def __init__(self, options: int = 2, probe_every: int = PROBE_EVERY, window: int = WINDOW):
        if options < 1 or probe_every < 2 or window < 1:
            raise ValueError(
                f"need options >= 1, probe_every >= 2, window >= 1; got {options}, "
                f"{probe_every}, {window}"
            )
        self.probe_every = int(probe_every)
        self._costs: list[deque[float]] = [deque(maxlen=window) for _ in range(options)]
        self._picks = 0

    def cost(self, option: int) -> float | None:
        """The median of ``option``'s recent costs, or None before it has one."""
        costs = self._costs[option]
        return statistics.median(costs) if costs else None

    def best(self) -> int | None:
        """The option with the lowest cost so far (the first on a tie), None while some option
        is untried."""
        costs = [self.cost(o) for o in range(len(self._costs))]
        if any(c is None for c in costs):
            return None
        return min(range(len(costs)), key=lambda o: costs[o])  # type: ignore[return-value, arg-type]

    def pick(self) -> int:
        """The option to use now."""
        self._picks += 1
        for option, costs in enumerate(self._costs):
            if not costs:
                return option
        best = self.best()
        assert best is not None
        if len(self._costs) > 1 and self._picks % self.probe_every == 0:
            others = [o for o in range(len(self._costs)) if o != best]
            return min(others, key=lambda o: self.cost(o))  # type: ignore[arg-type, return-value]
        return best

    def record(self, option: int, cost: float) -> None:
        """The cost of one use of ``option``; a cost that is not finite and non-negative (a
        clock that went back, a failed solve) is ignored."""
        if math.isfinite(cost) and cost >= 0.0:
            self._costs[option].append(float(cost))

"""Kernels compiled twice: on the calling thread, and with their ``prange`` loops on numba's threads.

A kernel body written with ``numba.prange`` for its outermost loop is compiled once as a plain
serial kernel (``prange`` is ``range`` there) and once with ``parallel=True``
(:func:`serial_and_parallel`). A body whose iterations write disjoint entries and read nothing
another iteration writes gives the same values, bit for bit, either way; reductions (sums) stay
in serial kernels, whose order of addition would otherwise depend on the split.

numba's on-disk cache keys a compiled kernel by its function's qualified name and bytecode, not
by its compile options, so the parallel twin is compiled from a copy of the function named
``<name>_parallel``: two kernels under one name would load each other's code from the cache.

The parallel twins run on numba's own threads (its threading layer: OpenMP or TBB where present,
else its work queue, which must not be entered from two threads at once). A caller sets how many
with :func:`parallel_section`, which also keeps two threads of this process from running parallel
kernels at the same time.

GNU OpenMP's threads spin after a parallel loop, waiting for the next, 300000 turns by default:
long enough to take the core from the solver's own component threads in the sub-step that
follows (3D 64³, advection 17.9 -> 23.1 ms a step). Unless the environment says otherwise, they
spin :data:`SPIN_COUNT` turns, which still keeps them awake between the loops of one solve
(``GOMP_SPINCOUNT``, read when OpenMP is loaded: by this import, just after it is set).

The threading layer is started when this module is imported, before any kernel loads from the
cache. A serial kernel that calls a parallel twin (the small dispatchers that pick one of the
two) and was compiled in an earlier process crashed the process when it was loaded from the
cache into one whose threading layer had not started yet, even on its serial path: a segfault,
not an exception (numba 0.68, as in numba's issue #8578).
"""

from __future__ import annotations

import contextlib
import os
import threading
import types
from collections.abc import Callable, Iterator
from typing import Any

import numba
from numba import njit

#: Any number of cells as the threshold: never parallel (the serial path).
NEVER = 2**62
#: Turns an idle OpenMP thread spins before it sleeps (module docstring).
SPIN_COUNT = "10000"

os.environ.setdefault("GOMP_SPINCOUNT", SPIN_COUNT)
numba.get_num_threads()  # starts the threading layer (module docstring)

_section = threading.Lock()


def serial_and_parallel(body: Callable[..., Any]) -> tuple[Any, Any]:
    """``body`` compiled as a serial and as a parallel kernel (both cached, ``nogil``)."""
    serial = njit(cache=True, nogil=True)(body)
    twin = types.FunctionType(
        body.__code__, body.__globals__, body.__name__ + "_parallel", body.__defaults__,
        body.__closure__,
    )  # fmt: skip
    twin.__qualname__ = body.__qualname__ + "_parallel"
    twin.__doc__ = body.__doc__
    twin.__module__ = body.__module__
    return serial, njit(cache=True, nogil=True, parallel=True)(twin)


def available_threads() -> int:
    """The most threads numba's parallel kernels can run on in this process."""
    return int(numba.config.NUMBA_NUM_THREADS)  # type: ignore[attr-defined]


@contextlib.contextmanager
def parallel_section(threads: int) -> Iterator[int]:
    """Run parallel kernels on ``threads`` threads (capped at :func:`available_threads`) in the
    block, one such block in the process at a time; yields the count granted."""
    count = max(1, min(int(threads), available_threads()))
    with _section:
        previous = numba.get_num_threads()
        numba.set_num_threads(count)
        try:
            yield count
        finally:
            numba.set_num_threads(previous)

"""Kernels compiled twice: on the calling thread, and with their ``prange`` loops on numba's threads.

A kernel body written with ``numba.prange`` for its outermost loop is compiled once as a plain
serial kernel and once with ``parallel=True`` (:func:`serial_and_parallel`). A body whose
iterations write disjoint entries and read nothing another iteration writes gives the same bits
either way; reductions (sums) stay serial, their order of addition otherwise split-dependent. The
twin is a copy of the function named ``<name>_parallel``: numba's on-disk cache keys a kernel by
qualified name and bytecode, not by compile options. A kernel that picks a twin at run time
(``if par: ..._parallel(...)``) compiles both; :func:`serial_twin` copies such a driver with
its parallel callees replaced by the serial ones, for the calls that never run on threads
(compiling the parallel twins takes seconds each, on a first run).

The twins run on numba's threading layer (OpenMP or TBB where present, else its work queue, which
must not be entered from two threads at once): :func:`parallel_section` sets how many threads and
keeps two threads of this process from running parallel kernels at the same time. GNU OpenMP's
threads spin :data:`SPIN_COUNT` turns after a loop unless the environment says otherwise
(``GOMP_SPINCOUNT``): awake between the loops of one solve, asleep before the solver's own
component threads need the core (the default 300000 keeps it from them).

Importing this module starts the threading layer, before any kernel loads from the cache: a
dispatcher that calls a parallel twin, loaded before it starts, segfaults (numba issue #8578).
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
        body.__code__,
        body.__globals__,
        body.__name__ + "_parallel",
        body.__defaults__,
        body.__closure__,
    )
    twin.__qualname__ = body.__qualname__ + "_parallel"
    twin.__doc__ = body.__doc__
    twin.__module__ = body.__module__
    return serial, njit(cache=True, nogil=True, parallel=True)(twin)


def serial_twin(kernel: Any, replace: dict[str, Any], suffix: str = "_serial") -> Any:
    """A copy of the kernel ``kernel`` (compiled as it is: cached, ``nogil``) that calls the
    kernels ``replace`` names where it names others: called with its parallel twins replaced by
    their serial selves, a driver whose threads are off (``par_cells`` at :data:`NEVER`) gives
    the same bits without compiling a parallel kernel (compiling those takes seconds each). The
    copy is named ``<name><suffix>`` (numba's cache keys a kernel by its qualified name)."""
    body = kernel.py_func
    twin = types.FunctionType(
        body.__code__,
        {**body.__globals__, **replace},
        body.__name__ + suffix,
        body.__defaults__,
        body.__closure__,
    )
    twin.__qualname__ = body.__qualname__ + suffix
    twin.__doc__ = body.__doc__
    twin.__module__ = body.__module__
    return njit(cache=True, nogil=True)(twin)


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

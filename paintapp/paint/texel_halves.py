"""A write-back's texel passes split in two, for two threads.

The passes that compute each texel (or each column) on its own,
:func:`~paintapp.paint.columns_kernels.texels_to_columns`,
:func:`~paintapp.paint.columns_kernels.spread_to_texels` and
:func:`~paintapp.paint.columns_kernels.store_texels`, take a range of rows (or columns) and
release the interpreter lock, so the two halves of a box run at once on the solver's component
threads (:func:`solver.compiled.threads.run_components`): this thread the first, a pool thread
the second. Every value is computed as one call over the whole box computes it, so the canvas is
the same, bit for bit, on one thread or two, whatever the machine. A box under
:data:`SPLIT_MIN_TEXELS` stays on this thread: handing a half to a sleeping thread costs more
than it saves there.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from solver import run_components, usable_cores

T = TypeVar("T")

#: Texels (box area times pigments passed) from which a pass runs on two threads. Below about
#: this, waking the second thread cost as much as the half it took (a demo-sized box is 20 000
#: to 200 000 texels; docs/performance.md, the write-back on two threads).
SPLIT_MIN_TEXELS = 20_000


def split_threads(texels: int) -> int:
    """Threads (1 or 2) a pass over ``texels`` runs on."""
    return 2 if texels >= SPLIT_MIN_TEXELS and usable_cores() >= 2 else 1


def on_halves(work: Callable[[int, int], T], n: int, threads: int) -> list[T]:
    """``[work(0, m), work(m, n)]`` (``m = n // 2``) on ``threads`` threads, or ``[work(0, n)]``
    with one thread (or ``n < 2``): ``work(lo, hi)`` does the rows (or columns) ``lo..hi-1``
    and must write nothing the other half reads."""
    if threads < 2 or n < 2:
        return [work(0, n)]
    m = n // 2
    halves = ((0, m), (m, n))
    return run_components(lambda a: work(*halves[a]), 2, threads)

"""The layer count that a kernel's innermost loop runs over, as numba should see it.

A 2D grid is one layer deep: its arrays are ``(nx, ny, 1)``. A kernel written for both whose
innermost loop runs over the layers pays that loop's setup at every ``(i, j)`` of a 2D grid, for
one pass. Such a kernel takes ``layers`` from :func:`layer_count`, ``None`` on a 2D grid, and
bounds its loop with ``1 if layers is None else nz``: numba prunes a branch on whether an argument
is ``None`` when it compiles, so the 2D grid gets its own compilation with a loop of one pass,
which the compiler removes. The values are the same, bit for bit.
"""

from __future__ import annotations


def layer_count(shape: tuple[int, ...]) -> int | None:
    """``None`` for a grid one layer deep (2D), else its number of layers."""
    return None if shape[2] == 1 else int(shape[2])

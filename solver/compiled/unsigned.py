"""Unsigned index constants for numba kernels.

A kernel that indexes with unsigned integers spares numba's wrap-around test (a negative index
counts from the end) on every access. An unsigned value must never meet a signed one in
arithmetic (numba would give a float), hence these constants for the offsets.
"""

from __future__ import annotations

import numpy as np

U0 = np.uint64(0)
U1 = np.uint64(1)
U2 = np.uint64(2)

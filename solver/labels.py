"""Cell labels and velocity face kinds, shared by the solver's kernels and the paint grid.

Cells carry a label: ``FLUID`` (-1), ``STATIC_SOLID`` (-2) or the index (>= 0) of the probe that
covers them. A face of velocity component ``a`` is

* ``FREE`` (0): both neighbouring cells are fluid (or fluid and an open outflow side); an unknown;
* ``BOUNDARY`` (1): it lies on a fluid/solid interface or on a closed domain side; its value is
  prescribed (the solid's or the side's velocity);
* ``INTERIOR`` (2): both neighbours are solid; its value is the solid's velocity, used as the
  wall value when a tangential neighbour reflects across the solid's surface (paper eq. 15).

Labels are stored as ``int32`` (cells) and face kinds as ``int8`` arrays.
"""

from __future__ import annotations

FLUID = -1
STATIC_SOLID = -2

FREE = 0
BOUNDARY = 1
INTERIOR = 2

"""The compile options every numba kernel of the project shares.

``@kernel`` compiles a function with numba in nopython mode, caches the machine code on disk
(``cache=True``: a second process loads it instead of compiling) and releases the interpreter lock
while it runs (``nogil=True``: the solver's component threads and the paint grid's beside jobs run
kernels on two threads at once). ``@inline_kernel`` is the same for small helpers that numba
inlines into their callers at the bytecode level (``inline="always"``).

numba's cache does not notice edits to a kernel's callees in other modules: after such an edit,
delete the ``__pycache__/*.nbi`` and ``*.nbc`` files.
"""

from __future__ import annotations

from numba import njit

kernel = njit(cache=True, nogil=True)
inline_kernel = njit(cache=True, nogil=True, inline="always")

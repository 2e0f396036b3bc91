"""Kernels compiled serial and parallel: distinct cache names, the same values, a thread count
that is set for a section and restored."""

from __future__ import annotations

import os
import subprocess
import sys

import numba
import numpy as np
from numba import prange

from solver.compiled.parallel import (
    SPIN_COUNT,
    available_threads,
    parallel_section,
    serial_and_parallel,
)


def _squares(x, out):
    for n in prange(x.size):
        out[n] = x[n] * x[n]


SERIAL, PARALLEL = serial_and_parallel(_squares)


def test_the_twins_have_cache_names_of_their_own_and_the_same_values():
    assert SERIAL.py_func.__qualname__ == "_squares"
    assert PARALLEL.py_func.__qualname__ == "_squares_parallel"
    assert not SERIAL.targetoptions.get("parallel")
    assert PARALLEL.targetoptions.get("parallel")
    x = np.random.default_rng(3).standard_normal(10_001)
    a, b = np.empty_like(x), np.empty_like(x)
    SERIAL(x, a)
    with parallel_section(2):
        PARALLEL(x, b)
    assert np.array_equal(a, b)
    assert np.array_equal(a, x * x)


def test_a_section_sets_the_threads_within_the_limit_and_restores_them():
    before = numba.get_num_threads()
    with parallel_section(10**6) as granted:
        assert granted == available_threads() == numba.get_num_threads()
    with parallel_section(0) as granted:
        assert granted == 1 == numba.get_num_threads()
    assert numba.get_num_threads() == before


def _spin_count_in_a_fresh_process(env: dict[str, str]) -> str:
    code = "import os, solver.compiled.parallel; print(os.environ['GOMP_SPINCOUNT'])"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True, timeout=120)  # fmt: skip
    return out.stdout.strip()


def test_openmp_threads_spin_briefly_unless_the_environment_says_otherwise():
    env = {k: v for k, v in os.environ.items() if k != "GOMP_SPINCOUNT"}
    assert _spin_count_in_a_fresh_process(env) == SPIN_COUNT
    assert _spin_count_in_a_fresh_process({**env, "GOMP_SPINCOUNT": "5"}) == "5"


_DISPATCH_MODULE = """
import sys

import numpy as np
from numba import njit, prange

from solver.compiled.parallel import NEVER, parallel_section, serial_and_parallel


def _fill(a):
    for n in prange(a.size):
        a[n] = n


FILL_S, FILL_P = serial_and_parallel(_fill)


@njit(cache=True, nogil=True)
def fill(par, a):
    if par:
        FILL_P(a)
    else:
        FILL_S(a)


@njit(cache=True, nogil=True)
def run(a, par_cells=NEVER):
    fill(a.size >= par_cells, a)
    return a.sum()


a = np.zeros(10)
if sys.argv[1] == "parallel":
    with parallel_section(2):
        print(run(a, 5))
else:
    print(run(a))
"""


def test_a_cached_kernel_that_dispatches_to_parallel_twins_loads_in_a_fresh_process(tmp_path):
    """The solver's pattern (:func:`solver.linalg.multigrid.mgpcg_flat`): a cached kernel whose
    ``par_cells`` picks, through a small dispatcher, one of two twins; compiled with the argument
    in one process, without it in a second, and loaded from the cache in a third. Before the
    threading layer was started at import, the third process died of a segfault."""
    module = tmp_path / "dispatch.py"
    module.write_text(_DISPATCH_MODULE)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}
    for mode in ("parallel", "serial", "serial", "serial"):
        run = subprocess.run([sys.executable, str(module), mode], env=env, cwd=tmp_path,
                             capture_output=True, text=True, timeout=300)  # fmt: skip
        assert run.returncode == 0, (mode, run.returncode, run.stderr[-2000:])
        assert float(run.stdout) == 45.0

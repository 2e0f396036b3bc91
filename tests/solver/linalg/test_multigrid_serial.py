"""The serial solve's own kernel chain: the bits of the driver that can run on threads, and no
parallel kernel compiled (nor one smoothing sweep per colour)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from numba.core.dispatcher import Dispatcher

from solver.linalg import multigrid
from solver.linalg.multigrid import Multigrid
from tests.support.stencil_systems import random_system


@pytest.mark.parametrize(("shape", "dim"), [((20, 17, 13), 3), ((33, 29, 1), 2)])
def test_the_serial_chain_gives_the_bits_of_the_driver_with_threads(monkeypatch, shape, dim):
    system = random_system(shape, dim, seed=3)
    b = np.random.default_rng(1).standard_normal(shape)
    solver = Multigrid(shape, dim)
    x_serial = np.zeros(shape)
    report = solver.solve(system, b, x_serial, 1e-10, 300)
    driver = multigrid.mgpcg_flat
    monkeypatch.setattr(multigrid, "mgpcg_flat_serial", lambda *args: driver(*args))
    x_driver = np.zeros(shape)
    assert solver.solve(system, b, x_driver, 1e-10, 300) == report
    assert np.array_equal(x_serial, x_driver)


def _kernels_called(dispatcher, seen=None) -> set:
    """The kernels ``dispatcher`` calls, directly or through others (by the names its code
    reads from its globals)."""
    seen = set() if seen is None else seen
    for name in dispatcher.py_func.__code__.co_names:
        callee = dispatcher.py_func.__globals__.get(name)
        if isinstance(callee, Dispatcher) and callee not in seen:
            seen.add(callee)
            _kernels_called(callee, seen)
    return seen


def test_the_serial_chain_calls_no_parallel_kernel():
    def parallel(d):
        return {k.py_func.__name__ for k in _kernels_called(d) if k.targetoptions.get("parallel")}

    assert parallel(multigrid.mgpcg_flat)  # the driver that can run on threads
    assert parallel(multigrid.mgpcg_flat_serial) == set()


_FRESH_PROCESS = """
import json
import numpy as np
from solver.linalg import multigrid as m
from tests.support.stencil_systems import random_system

shape = (9, 7, 5)
m.Multigrid(shape, 3).solve(random_system(shape, 3, seed=1), np.ones(shape), np.zeros(shape),
                            1e-10, 300)
print(json.dumps({
    "parallel": [d.py_func.__name__ for d in (m._sweep_p, m._copy_p, m.v_cycle) if d.signatures],
    "sweeps": [str(s) for s in m._sweep_s.signatures],
}))
"""


def test_a_serial_solve_compiles_one_sweep_for_both_colours(tmp_path):
    # an empty cache of its own: the chain compiles (seconds), so its callees are seen
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    run = subprocess.run(
        [sys.executable, "-c", _FRESH_PROCESS], env=env, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr[-2000:]
    seen = json.loads(run.stdout.strip().splitlines()[-1])
    assert seen["parallel"] == []
    assert len(seen["sweeps"]) == 1
    assert "Literal" not in seen["sweeps"][0]

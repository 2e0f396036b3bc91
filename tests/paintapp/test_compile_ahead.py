"""The second process that compiles a cold run's kernels from the far end of the bundled list."""

from __future__ import annotations

import inspect
import pickle
from pathlib import Path

import numba
import numpy as np
from numba import types

from paintapp import compile_ahead, first_run
from paintapp.compile_ahead import compile_from_the_end, compiling_ahead, load_manifest, resolve

VECTOR = types.Array(types.float64, 1, "C")


def write_manifest(path: Path, entries: list, version: str = numba.__version__) -> Path:
    with path.open("wb") as handle:
        pickle.dump({"numba": version, "entries": entries}, handle)
    return path


def test_the_bundled_list_names_the_run_s_kernels_with_numba_types() -> None:
    entries = load_manifest()
    assert len(entries) > 50
    modules = {module.split(".")[0] for module, _, _ in entries}
    assert modules == {"solver", "brushes", "paintapp"}
    resolved = [resolve(module, name) for module, name, _ in entries]
    # the multigrid's serial twins are made at import, not module attributes: their callers
    # compile them
    assert sum(d is not None for d in resolved) >= 0.8 * len(entries)
    assert all(isinstance(t, types.Type) for _, _, args in entries for t in args)
    assert ("brushes.tips_kernels", "tip_sdf") in {(m, n) for m, n, _ in entries}


def stale_entries(entries: list) -> list[str]:
    """The entries whose argument count no longer fits their kernel's parameters."""
    stale = []
    for module, name, args in entries:
        dispatcher = resolve(module, name)
        if dispatcher is None:
            continue
        params = list(inspect.signature(dispatcher.py_func).parameters.values())
        required = sum(p.default is inspect.Parameter.empty for p in params)
        if not required <= len(args) <= len(params):
            stale.append(f"{module}.{name}: {len(args)} arguments, takes {len(params)}")
    return stale


def test_every_bundled_entry_fits_its_kernel_s_parameters() -> None:
    """A kernel given a parameter more (or fewer) since the list was recorded is skipped by the
    second process and compiled by the run itself: record the list again
    (``NUMBA_CACHE_DIR=$(mktemp -d) python -m paintapp.compile_order``)."""
    assert stale_entries(load_manifest()) == []
    shifted = [("solver.linalg.pcg", "dot", (VECTOR, VECTOR, VECTOR))]
    assert stale_entries(shifted) == ["solver.linalg.pcg.dot: 3 arguments, takes 2"]


def test_garbage_is_no_list_and_another_numba_s_list_is_still_read(tmp_path: Path) -> None:
    entries = [("solver.linalg.pcg", "dot", (VECTOR, VECTOR))]
    assert load_manifest(write_manifest(tmp_path / "ok.pkl", entries)) == entries
    assert load_manifest(write_manifest(tmp_path / "old.pkl", entries, "0.1")) == entries
    (tmp_path / "junk.pkl").write_bytes(b"not a pickle")
    assert load_manifest(tmp_path / "junk.pkl") == []
    assert load_manifest(tmp_path / "missing.pkl") == []


def test_the_list_is_compiled_last_first_and_stale_entries_are_skipped(monkeypatch) -> None:
    from solver.linalg import pcg

    order: list[str] = []
    real = resolve

    def noting(module: str, name: str):
        order.append(name)
        return real(module, name)

    monkeypatch.setattr(compile_ahead, "resolve", noting)
    entries = [
        ("solver.linalg.pcg", "dot", (VECTOR, VECTOR)),
        ("solver.linalg.pcg", "no_such_kernel", (VECTOR,)),
        ("solver.linalg.pcg", "dot", (types.unicode_type, VECTOR)),  # no longer compiles
        ("no.such.module", "dot", (VECTOR,)),
    ]
    assert compile_from_the_end(entries) == 1
    assert order == ["dot", "dot", "no_such_kernel", "dot"]
    assert pcg.dot(np.ones(3), np.ones(3)) == 3.0


def test_a_warm_cache_starts_no_second_process(monkeypatch) -> None:
    monkeypatch.setattr(first_run, "kernels_cold", lambda: False)
    with compiling_ahead() as started:
        assert not started


def test_a_cold_cache_starts_one_and_the_run_s_end_stops_it(monkeypatch, tmp_path) -> None:
    """The second process runs on its own (empty) cache here, and is stopped mid-list."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(first_run, "kernels_cold", lambda: True)
    started_children = []
    real_popen = compile_ahead.subprocess.Popen

    def popen(*args, **kwargs):
        child = real_popen(*args, **kwargs)
        started_children.append(child)
        return child

    monkeypatch.setattr(compile_ahead.subprocess, "Popen", popen)
    with compiling_ahead() as started:
        assert started and len(started_children) == 1
        assert started_children[0].poll() is None  # compiling
    assert started_children[0].poll() is not None  # stopped with the run
    monkeypatch.setattr(compile_ahead, "ENABLED", False)
    with compiling_ahead() as started:
        assert not started
    with compiling_ahead(tmp_path / "no_list.pkl") as started:
        assert not started


def test_the_environment_turns_it_off(monkeypatch) -> None:
    import importlib

    monkeypatch.setenv("PAINTAPP_COMPILE_AHEAD", "0")
    fresh = importlib.reload(compile_ahead)
    try:
        assert fresh.ENABLED is False
    finally:
        monkeypatch.delenv("PAINTAPP_COMPILE_AHEAD")
        importlib.reload(compile_ahead)

"""The brush's paint reservoir: capacity, depletion, mixing and conservation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushes.reservoir import PaintReservoir

CAP = 2e-8


def test_load_fills_up_to_capacity():
    res = PaintReservoir(CAP)
    assert res.is_empty and res.fractions() == {}
    assert res.load("ultramarine", 1.5e-8) == pytest.approx(1.5e-8)
    assert res.load("yellow", 1e-8) == pytest.approx(0.5e-8)  # only the free room
    assert res.total_m3 == pytest.approx(CAP)
    assert res.free_m3 == pytest.approx(0.0, abs=1e-24)
    assert res.load("yellow", 1e-8) == pytest.approx(0.0, abs=1e-24)


def test_deposit_is_proportional_and_limited_by_what_is_there():
    res = PaintReservoir(CAP)
    res.load("a", 6e-9)
    res.load("b", 2e-9)
    out = res.deposit(4e-9)
    assert out["a"] == pytest.approx(3e-9) and out["b"] == pytest.approx(1e-9)
    assert res.fractions() == pytest.approx({"a": 0.75, "b": 0.25})
    rest = res.deposit(1.0)  # far more than there is
    assert math.fsum(rest.values()) == pytest.approx(4e-9)
    assert res.is_empty and all(v == 0.0 for v in res.volumes_m3.values())
    assert res.deposit(1e-9) == {"a": 0.0, "b": 0.0}


def test_pick_up_scales_down_to_free_room():
    res = PaintReservoir(CAP, {"a": 1.5e-8})
    taken = res.pick_up({"b": 0.6e-8, "c": 0.4e-8})
    assert taken["b"] == pytest.approx(0.3e-8) and taken["c"] == pytest.approx(0.2e-8)
    assert res.total_m3 == pytest.approx(CAP)


def test_clean_empties_and_returns_everything():
    res = PaintReservoir(CAP, {"a": 1e-8, "b": 0.5e-8})
    removed = res.clean()
    assert removed == pytest.approx({"a": 1e-8, "b": 0.5e-8})
    assert res.is_empty and np.all(res.as_array(["a", "b", "c"]) == 0.0)


def test_conservation_over_random_operations():
    rng = np.random.default_rng(3)
    res = PaintReservoir(CAP)
    names = ["red", "blue", "white"]
    ledger = dict.fromkeys(names, 0.0)  # volumes put in minus volumes taken out
    for _ in range(2000):
        op = rng.integers(4)
        if op == 0:
            name = names[rng.integers(3)]
            ledger[name] += res.load(name, rng.uniform(0, 1e-8))
        elif op == 1:
            for name, v in res.pick_up({n: rng.uniform(0, 3e-9) for n in names}).items():
                ledger[name] += v
        elif op == 2:
            for name, v in res.deposit(rng.uniform(0, 5e-9)).items():
                ledger[name] -= v
        elif rng.uniform() < 0.05:
            for name, v in res.clean().items():
                ledger[name] -= v
        vols = res.volumes_m3
        assert all(v >= 0.0 for v in vols.values())
        assert res.total_m3 <= CAP * (1 + 1e-12)
        for name in names:
            assert vols.get(name, 0.0) == pytest.approx(ledger[name], abs=1e-12 * CAP)


def test_rejects_bad_volumes():
    res = PaintReservoir(CAP)
    for bad in (-1e-9, float("nan"), float("inf")):
        with pytest.raises(ValueError):
            res.load("a", bad)
        with pytest.raises(ValueError):
            res.deposit(bad)
    with pytest.raises(ValueError):
        PaintReservoir(0.0)

"""``paintapp bench``: the noise definition, the Pareto front, filter reconstruction, the command."""

from __future__ import annotations

import json

import numpy as np
import pytest

from paintapp.bench.measure import Measurement
from paintapp.bench.noise import relative_deviation, relative_noise, smooth, window_samples
from paintapp.bench.rates import reconstruct
from paintapp.bench.registry import Family, Registry, Setting
from paintapp.bench.report import format_table, json_ready, pareto_front
from paintapp.bench.square_sweep import SweepTrace
from paintapp.cli import main


def test_noise_of_a_smooth_signal_is_near_zero_and_white_noise_is_measured():
    dt = 0.005
    t = np.arange(0.0, 2.0, dt)
    clean = np.column_stack([np.sin(np.pi * t), 0.5 * np.cos(np.pi * t)])
    assert relative_noise(clean, dt) < 1e-3
    rng = np.random.default_rng(1)
    jitter = 0.1 * rng.standard_normal(clean.shape)
    expected = np.sqrt(np.mean(np.sum(jitter**2, 1))) / np.sqrt(np.mean(np.sum(clean**2, 1)))
    # the smoothing keeps a little of the noise (a 21-point cubic fit), so slightly less is seen
    assert relative_noise(clean + jitter, dt) == pytest.approx(expected, rel=0.2)
    assert relative_noise(np.zeros(50), dt) == 0.0
    assert window_samples(dt) == 21 and window_samples(0.05) == 5
    assert smooth(clean, dt).shape == clean.shape
    assert relative_deviation(2 * clean, clean) == pytest.approx(1.0)


def test_json_records_are_strict_json():
    record = {"errors": {"a": float("inf"), "b": np.float64(0.5)}, "knobs": (np.int64(3),)}
    assert json_ready(record) == {"errors": {"a": None, "b": 0.5}, "knobs": [3]}


def test_pareto_front_keeps_only_unbeaten_points():
    points = [(1.0, 0.5), (2.0, 0.6), (2.0, 0.1), (4.0, 0.05), (5.0, 0.2)]
    assert pareto_front(points) == [0, 2, 3]


def _staircase_trace(rate_hz: float) -> SweepTrace:
    t = np.arange(1, int(2.2 * rate_hz) + 1) / rate_hz
    force = np.column_stack([np.sin(np.pi * t), np.cos(np.pi * t)])
    n = len(t)
    return SweepTrace(t, force, np.zeros(n), np.zeros((n, 2)), np.zeros(n), [], 1 / rate_hz, (8, 8))


def test_filters_smooth_the_stair_steps_of_a_slow_simulation():
    trace = _staircase_trace(30.0)
    jumps = {}
    for kind in ("zoh", "linear", "fir"):
        ticks, out, _ = reconstruct(trace, kind, 1e-3)
        late = out[ticks > 0.1, :2]  # past the start, where every filter jumps from zero
        jumps[kind] = np.sqrt(np.mean(np.sum(np.diff(late, axis=0) ** 2, axis=1)))
    assert jumps["fir"] < 0.5 * jumps["zoh"]
    assert jumps["linear"] < 0.5 * jumps["zoh"]


def test_quick_bench_writes_table_json_and_plot(tmp_path, capsys):
    out_json, out_png = tmp_path / "bench.json", tmp_path / "pareto.png"
    args = ["bench", "--quick", "--only", "taylor_green", "--json", str(out_json)]
    assert main([*args, "--plot", str(out_png)]) == 0
    records = json.loads(out_json.read_text())
    assert [r["knobs"]["cells"] for r in records] == [16, 32, 32]
    for r in records:
        assert r["family"] == "taylor_green"
        assert r["cost"]["median_step_ms"] > 0 and r["cost"]["state_mib"] > 0
        assert 0 <= r["errors"]["decay_rate_rel_error"] < 1
        assert r["notes"] and r["reference"]
    assert out_png.read_bytes()[:4] == b"\x89PNG"
    assert "decay_rate_rel_error" in capsys.readouterr().out


def test_unknown_family_is_refused(capsys):
    assert main(["bench", "--quick", "--only", "nonsense"]) == 2
    assert "unknown family nonsense" in capsys.readouterr().err


def test_a_registered_family_is_run_and_a_failing_setting_is_recorded():
    def fake(size: int = 1) -> Measurement:
        if size < 0:
            raise ValueError("negative size")
        return Measurement({"err": 1.0 / size}, {"median_step_ms": float(size)}, "fake run")

    family = Family("fake", fake, ("err",), {"size": 1}, quick=({"size": 2},))
    registry = Registry([family])
    assert Setting("fake", {"size": 2}) in registry.quick_settings()
    assert all(s.family != "fake" for s in registry.full_settings())
    good = registry.run_setting(Setting("fake", {"size": 4}))
    assert good["errors"] == {"err": 0.25} and good["knobs"] == {"size": 4}
    bad = registry.run_setting(Setting("fake", {"size": -1}))
    assert bad["failed"] == "ValueError: negative size"
    assert "FAILED" in format_table([good, bad])


def test_only_takes_several_families_in_one_flag_or_repeated():
    from paintapp.cli import build_parser

    args = build_parser().parse_args(
        ["bench", "--only", "cavity", "taylor_green", "--only", "rates"]
    )
    assert args.only == ["cavity", "taylor_green", "rates"]

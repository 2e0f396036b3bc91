"""The Fig. 3 reproduction: what the figure shows, and the command that draws it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from paintapp.cli import main
from paintapp.figures.filter import figure_data, high_frequency_energy


@pytest.mark.parametrize("seed", [0, 3, 11])
def test_fir_output_has_far_less_high_frequency_energy_and_the_same_mean(seed: int) -> None:
    data = figure_data(seed=seed, duration_s=2.0)
    zoh, fir = data["zoh"], data["fir"]
    assert high_frequency_energy(fir, 1e-3) < 0.1 * high_frequency_energy(zoh, 1e-3)
    # the step jumps: the hold jumps by up to the full range in one tick, the FIR never does
    assert np.max(np.abs(np.diff(zoh))) > 0.5
    assert np.max(np.abs(np.diff(fir))) < 0.5 * np.max(np.abs(np.diff(zoh)))
    assert np.mean(fir[20:]) == pytest.approx(np.mean(zoh[20:]), abs=0.02 * np.std(zoh))


def test_the_input_is_a_random_70_hz_signal() -> None:
    data = figure_data(seed=5, duration_s=2.0)
    rate = (len(data["t_in"]) - 1) / (data["t_in"][-1] - data["t_in"][0])
    assert rate == pytest.approx(70.0, rel=0.05)
    assert len(data["t"]) == 2000 and np.std(data["x_in"]) > 0.3


def test_figures_filter_writes_a_png(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "fig3.png"
    assert main(["figures", "filter", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "FIR" in capsys.readouterr().out


def test_figures_filter_rejects_a_missing_directory(tmp_path: Path) -> None:
    assert main(["figures", "filter", "--out", str(tmp_path / "nope" / "f.png")]) == 2


def test_figures_filter_rejects_a_negative_seed(tmp_path: Path, capsys) -> None:
    assert main(["figures", "filter", "--out", str(tmp_path / "f.png"), "--seed", "-1"]) == 2
    err = capsys.readouterr().err
    assert "'--seed'" in err and "Traceback" not in err

"""``paintapp figures filter --out F.png``: the paper's Fig. 3, filtering a random 70 Hz signal
for display at 1 kHz.

A random value arrives about every 1/70 s (with the jitter a real simulation has); each
reconstruction filter of :mod:`paintapp.haptics.filters` turns it into a 1 kHz signal. The top
panel shows the signals, the bottom panel their spectra: the zero-order hold's steps put energy at
high frequencies that the FIR window filter removes, while all three keep the signal's mean.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from common.errors import InputError
from paintapp.haptics.filters import make_filter

FILTERS = ("zoh", "linear", "fir")
LABELS = {
    "zoh": "zero-order hold",
    "linear": "linear interpolation",
    "fir": "FIR, 10th-order Bartlett-Hanning",
}


def figure_data(
    seed: int = 3,
    duration_s: float = 0.25,
    input_rate_hz: float = 70.0,
    tick_s: float = 1e-3,
    jitter: float = 0.15,
) -> dict[str, np.ndarray]:
    """Inputs and the 1 kHz output of each filter.

    Returns:
        ``t_in`` (n,) arrival times and ``x_in`` (n,) values of the input samples, ``t`` (m,)
        the tick times, and one array (m,) per filter name in :data:`FILTERS`.
    """
    rng = np.random.default_rng(seed)
    period = 1.0 / input_rate_hz
    gaps = period * (1.0 + jitter * rng.uniform(-1.0, 1.0, int(duration_s / period) + 2))
    t_in = np.concatenate([[0.0], np.cumsum(gaps)])
    t_in = t_in[t_in < duration_s]
    x_in = rng.uniform(-1.0, 1.0, len(t_in))
    t = np.arange(round(duration_s / tick_s)) * tick_s
    out: dict[str, np.ndarray] = {"t_in": t_in, "x_in": x_in, "t": t}
    for name in FILTERS:
        filt = make_filter(name, tick_s, dim=1)
        y = np.empty(len(t))
        k = 0
        for i, ti in enumerate(t):
            while k < len(t_in) and t_in[k] <= ti + 1e-12:
                filt.push(t_in[k], np.array([x_in[k]]))
                k += 1
            y[i] = filt.output(ti)[0]
        out[name] = y
    return out


def high_frequency_energy(y: np.ndarray, tick_s: float, above_hz: float = 100.0) -> float:
    """Energy of ``y`` (sampled every ``tick_s``) above ``above_hz``: sum of |FFT|^2 / n."""
    spectrum = np.fft.rfft(y - np.mean(y))
    freqs = np.fft.rfftfreq(len(y), tick_s)
    return float(np.sum(np.abs(spectrum[freqs > above_hz]) ** 2) / len(y))


def plot(data: dict[str, np.ndarray], out: Path, tick_s: float = 1e-3) -> None:
    """Draw the figure into a PNG at ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, axf) = plt.subplots(2, 1, figsize=(8.0, 6.5), height_ratios=[3, 2])
    t_ms = data["t"] * 1e3
    ax.plot(data["t_in"] * 1e3, data["x_in"], "ko", ms=4, label="input samples (~70 Hz)")
    styles = {"zoh": ("C0", "-", 1.0), "linear": ("C2", "--", 1.0), "fir": ("C3", "-", 1.8)}
    for name in FILTERS:
        color, ls, lw = styles[name]
        drawstyle = "steps-post" if name == "zoh" else "default"
        ax.plot(
            t_ms, data[name], color=color, ls=ls, lw=lw, drawstyle=drawstyle, label=LABELS[name]
        )
    ax.set(
        xlabel="time (ms)",
        ylabel="force (arbitrary units)",
        title="Filtering a random 70 Hz input for haptic display at 1 kHz",
    )
    ax.legend(loc="upper right", fontsize=8)
    for name in FILTERS:
        y = data[name] - np.mean(data[name])
        freqs = np.fft.rfftfreq(len(y), tick_s)
        power = np.abs(np.fft.rfft(y)) ** 2 / len(y)
        axf.semilogy(freqs, np.maximum(power, 1e-12), color=styles[name][0], label=LABELS[name])
    axf.set(xlabel="frequency (Hz)", ylabel="power", xlim=(0, 500))
    axf.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def register(figs: argparse._SubParsersAction) -> None:
    p = figs.add_parser("filter", help="Fig. 3: a random 70 Hz signal through each 1 kHz filter")
    p.add_argument("--out", required=True, help="PNG file to write")
    p.add_argument("--seed", type=int, default=3, help="random seed of the input signal")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    out = Path(args.out)
    if out.suffix.lower() != ".png":
        raise InputError("the figure is written as PNG; give a .png file name", key="--out")
    if not out.parent.exists():
        raise InputError(f"directory {out.parent} does not exist", key="--out")
    if not 0 <= args.seed < 2**63:
        raise InputError(f"expected a seed >= 0 and < 2**63, got {args.seed}", key="--seed")
    data = figure_data(seed=args.seed)
    plot(data, out)
    zoh = high_frequency_energy(data["zoh"], 1e-3)
    for name in FILTERS:
        energy = high_frequency_energy(data[name], 1e-3)
        print(
            f"{LABELS[name]:34s} mean {np.mean(data[name]):+.3f}  energy above 100 Hz "
            f"{energy:.3g} ({energy / zoh:.1%} of the hold's)"
        )
    print(f"wrote {out}")
    return 0

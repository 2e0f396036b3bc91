"""Presenting benchmark records: a text table, and the Pareto front of error against cost.

A record is what :meth:`paintapp.bench.registry.Registry.run_setting` returns: ``name``, ``family``,
``knobs``, ``cost`` and ``errors`` (and ``failed`` when the run raised).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from paintapp.bench.registry import Family, Record


def _fmt(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.3g}"
    return str(value)


def format_table(records: Sequence[Record]) -> str:
    """One line per setting: cost (ms per step, MiB) and the family's errors."""
    head = f"{'setting':<44}{'ms/step':>9}{'MiB':>8}{'unconv':>7}  errors"
    lines = [head, "-" * len(head)]
    for r in records:
        if "failed" in r:
            lines.append(f"{r['name']:<44}  FAILED: {r['failed']}")
            continue
        c = r["cost"]
        mib = c.get("state_mib", 0.0) + c.get("peak_step_mib", 0.0)
        errs = ", ".join(f"{k} {_fmt(v)}" for k, v in r["errors"].items() if v is not None)
        if "compute_ms_per_s" in c:
            errs += f"; {c['compute_ms_per_s']:.0f} ms per s"
        if "replay_s" in c:
            errs += f"; replay {c['replay_s']:.2f} s, {c.get('solver_steps', 0)} solver steps"
        if c.get("speedup") is not None:
            errs += f", {c['speedup']:.2f}x the reference's speed"
        lines.append(
            f"{r['name']:<44}{c['median_step_ms']:>9.3f}{mib:>8.2f}"
            f"{c.get('unconverged_solves', 0):>7d}  {errs}"
        )
    return "\n".join(lines)


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the points no other point beats on both cost and error (lower is better),
    ordered by cost."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def panels(
    records: Sequence[Record], families: Sequence[Family]
) -> list[tuple[str, str, str, list[Record]]]:
    """(family, error key, cost key, records) for every plotted panel with data."""
    out = []
    for fam in families:
        name = fam.name
        rows = [r for r in records if r["family"] == name and "failed" not in r]
        for key in fam.errors:
            usable = [r for r in rows if r["errors"].get(key) is not None]
            if usable:
                out.append((name, key, fam.cost_key, usable))
    return out


def plot_pareto(records: Sequence[Record], families: Sequence[Family], path: str | Path) -> None:
    """Write a PNG with one panel per (family, error): error against cost, front highlighted."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from paintapp.atomic import atomic_write_with

    groups = panels(records, families)
    if not groups:
        raise ValueError("no successful settings to plot")
    cols = min(3, len(groups))
    rows = (len(groups) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.2 * rows), squeeze=False)
    for ax, (family, key, cost_key, rs) in zip(axes.flat, groups, strict=False):
        _panel(ax, family, key, cost_key, rs)
    for ax in list(axes.flat)[len(groups) :]:
        ax.set_visible(False)
    fig.suptitle("paintapp bench: error against cost (Pareto front in red)")
    fig.tight_layout()
    atomic_write_with(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def _panel(ax, family: str, key: str, cost_key: str, rs: Sequence[Record]) -> None:
    from matplotlib.ticker import FuncFormatter, NullFormatter

    floor = 1e-6  # errors of exactly 0 (a noiseless drag formula) sit on the axis floor
    pts = [(r["cost"][cost_key], max(float(r["errors"][key]), floor)) for r in rs]
    xs, ys = zip(*pts, strict=True)
    ax.scatter(xs, ys, s=18, color="tab:blue", zorder=3)
    front = pareto_front(pts)
    ax.step([xs[i] for i in front], [ys[i] for i in front], where="post", color="tab:red", lw=1.2)
    ax.scatter([xs[i] for i in front], [ys[i] for i in front], s=30, color="tab:red", zorder=4)
    for (x, y), r in zip(pts, rs, strict=True):
        label = r["name"].split(" ", 1)[1] if " " in r["name"] else "default"
        ax.annotate(label, (x, y), fontsize=6, xytext=(3, 2), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis, values in ((ax.xaxis, xs), (ax.yaxis, ys)):
        # with no power of ten inside the data's range, label the minor ticks instead
        no_decade = np.floor(np.log10(max(values))) < np.ceil(np.log10(min(values)))
        axis.set_minor_formatter(
            FuncFormatter(lambda v, _: f"{v:g}") if no_decade else NullFormatter()
        )
    unit = "ms per step" if cost_key == "median_step_ms" else cost_key.replace("_", " ")
    ax.set_xlabel(f"{unit} (median)")
    ax.set_ylabel(key.replace("_", " "))
    ax.set_title(family, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)


def json_ready(value: Any) -> Any:
    """``value`` with numpy scalars made plain and non-finite numbers made None (strict JSON)."""
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_ready(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value

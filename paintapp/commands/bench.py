"""``paintapp bench [--quick] [--json OUT.json] [--plot P.png]``: the speed/accuracy trade.

Sweeps grid resolution, pressure tolerance and iteration cap, advection order, force model, 2D
against 3D, and simulation rate against the servo rate with each reconstruction filter; measures
each setting's cost (median step time, memory) and its error against references (Ghia cavity,
Schaefer-Turek c_D, Taylor-Green decay, force noise on the paper's square sweep).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from typing import TYPE_CHECKING

from common.errors import InputError

if TYPE_CHECKING:
    from paintapp.bench.registry import Registry


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "bench", help="measure cost against accuracy over the solver's knobs (table, JSON, plot)"
    )
    p.add_argument("--quick", action="store_true", help="a small subset (under a minute)")
    p.add_argument("--json", metavar="OUT.json", help="write every setting's knobs, cost, errors")
    p.add_argument("--plot", metavar="P.png", help="write the Pareto fronts (error vs cost)")
    p.add_argument(
        "--only",
        metavar="FAMILY",
        action="extend",
        nargs="+",
        help="run only these families (one or more, repeatable): cavity, schaefer_turek, "
        "taylor_green, sweep, rates, painting_models, painting_fidelity",
    )
    p.set_defaults(func=run)


def bench_registry() -> Registry:
    """The families ``paintapp bench`` runs: the solver's, then the painting replays'."""
    from paintapp.bench.painting_families import painting_families
    from paintapp.bench.registry import Registry
    from paintapp.bench.solver_families import solver_families

    return Registry([*solver_families(), *painting_families()])


def run(args: argparse.Namespace) -> int:
    # imported here: scipy.signal and the benchmark modules are slow to load for other commands
    from tqdm import tqdm

    from paintapp.atomic import atomic_write_text
    from paintapp.bench.report import format_table, json_ready, plot_pareto
    from paintapp.output_paths import prepare_outputs

    registry = bench_registry()
    settings = registry.quick_settings() if args.quick else registry.full_settings()
    if args.only:
        unknown = sorted(set(args.only) - set(registry.families))
        if unknown:
            raise InputError(
                f"unknown family {', '.join(unknown)}; expected {', '.join(registry.families)}",
                key="--only",
            )
        settings = [s for s in settings if s.family in args.only]
    for flag, path in (("--json", args.json), ("--plot", args.plot)):
        if path is not None and not path.strip():
            raise InputError(f"expected a file name, got {path!r}", key=flag)
    prepare_outputs([("--json", args.json), ("--plot", args.plot)])
    start = time.perf_counter()
    records = []
    bar = tqdm(settings, unit="setting", file=sys.stderr, disable=None, leave=False)
    for setting in bar:
        bar.set_postfix_str(setting.label)
        records.append(registry.run_setting(setting))
    registry.cleanup()
    elapsed = time.perf_counter() - start
    print(format_table(records))
    print(f"{len(records)} settings in {elapsed:.1f} s")
    if args.json:
        atomic_write_text(args.json, json.dumps(json_ready(records), indent=1, allow_nan=False))
        print(f"wrote {args.json}")
    if args.plot:
        try:
            plot_pareto(records, list(registry.families.values()), args.plot)
        except ValueError as exc:  # nothing succeeded, so nothing to plot
            print(f"paintapp bench: error: {exc}", file=sys.stderr)
            return 1
        print(f"wrote {args.plot}")
    return 1 if any("failed" in r for r in records) else 0

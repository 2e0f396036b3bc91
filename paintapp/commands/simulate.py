"""``paintapp simulate SCENE.toml [--json OUT.json]``: run a fluid scene and report its results."""

from __future__ import annotations

import argparse
import json
import sys


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help="run a scene file (TOML) and write its results as JSON")
    p.add_argument("scene", help="scene file (TOML, schema version 1)")
    p.add_argument("--json", metavar="OUT.json", help="write the full results here")
    p.add_argument("--steps", type=int, help="override the number of steps (for a quick look)")
    p.add_argument(
        "--explain",
        action="store_true",
        help="before running, print what the solver will compute for this scene and why",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from paintapp.atomic import atomic_write_text
    from paintapp.output_paths import prepare_outputs
    from solver import (
        NonFiniteError,
        check_memory,
        explain,
        load_scene,
        run_scene,
        slow_step_warning,
    )

    scene = load_scene(args.scene)
    if args.steps is not None:
        if args.steps < 1:
            print("paintapp simulate: error: --steps must be >= 1", file=sys.stderr)
            return 2
        scene.run = type(scene.run)(scene.run.dt_s, args.steps)
    check_memory(scene)  # before anything is allocated
    prepare_outputs([("--json", args.json)])
    g = scene.grid
    cells = "x".join(str(c) for c in g.cells[: g.dim])
    print(
        f"scene {scene.name}: {g.dim}D {cells} cells, h = {g.cell_size_m:.4g} m, "
        f"{len(scene.probes)} probe(s), {scene.run.steps} steps of {scene.run.dt_s:g} s"
    )
    slow = slow_step_warning(scene)
    if slow:
        print(slow, file=sys.stderr)
    if args.explain:
        for decision in explain(scene.build(), scene.run.dt_s):
            print(f"  {decision.topic}: {decision.chosen}\n      because {decision.reason}")
    with tqdm(
        total=scene.run.steps, unit="step", file=sys.stderr, disable=None, leave=False
    ) as bar:
        try:
            results = run_scene(scene, progress=bar.update)
        except NonFiniteError as exc:
            print(f"paintapp simulate: error: {scene.source}: {exc}", file=sys.stderr)
            return 1
    _summarise(results)
    if args.json:
        try:  # strict JSON: the runner writes null (with a note) where it has no finite value
            text = json.dumps(results, indent=1, allow_nan=False)
        except ValueError as exc:
            print(f"paintapp simulate: error: the results are not finite: {exc}", file=sys.stderr)
            return 1
        atomic_write_text(args.json, text)
        print(f"wrote {args.json}")
    return 0


def _summarise(results: dict) -> None:
    import numpy as np

    t = results["timing"]
    print(
        f"median step {t['median_step_ms']:.3f} ms; pressure PCG "
        f"{t['pressure_iterations']['mean']:.1f} iterations (max residual "
        f"{t['pressure_max_residual']:.1e}); max |div u| "
        f"{results['diagnostics']['max_abs_divergence_per_s']:.2e} 1/s"
    )
    if t["unconverged_solves"]:
        print(
            f"warning: {t['unconverged_solves']} linear solve(s) stopped at the iteration cap "
            "before reaching the tolerance; raise solver.max_iterations or check the time step"
        )
    for name, rec in results["probes"].items():
        if rec["force"]:
            f = np.asarray(rec["force"][-1])
            tq = rec["torque"][-1]
            print(
                f"probe {name}: final force {np.array2string(f, precision=5)}, "
                f"torque {np.array2string(np.asarray(tq), precision=5)}"
            )
    for name, rec in results["points"].items():
        if "note" in rec:  # no fluid near the point: values are null in the JSON
            print(f"point {name}: {rec['note']}")
            continue
        print(
            f"point {name}: p = {rec['pressure']:.5g} Pa, u = "
            f"{np.array2string(np.asarray(rec['velocity']), precision=5)} m/s"
        )

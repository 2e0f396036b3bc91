"""``paintapp explore DATA [--probe circle|box|sphere --size M] [--path PATH.csv --forces F.csv]``.

Feel a flow someone else computed. DATA is pressure and velocity in SI units: on a regular grid
(one ``.npz``, one frame or a time series, or VTK ``.vti``, ``.vtr``, ``.vtk`` files), an
OpenFOAM case (its folder or ``.foam`` marker: the latest time, ``--time T`` or ``--all-times``;
``nu`` and the pressure's units from the case, so only ``--density`` is needed), or an
unstructured mesh (``.vtu``, ``.vtm``, legacy ``.vtk``, a ``.pvd`` or ``.series`` time series).
A rigid probe in the flow feels the stress integral of the stored fields over its surface
(pressure plus viscous traction; on a mesh, resampled around the probe onto a local grid
``--refine`` times finer than the mesh there); the probe does not change the data. The force goes
through the same servo loop, filter and safety as painting. A 2D mesh one cell thick is felt
over its thickness unless ``--depth`` says otherwise.

With ``--path`` the probe follows a scripted path (CSV: ``t_s, x_m, y_m[, z_m][, angle_rad |
qw, qx, qy, qz]``) and ``--forces`` writes the force trace, one row per servo tick: the force
written to the device and the fluid's physical force and torque (``fluid_force_x_n``, ...). Without it the window opens: a slice of the field with the probe, driven by the mouse or
the haptic device (``--device sim|hid:VID:PID|openhaptics[:NAME]|dhd|haply[:ID]|none``).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from common.errors import InputError

if TYPE_CHECKING:
    from paintapp.explore.exploration import Exploration

EXAMPLE = "schaefer_turek_2d2.npz"


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "explore",
        help="feel a flow computed offline (CFD data: OpenFOAM cases, .vtu, .vtm, .pvd, .series, "
        ".npz, .vti, .vtr, .vtk) with a probe",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument(
        "data",
        nargs="+",
        metavar="DATA",
        help=f"data file(s) or an OpenFOAM case, or 'example' for the bundled {EXAMPLE} "
        "(Schaefer-Turek 2D-2)",
    )
    times = parser.add_mutually_exclusive_group()
    times.add_argument(
        "--time", type=float, metavar="T", help="OpenFOAM case or series: read time T (s)"
    )
    times.add_argument(
        "--all-times", action="store_true", help="OpenFOAM case: read every time as a series"
    )
    parser.add_argument(
        "--refine",
        type=float,
        default=2.0,
        metavar="F",
        help="mesh: local grid spacing = the finest cell size near the probe / F (>= 1)",
    )
    parser.add_argument(
        "--probe",
        default=None,
        choices=("circle", "box", "sphere"),
        help="probe shape (default: circle in 2D, sphere in 3D)",
    )
    parser.add_argument(
        "--size",
        type=float,
        nargs="+",
        metavar="M",
        help="diameter, or the box's edge(s), metres (default: 8 node spacings, at most half the "
        "data set's longest side; larger than that side is an error)",
    )
    parser.add_argument(
        "--depth", type=float, metavar="M", help="2D: depth of the probe the force is felt over"
    )
    parser.add_argument("--path", type=Path, metavar="PATH.csv", help="scripted probe path")
    parser.add_argument("--forces", type=Path, metavar="F.csv", help="write the force trace")
    parser.add_argument("--plot", type=Path, metavar="F.png", help="plot the force trace")
    parser.add_argument(
        "--rate", type=float, default=200.0, metavar="HZ", help="force evaluations per second"
    )
    parser.add_argument(
        "--loop", action="store_true", help="repeat the frames (a periodic flow) past the last one"
    )
    parser.add_argument("--force-scale", type=float, default=1.0, help="haptic force scale")
    parser.add_argument("--density", type=float, help="kg/m^3, if the file does not say")
    parser.add_argument("--viscosity", type=float, help="dynamic, Pa s, if the file does not say")
    parser.add_argument(
        "--pressure-units", choices=("Pa", "m2/s2"), help="if the file does not say (default Pa)"
    )
    parser.add_argument("--frame-dt", type=float, metavar="S", help="VTK series without times")
    parser.add_argument(
        "--device",
        default="none",
        metavar="sim|hid:VID:PID|openhaptics|dhd|haply|none",
        help="haptic device (window)",
    )
    parser.set_defaults(func=run)


def _data_paths(args: argparse.Namespace) -> list[Path]:
    if args.data == ["example"]:
        from paintapp.resources import asset_path

        return [asset_path("flows", EXAMPLE)]
    return [Path(d) for d in args.data]


def build_exploration(args: argparse.Namespace) -> Exploration:
    """Load the data and place the probe the arguments describe."""
    from paintapp.explore.flow_files import FluidOverrides, load_flow
    from paintapp.explore.local_resample import ResampleSpec
    from paintapp.explore.openfoam_case import CaseSelection

    if not (math.isfinite(args.refine) and 1.0 <= args.refine <= 16.0):
        raise InputError(f"expected a factor in [1, 16], got {args.refine}", key="--refine")
    overrides = FluidOverrides(args.density, args.viscosity, args.frame_dt, args.pressure_units)
    selection = CaseSelection(args.time, args.all_times)
    flow = load_flow(_data_paths(args), overrides, selection)  # checked before the numerics
    from paintapp.explore.exploration import Exploration, ProbeSpec

    shape = args.probe or ("circle" if flow.dim == 2 else "sphere")
    lo, hi = flow.extent_m
    default = min(8.0 * float(flow.spacing_m.min()), 0.5 * float((hi - lo).max()))
    size = tuple(args.size) if args.size else (default,)
    return Exploration(
        flow, ProbeSpec(shape, size, args.depth), resample=ResampleSpec(refine=args.refine)
    )


def run(args: argparse.Namespace) -> int:
    outputs = (("--forces", args.forces), ("--plot", args.plot))
    for flag, value in outputs:
        if value is not None and args.path is None:
            raise InputError(f"{flag} needs a scripted --path", key=flag)
    if args.path is None:
        return _window(args)
    from paintapp.explore.probe_paths import read_probe_path
    from paintapp.output_paths import prepare_outputs

    prepare_outputs(outputs)  # before any work: writable, not a folder, not the same file twice
    exploration = build_exploration(args)
    from paintapp.explore.exploration import run_scripted
    from paintapp.explore.force_trace import plot_explore_forces, write_explore_forces_csv
    from paintapp.explore.unstructured import UnstructuredFlow

    path = read_probe_path(args.path, exploration.flow.dim)
    result = run_scripted(
        exploration, path, rate_hz=args.rate, force_scale=args.force_scale, loop=args.loop
    )
    flow = exploration.flow
    lo, hi = flow.extent_m
    unit = "N/m per depth" if flow.dim == 2 else "N"
    if isinstance(flow, UnstructuredFlow):
        data = flow.describe()
    else:
        data = (
            f"{flow.dim}D data, {'x'.join(map(str, flow.nodes))} nodes, "
            f"{len(flow.times_s)} frame(s)"
        )
    print(
        f"{data}, extent {lo.round(4).tolist()} .. {hi.round(4).tolist()} m; probe "
        f"{exploration.probe.shape} {exploration.probe.size_m} m ({unit} x "
        f"{exploration.depth_m:g} m felt)"
    )
    felt = result.evaluations[:, 1:4]
    peak = float(abs(felt).max()) if len(felt) else 0.0
    print(
        f"{len(result.evaluations)} force evaluations, peak |F| component {peak:.4g} N, "
        f"{len(result.trace)} servo ticks"
    )
    if result.outside_evaluations:
        print(
            f"warning: part of the probe left the data set in {result.outside_evaluations} "
            "evaluations (the nearest boundary values were used there)",
            file=sys.stderr,
        )
    if args.forces is not None:
        write_explore_forces_csv(args.forces, result.trace, result.evaluations)
        print(f"wrote {args.forces}")
    if args.plot is not None:
        title = f"force on the probe ({path.source})"
        plot_explore_forces(args.plot, result.trace, result.evaluations, title)
        print(f"wrote {args.plot}")
    return 0


def _window(args: argparse.Namespace) -> int:
    from paintapp.app.explore_launch import launch_explorer

    return launch_explorer(args, build_exploration)

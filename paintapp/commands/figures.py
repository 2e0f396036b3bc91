"""``paintapp figures NAME --out F.png``: reproduce the paper's figures as plots.

Each figure lives in its own module under :mod:`paintapp.figures` and exposes
``register(subparsers)`` like a command does.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil

import paintapp.figures


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("figures", help="write the paper's figures as PNG plots")
    figs = parser.add_subparsers(dest="figure", metavar="FIGURE")
    for info in sorted(pkgutil.iter_modules(paintapp.figures.__path__), key=lambda m: m.name):
        if not info.name.startswith("_"):
            importlib.import_module(f"paintapp.figures.{info.name}").register(figs)
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])

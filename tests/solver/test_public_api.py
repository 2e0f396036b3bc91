"""The solver's public API: every exported name loads, lazily, from the module that holds it."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import solver
from tests.support.imports import loads_module

INIT = Path(solver.__file__)


def _type_checking_imports() -> dict[str, str]:
    """Name -> module of the imports under ``if TYPE_CHECKING:`` in solver/__init__.py."""
    tree = ast.parse(INIT.read_text())
    found: dict[str, str] = {}
    for node in tree.body:
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            for imp in node.body:
                assert isinstance(imp, ast.ImportFrom) and imp.module is not None
                for alias in imp.names:
                    found[alias.name] = imp.module
    return found


def test_all_names_the_homes_and_the_type_checking_imports_alike() -> None:
    homes = solver._HOME  # type: ignore[attr-defined]
    assert sorted(solver.__all__) == sorted(homes)
    assert _type_checking_imports() == homes


@pytest.mark.parametrize("name", solver.__all__)
def test_each_name_is_the_object_its_module_holds(name: str) -> None:
    home = importlib.import_module(solver._HOME[name])  # type: ignore[attr-defined]
    assert getattr(solver, name) is getattr(home, name)


def test_an_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        _ = solver.nonexistent  # type: ignore[attr-defined]


def test_a_light_name_does_not_load_the_simulation() -> None:
    code = "from solver import FLUID, SolverSettings\nassert FLUID == -1"
    assert not loads_module(code, "solver.simulation")

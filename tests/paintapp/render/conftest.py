"""The render tests' headless OpenGL context and the bundled pigments."""

from __future__ import annotations

import pytest

from paintapp.pigments.library import bundled_pigments
from paintapp.render import RenderUnavailable, create_headless_context


@pytest.fixture(scope="module")
def ctx():
    try:
        context = create_headless_context()
    except RenderUnavailable as exc:
        pytest.skip(f"no headless OpenGL (EGL) on this machine: {exc}")
    yield context
    context.release()


@pytest.fixture(scope="module")
def library():
    return bundled_pigments()

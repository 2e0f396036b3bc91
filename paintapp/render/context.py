"""OpenGL contexts and shader programs.

Headless rendering uses an EGL standalone context (Mesa llvmpipe on machines without a GPU).
Each program is one GLSL file under ``shaders/`` holding both stages; :func:`program_sources`
prepends the ``#version`` line, the stage define and any compile-time constants.
"""

from __future__ import annotations

from collections.abc import Mapping

import moderngl

from paintapp.resources import shader_source

GLSL_VERSION = "#version 330 core"
#: Every program shipped in ``shaders/`` (file ``<name>.glsl``).
PROGRAM_NAMES: tuple[str, ...] = ("canvas", "overlay", "picture")


class RenderUnavailable(RuntimeError):
    """No OpenGL context could be created (no EGL / driver); the message says why."""


def create_headless_context() -> moderngl.Context:
    """A standalone OpenGL 3.3+ context through EGL; raises :class:`RenderUnavailable`."""
    try:
        # moderngl's stubs type **settings as dict values; backend is a str.
        return moderngl.create_standalone_context(backend="egl", require=330)  # type: ignore[arg-type]
    except Exception as exc:  # moderngl/glcontext raise plain Exceptions for missing drivers
        raise RenderUnavailable(f"cannot create a headless EGL OpenGL context: {exc}") from exc


def program_sources(name: str, defines: Mapping[str, int | float] | None = None) -> tuple[str, str]:
    """(vertex, fragment) source text of ``shaders/<name>.glsl`` with the given ``#define``s."""
    body = shader_source(f"{name}.glsl")
    header = "".join(f"#define {key} {value}\n" for key, value in (defines or {}).items())
    return tuple(  # type: ignore[return-value]
        f"{GLSL_VERSION}\n#define {stage}\n{header}#line 1\n{body}"
        for stage in ("VERTEX_SHADER", "FRAGMENT_SHADER")
    )


def load_program(
    ctx: moderngl.Context, name: str, defines: Mapping[str, int | float] | None = None
) -> moderngl.Program:
    """Compile and link program ``name``; compile errors propagate with the GL log."""
    vertex, fragment = program_sources(name, defines)
    return ctx.program(vertex_shader=vertex, fragment_shader=fragment)

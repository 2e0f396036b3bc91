"""Wait for the OpenGL work queued in the current context with the interpreter lock released.

moderngl holds Python's interpreter lock through every call, so a read-back
(``Framebuffer.read``) that has to wait for the rasterizer blocks every other Python thread
meanwhile: in the painting window, the simulation worker. On a software rasterizer (llvmpipe)
that wait is the whole fragment shading. :func:`gl_finish` calls ``glFinish`` through ctypes,
which releases the lock during foreign calls, so the read-back that follows only copies pixels.
The function comes from ``eglGetProcAddress`` (the headless contexts are EGL's).
"""

from __future__ import annotations

import ctypes
import functools
from collections.abc import Callable


@functools.cache
def _gl_finish() -> Callable[[], None] | None:
    try:
        egl = ctypes.CDLL("libEGL.so.1")
        lookup = egl.eglGetProcAddress
    except (OSError, AttributeError):
        return None
    lookup.restype = ctypes.c_void_p
    lookup.argtypes = [ctypes.c_char_p]
    address = lookup(b"glFinish")
    if not address:
        return None
    return ctypes.CFUNCTYPE(None)(address)


def gl_finish() -> bool:
    """``glFinish`` in the current context, the interpreter lock released meanwhile; False when
    the function is unavailable (the caller's read-back then waits holding the lock)."""
    finish = _gl_finish()
    if finish is None:
        return False
    finish()
    return True

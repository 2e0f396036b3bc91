"""Starting the app: the display check, Qt and OpenGL set-up, recovery, the device, the window."""

from __future__ import annotations

import gc
import os
import sys
from pathlib import Path

from common.errors import InputError
from paintapp.app.options import PaintOptions, blank_canvas
from paintapp.canvas.model import Canvas
from paintapp.pigments.library import PigmentLibrary, load_pigment_library

NO_DISPLAY = (
    "no display: paintapp paint opens a window and needs a graphical session "
    "(DISPLAY or WAYLAND_DISPLAY; QT_QPA_PLATFORM to choose a Qt platform).\n"
    "Without one, paint from a stroke file instead:\n"
    "  paintapp demo                      replay the bundled demo strokes\n"
    "  paintapp replay STROKES.jsonl      replay a recording onto a canvas"
)


def display_available() -> bool:
    """Whether a window can be opened (always on macOS and Windows)."""
    if sys.platform in ("darwin", "win32"):
        return True
    return any(os.environ.get(k) for k in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"))


def qt_application():
    """The QApplication (created once, with an OpenGL 3.3 core default surface)."""
    from PySide6.QtGui import QSurfaceFormat
    from PySide6.QtWidgets import QApplication

    app = QApplication.instance()
    if app is None:
        fmt = QSurfaceFormat()
        fmt.setVersion(3, 3)
        fmt.setProfile(QSurfaceFormat.OpenGLContextProfile.CoreProfile)
        fmt.setSwapInterval(0)
        QSurfaceFormat.setDefaultFormat(fmt)
        app = QApplication([sys.argv[0] if sys.argv else "paintapp"])
        app.setApplicationName("paintapp")
    return app


def _ask_recover(text: str) -> bool:
    from PySide6.QtWidgets import QMessageBox

    buttons = QMessageBox.StandardButton
    answer = QMessageBox.question(
        None, "Recover paint?", f"{text}\n\nRecover it?", buttons.Yes | buttons.No
    )
    return answer == buttons.Yes


def starting_canvas(
    options: PaintOptions, library: PigmentLibrary
) -> tuple[Canvas, Path | None, str]:
    """The canvas to start with, its file, and a note: the given file, a recovered autosave
    (asked, or as ``options.recover`` says), or a blank canvas."""
    from paintapp.app.recovery import Recovery
    from paintapp.canvas.exr import read_canvas_exr

    recovery = Recovery(options.recovery_dir, library)
    pending = recovery.pending()
    if pending is not None:
        wanted = options.recover == "yes" or (
            options.recover == "ask" and _ask_recover(pending.describe())
        )
        if wanted:
            canvas = recovery.load()
            document = Path(pending.document) if pending.document else None
            recovery.discard()
            return canvas, document, "recovered the autosave"
        recovery.discard()
    if options.canvas_path is not None:
        canvas = read_canvas_exr(options.canvas_path)
        library.require(canvas.pigment_names, source=str(options.canvas_path))
        return canvas, options.canvas_path, f"opened {options.canvas_path}"
    return blank_canvas(options=options), None, "new canvas"


def start_link(options: PaintOptions, surface: str = "smooth"):
    """The started haptic link: the servo process, or the thread form when asked for or when a
    process cannot be started (the note says why); its canvas contact follows ``surface``'s
    tooth. DeviceNotFoundError if the device is absent."""
    from paintapp.app.haptic_link import HapticLink
    from paintapp.haptics.device import DeviceNotFoundError

    scale = options.settings.force_scale
    if options.servo == "process":
        # the window arms the heartbeat watchdog once its start-up is over
        link = HapticLink(options.device, None, scale, mode="process", armed=False, surface=surface)
        try:
            link.start()
            return link
        except DeviceNotFoundError:
            raise
        except (RuntimeError, OSError) as exc:
            print(
                f"servo process unavailable ({exc}); running the servo loop in a thread",
                file=sys.stderr,
            )
    link = HapticLink(options.device, None, scale, mode="thread", surface=surface)
    link.start()
    return link


def create_window(options: PaintOptions, interactive: bool = True):
    """Make the QApplication and the window (shown); returns ``(app, window)``.

    Raises :class:`InputError` for a missing display, an unreadable canvas or a device that
    cannot be opened.
    """
    if not display_available():
        raise InputError(NO_DISPLAY)
    app = qt_application()
    from paintapp.app.window import PaintWindow

    library = load_pigment_library()
    canvas, document, note = starting_canvas(options, library)
    link = None
    if options.device.kind != "none":
        link = start_link(options, canvas.surface)
    try:
        window = PaintWindow(canvas, library, options, link, document, interactive)
    except BaseException:
        if link is not None:
            link.stop()
        raise
    window.statusBar().showMessage(note, 5000)
    window.show()
    return app, window


def freeze_startup_heap() -> int:
    """Move everything alive now (modules, compiled kernels, the window) out of the cyclic
    garbage collector's reach, and return how many objects that was.

    The collector's full pass scans every tracked object while holding the interpreter lock: with
    the app's start-up objects, a visible freeze of the window and the simulation whenever a long
    session ages enough new objects to trigger one. After the freeze a pass scans only what was
    made since (start-up objects are never garbage)."""
    gc.collect()
    gc.freeze()
    return gc.get_freeze_count()


def release_startup_heap() -> None:
    """Undo :func:`freeze_startup_heap` once the window has closed: frozen objects outlive the
    interpreter's last collection, and OpenImageIO's bindings then print every instance, type and
    function of theirs still alive as leaked, some 800 lines at every exit."""
    gc.unfreeze()
    gc.collect()


def run_paint(options: PaintOptions) -> int:
    """Run the app until its window closes; returns the exit status."""
    app, window = create_window(options)
    freeze_startup_heap()
    status = app.exec()
    window.deleteLater()
    release_startup_heap()
    return int(status)

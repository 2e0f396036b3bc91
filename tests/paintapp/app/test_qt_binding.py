"""The Qt binding keeps Python's reference counts: a window calls void Qt methods (``update``,
``setText`` ...) hundreds of times a second for as long as it is open.

PySide6-Essentials 6.12.0 on Python 3.11 drops a reference to ``None`` on every call of a method
returning void; ``None`` is not immortal before Python 3.12, so a painting session ended, after
some thousands of frames, in "Fatal Python error: none_dealloc". pyproject excludes that release.
"""

from __future__ import annotations

import sys


def test_void_qt_calls_keep_the_reference_count_of_none(qapp):
    from PySide6.QtCore import QRect
    from PySide6.QtWidgets import QWidget

    widget = QWidget()
    widget.resize(64, 48)
    calls = 2000
    before = sys.getrefcount(None)
    for i in range(calls):
        widget.update(QRect(0, 0, 8, 8))
        widget.setWindowTitle(str(i & 1))
    lost = before - sys.getrefcount(None)
    widget.deleteLater()
    # Other threads may take or drop a few references meanwhile; a broken binding loses 4000.
    assert lost < calls // 10, f"{lost} references to None lost over {2 * calls} void calls"

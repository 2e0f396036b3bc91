"""Processes the servo-process tests start and kill: a stand-in for the app, a seqlock writer.

Both run under the ``spawn`` start method (so they are module-level functions here).
"""

from __future__ import annotations

import math
import time
from multiprocessing.connection import Connection

import numpy as np

from paintapp.haptics.process import ProcessOptions, ServoProcess
from paintapp.haptics.shared_state import SeqlockRecord, SharedBlock

#: Where the harness's simulated hand paints (canvas frame, m).
PAINT_AT = (0.03, 0.03)


def app_stand_in(conn: Connection, press_m: float = 0.0015) -> None:
    """Act as the app: start a servo process (simulated hand), press the hand into the canvas,
    publish a fluid force at 100 Hz, and report ``(block name, child pid)`` on ``conn``. Runs
    until killed (or for 120 s)."""
    servo = ServoProcess(ProcessOptions(device="sim", start_m=(*PAINT_AT, 0.005)))
    servo.start()
    conn.send((servo.block.name, servo.pid))
    start = time.monotonic()
    pressing = False
    while time.monotonic() - start < 120.0:
        t = time.monotonic() - start
        engaged = servo.audit()["last_force_n"] > 0  # only press once the output is engaged
        pressing = pressing or engaged
        servo.target.set_position((*PAINT_AT, -press_m if pressing else 0.005))
        servo.forces.publish_force(t, [0.05 * math.sin(3 * t), 0.05, 0.0], [0.0, 0.0, 0.001])
        time.sleep(0.01)
    servo.stop()


def seqlock_writer(name: str, writes: int) -> None:
    """Write ``writes`` records into the block's force record, every value equal to the write's
    index, as fast as possible (a reader must never see a mix)."""
    block = SharedBlock(name)
    record: SeqlockRecord = block.force
    values = np.empty(record.width)
    for i in range(1, writes + 1):
        values.fill(float(i))
        record.write(values)
    block.close()

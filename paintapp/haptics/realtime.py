"""Real-time hygiene for the servo process: priority, a core of its own, no GC pauses, locked memory.

:func:`apply_realtime` asks the OS for what it will grant and says what it got
(:class:`Granted`): a real-time scheduling class (``SCHED_FIFO``, else ``SCHED_RR``) when the user
may (root or ``CAP_SYS_NICE``, or an ``rtprio`` limit), else a lower nice value; pinning to one
core when there are several (the last one: the GUI and the simulation start on the first); the
cyclic garbage collector frozen and disabled (every object made so far is moved out of its reach;
the loop's short-lived arrays are freed by reference counting, so no collection ever runs inside
a tick); and the process's pages locked in memory when permitted. Linux's real-time throttling
(``sched_rt_runtime_us``, 95 % by default) still leaves the other tasks some time on that core,
and the loop sleeps most of every period anyway.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import os
from dataclasses import dataclass

#: Real-time priority asked for (1-99; the kernel's own threads sit at 50 and above).
RT_PRIORITY = 40
#: Nice values tried, best first, when no real-time class is granted.
NICE_STEPS = (-15, -10, -5, -1)
_MCL_CURRENT = 1


@dataclass(frozen=True)
class Granted:
    """What the OS granted the servo process.

    Attributes:
        scheduler: "SCHED_FIFO 40", "SCHED_RR 40", "nice -10" or "normal".
        cpu: the core it is pinned to, or None.
        gc: "off" once the collector is disabled, else "on".
        memory_locked: whether its pages are locked in memory.
    """

    scheduler: str = "normal"
    cpu: int | None = None
    gc: str = "on"
    memory_locked: bool = False

    @property
    def realtime(self) -> bool:
        """Whether a real-time scheduling class was granted."""
        return self.scheduler.startswith("SCHED_")

    def describe(self) -> str:
        """One line for the HUD and ``haptics-check``."""
        cpu = "not pinned" if self.cpu is None else f"pinned to CPU {self.cpu}"
        mem = "memory locked" if self.memory_locked else "memory not locked"
        return f"{self.scheduler}, {cpu}, GC {self.gc}, {mem}"


def _scheduler(priority: int) -> str:
    for name in ("SCHED_FIFO", "SCHED_RR"):
        policy = getattr(os, name, None)
        if policy is None:
            continue
        try:
            os.sched_setscheduler(0, policy, os.sched_param(priority))
            return f"{name} {priority}"
        except (OSError, AttributeError):
            continue
    for step in NICE_STEPS:
        try:
            current = os.getpriority(os.PRIO_PROCESS, 0)
            if step >= current:
                return f"nice {current}" if current < 0 else "normal"
            os.setpriority(os.PRIO_PROCESS, 0, step)
            return f"nice {step}"
        except (OSError, AttributeError):
            continue
    return "normal"


def _pin(cpu: int | None) -> int | None:
    try:
        cpus = sorted(os.sched_getaffinity(0))
    except (OSError, AttributeError):
        return None
    if len(cpus) < 2:
        return None
    chosen = cpus[-1] if cpu is None else cpu
    try:
        os.sched_setaffinity(0, {chosen})
    except (OSError, ValueError):
        return None
    return chosen


def _lock_memory() -> bool:
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        return int(libc.mlockall(_MCL_CURRENT)) == 0
    except (OSError, AttributeError):
        return False


def apply_realtime(
    priority: int = RT_PRIORITY, pin: bool = True, cpu: int | None = None, lock_memory: bool = True
) -> Granted:
    """Ask for real-time treatment for the calling process (see the module docstring).

    Call it once everything the loop needs is built: the collector is frozen and disabled last.
    """
    scheduler = _scheduler(priority)
    pinned = _pin(cpu) if pin else None
    locked = _lock_memory() if lock_memory else False
    gc.collect()
    gc.freeze()
    gc.disable()
    return Granted(scheduler, pinned, "off", locked)

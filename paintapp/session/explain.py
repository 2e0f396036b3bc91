"""``--explain`` for replays: every modelling decision with its reason, and what ran.

:func:`explain_session` lists the session's decisions (:attr:`PaintingSession.decisions`: the
set-up, each touch-down, model switch and grid refit, and the solver's own choices the first
time each model runs) and then the counts of a replay: samples in the air, steps per model with
their solver steps and time, the grids used, the pigment channels carried, switches and refits.
:func:`choice_summary` gives the same counts as a JSON-ready dict (the bench uses it).
"""

from __future__ import annotations

from typing import Any

from paintapp.session.painting import PaintingSession


def choice_summary(session: PaintingSession) -> dict[str, Any]:
    """What ran in ``session``: counts per model kind, grid and channel count (JSON-ready)."""
    st, ch = session.stats, session.choices
    return {
        "samples": st.samples,
        "air_samples": st.air_samples,
        "dry_steps": st.dry_steps,
        "paint_steps": st.paint_steps,
        "solver_steps": st.solver_steps,
        "steps_by_model": dict(ch.steps),
        "solver_steps_by_model": dict(ch.solver_steps),
        "stokes_steps_by_model": dict(ch.stokes_steps),
        "ms_by_model": {k: round(v, 1) for k, v in ch.step_ms.items()},
        "grids": dict(ch.grids),
        "channels": {str(k): v for k, v in sorted(ch.channels.items())},
        "switches": ch.switches,
        "refits": ch.refits,
        "outputs": session.needs.describe(),
    }


def _counts(session: PaintingSession) -> list[str]:
    st, ch = session.stats, session.choices
    contact = st.samples - st.air_samples
    lines = [
        f"samples: {st.samples} ({contact} in contact; {st.air_samples} in the air, no steps)",
    ]
    for kind, n in ch.steps.most_common():
        solver = ch.solver_steps.get(kind, 0)
        ms = ch.step_ms.get(kind, 0.0)
        lines.append(f"  {kind:<15} {n:>5} steps, {solver:>5} solver steps, {ms / 1e3:7.2f} s")
        if ch.stokes_steps.get(kind, 0):
            lines.append(
                f"  {'':<15} {ch.stokes_steps[kind]:>5} of them as Stokes flow "
                f"(Re < {session.scene.choose.stokes_below_re:g}: no momentum advection)"
            )
    grids = ", ".join(f"{label}: {n}" for label, n in ch.grids.most_common())
    lines.append(f"grids used (steps): {grids or 'none'}")
    total = len(session.canvas.pigment_names)
    chans = ", ".join(f"{k}: {n}" for k, n in sorted(ch.channels.items()))
    lines.append(f"pigment channels carried (of {total}), steps: {chans or 'none'}")
    lines.append(f"model switches: {ch.switches}, grid refits: {ch.refits}")
    lines.append(f"outputs: {session.needs.describe()}")
    if session.selector.dropped_decisions:
        lines.append(f"({session.selector.dropped_decisions} later decisions not logged)")
    return lines


def explain_session(session: PaintingSession, header: str | None = None) -> str:
    """The decisions and counts of ``session`` as text (``header`` first, if given)."""
    lines = [header] if header else []
    lines.append("decisions:")
    lines += [f"  {d}" for d in session.decisions]
    lines.append("what ran:")
    lines += [f"  {line}" for line in _counts(session)]
    return "\n".join(lines)

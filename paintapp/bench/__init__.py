"""``paintapp bench``: cost against accuracy over the knobs that trade one for the other.

Modules: :mod:`~paintapp.bench.registry` (families, settings, running them),
:mod:`~paintapp.bench.solver_families` and :mod:`~paintapp.bench.painting_families` (the families the
command composes), :mod:`~paintapp.bench.noise` (the force-noise definition),
:mod:`~paintapp.bench.measure` (step time and memory), :mod:`~paintapp.bench.references` (Ghia
cavity, Schaefer-Turek c_D, Taylor-Green decay), :mod:`~paintapp.bench.square_sweep` and
:mod:`~paintapp.bench.sweep_force` (the paper's square-probe sweep), :mod:`~paintapp.bench.rates`
(simulation rate against the servo rate, per reconstruction filter), :mod:`~paintapp.bench.report`
(table, Pareto plot); and the timing checks behind other commands and scripts:
:mod:`~paintapp.bench.servo_check` (``paintapp haptics-check``) and
:mod:`~paintapp.bench.render_timing` (the renderer), with :mod:`~paintapp.bench.host_steal` (the CPU time
the host took meanwhile).
"""

"""``paintapp bench``: cost against accuracy over the knobs that trade one for the other.

Modules: :mod:`.registry` (families, settings, running them), :mod:`.solver_families` and
:mod:`.painting_families` (the families the command composes), :mod:`.noise` (the force-noise
definition), :mod:`.measure` (step time and memory), :mod:`.references` (Ghia cavity,
Schaefer-Turek c_D, Taylor-Green decay), :mod:`.square_sweep` and :mod:`.sweep_force` (the
paper's square-probe sweep), :mod:`.rates` (simulation rate against the servo rate, per
reconstruction filter), :mod:`.report` (table, Pareto plot); and the timing checks behind other
commands and scripts: :mod:`.servo_check` (``paintapp haptics-check``) and :mod:`.render_timing`
(the renderer), with :mod:`.host_steal` (the CPU time the host took meanwhile).
"""

"""Feeling a flow someone else computed (``paintapp explore``): reading CFD data sets
(:mod:`.flow_files`, VTK through :mod:`.vtk_files`; a frame as a reader found it,
:mod:`.flow_frame`), writing ours (:mod:`.flow_export`), scripted probe paths
(:mod:`.probe_paths`), and the probe whose force reaches the servo loop (:mod:`.exploration`).
The force itself is the solver's stress integral over the probe's exact surface
(:mod:`solver.sampled.forces`)."""

"""Scene files and what a run will do: the TOML schema (:mod:`.scene`), running a scene to the end
(:mod:`.runner`), the model plan behind ``--explain`` (:mod:`.plan`) and the memory and time
budget checked before a run (:mod:`.budget`).
"""

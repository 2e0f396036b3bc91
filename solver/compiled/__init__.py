"""The numba plumbing every kernel module shares: the compile options (:mod:`.jit`), kernels
compiled serial and parallel (:mod:`.parallel`), unsigned index constants (:mod:`.unsigned`), the
layer count of a 2D grid (:mod:`.layers`), the velocity components' work on two threads
(:mod:`.threads`) and the choice between ways of doing the same work by measurement
(:mod:`.timed_choice`).
"""

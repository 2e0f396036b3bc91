"""Linear solvers for the 7-point stencil systems: MIC(0)/Jacobi PCG (:mod:`.pcg`), the multigrid
preconditioner (:mod:`.multigrid`) and warm starts from the last step's solution
(:mod:`.warm_start`).
"""

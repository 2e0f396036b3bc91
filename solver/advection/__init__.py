"""Moving things with the flow: semi-Lagrangian advection of the staggered velocity
(:mod:`.velocity`) and conservative transport of cell-centred scalars such as paint
(:mod:`.scalars`, first-order upwind, with the flux-corrected sharpening of :mod:`.fct`).
"""

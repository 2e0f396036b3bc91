"""The paper's voxelized boundary: each cell all fluid or all solid (Baxter & Lin 2004, eqs. 9-18).

Face classification and rigid no-slip values (:mod:`.faces`), implicit viscosity
(:mod:`.viscosity`), the Chorin projection (:mod:`.projection`) and the staircase stress integral
(:mod:`.stress`). Kept as the method to compare the cut cells against.
"""

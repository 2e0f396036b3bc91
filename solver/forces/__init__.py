"""Force models beside the surface stress integral: the momentum balance over a control volume
(:mod:`.momentum_balance`) and the paper's cheap drag approximations (:mod:`.drag_models`).
"""

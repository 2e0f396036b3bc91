"""Random stencil systems and their sparse-matrix form, for the linear solver tests."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from solver.linalg.pcg import StencilSystem


def random_system(
    shape: tuple[int, int, int], dim: int, seed: int = 0, margin: float = 0.5, low: float = 0.2
) -> StencilSystem:
    """A random symmetric 7-point system: ~85 % of entries active, couplings in [low, 1], a
    diagonal margin ``margin`` over the couplings' sum (positive: diagonally dominant and SPD;
    0: a Neumann Laplacian with random face weights, singular on each connected region)."""
    rng = np.random.default_rng(seed)
    s = StencilSystem.empty(shape, dim)
    s.active[:] = rng.random(shape) > 0.15
    for b in range(dim):
        off = -rng.uniform(low, 1.0, shape)
        sl = [slice(None)] * 3
        sl[b] = slice(-1, None)
        off[tuple(sl)] = 0.0
        nb = np.roll(s.active, -1, axis=b)
        off[~(s.active & nb)] = 0.0
        s.off[b][:] = off
    # diagonal dominance makes it SPD
    diag = np.full(shape, margin)
    for b in range(dim):
        diag += -s.off[b] - np.roll(s.off[b], 1, axis=b)
    s.diag[:] = np.where(s.active, diag, 0.0)
    return s


def to_sparse(s: StencilSystem) -> tuple[sp.csr_matrix, np.ndarray]:
    idx = np.flatnonzero(s.active.ravel())
    pos = -np.ones(s.active.size, dtype=int)
    pos[idx] = np.arange(idx.size)
    rows, cols, vals = list(idx), list(idx), list(s.diag.ravel()[idx])
    strides = [s.active.shape[1] * s.active.shape[2], s.active.shape[2], 1]
    for b in range(s.dim):
        off = s.off[b].ravel()
        for n in idx:
            if off[n] != 0.0:
                m = n + strides[b]
                rows += [n, m]
                cols += [m, n]
                vals += [off[n], off[n]]
    a = sp.coo_matrix((vals, (pos[rows], pos[cols])), shape=(idx.size, idx.size)).tocsr()
    return a, idx

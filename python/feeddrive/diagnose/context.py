"""The residuals of all runs stacked over their valid samples, with held-out blocks.

Candidate regressors are built per run (unfiltered force columns), filtered with the run's
acceleration kernel K (as the residual's force side is) and stacked like the residual.
The part of a column that the run's estimated GMS start state could take up
(:mod:`feeddrive.physics.gms_start`: the start forces are re-estimated with any new model)
is projected out: a run whose elements never slip cannot tell a constant force from the
friction they hold, and must not count against (or for) a candidate because of it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..model_file import ModelFile
from ..physics import PlantParameters, compile
from ..residual import RunResidual

#: Held-out blocks over all runs (contiguous pieces of each run).
DEFAULT_BLOCKS = 10
#: Fewest samples in a held-out block.
MIN_BLOCK = 100


@dataclass
class Context:
    """Stacked residual of every run (valid samples only) and the block of each sample."""

    res: list[RunResidual]
    model: ModelFile
    n_blocks: int = DEFAULT_BLOCKS
    r: np.ndarray = field(init=False)
    block: np.ndarray = field(init=False)
    run_id: np.ndarray = field(init=False)
    guard: list[np.ndarray] = field(init=False)
    block_bounds: list[tuple[int, int]] = field(init=False)
    #: per-context memo of expensive per-run signals (e.g. the GMS sliding share)
    cache: dict = field(init=False, default_factory=dict)
    #: the model compiled (effect switches applied)
    plant: PlantParameters = field(init=False)

    def __post_init__(self) -> None:
        self.plant = compile(self.model)
        self.r = np.concatenate([q.r[q.valid] for q in self.res])
        self.run_id = np.concatenate(
            [np.full(int(q.valid.sum()), j) for j, q in enumerate(self.res)]
        )
        per_run = max(2, int(np.ceil(self.n_blocks / len(self.res))))
        blocks, guards = [], []
        b0 = 0
        for q in self.res:
            n = int(q.valid.sum())
            if n < 2 * MIN_BLOCK:
                raise ValueError(
                    f"run {q.name!r}: {n} usable samples; the diagnosis needs at "
                    f"least {2 * MIN_BLOCK} per run (two held-out blocks)"
                )
            nb = min(per_run, n // MIN_BLOCK)
            edges = np.linspace(0, n, nb + 1).astype(int)
            bid = np.searchsorted(edges, np.arange(n), side="right") - 1 + b0
            blocks.append(bid)
            b0 += nb
        self.block = np.concatenate(blocks)
        # samples next to a block boundary (within a kernel length) are dropped from training
        # when either neighbour is held out: the filtered residual is correlated across it
        g = max(len(q.K) for q in self.res)
        self.block_bounds = []
        for b in range(b0):
            idx = np.flatnonzero(self.block == b)
            lo, hi = int(idx[0]), int(idx[-1]) + 1
            self.block_bounds.append((lo, hi))
            near = np.r_[max(lo - g, 0) : lo, hi : min(hi + g, len(self.r))]
            near = near[self.run_id[near] == self.run_id[lo]]
            guards.append(near.astype(int))
        self.guard = guards

    @property
    def blocks(self) -> int:
        """Number of held-out blocks."""
        return len(self.guard)

    def stack(
        self,
        fn: Callable[[RunResidual], np.ndarray],
        filtered: bool = True,
        mask_stuck: bool = False,
    ) -> np.ndarray:
        """Columns ``fn(q)`` (shape (n,) or (n, p), unfiltered) of every run, filtered with K
        (unless ``filtered`` is False: already an acceleration-like signal), zeroed on the
        static model's stuck samples when ``mask_stuck``, stacked over the valid samples."""
        out = []
        for q in self.res:
            c = np.asarray(fn(q), dtype=float)
            c2 = c.reshape(len(q.r), -1)
            if mask_stuck:
                c2 = c2 * (~q.stuck)[:, None]
            if filtered:
                c2 = np.column_stack([q.filt(c2[:, j]) for j in range(c2.shape[1])])
            cv = np.nan_to_num(c2[q.valid])
            Q = self._start_space(q)
            out.append(cv - Q @ (Q.T @ cv) if Q is not None else cv)
        return np.concatenate(out, axis=0)

    def _start_space(self, q: RunResidual) -> np.ndarray | None:
        """Orthonormal basis (valid samples) of what the run's start state can absorb, or
        None; memoised per run."""
        key = ("start_space", id(q))
        if key not in self.cache:
            Q = None
            if q.start is not None and q.start.basis is not None:
                B = q.start.full_basis(len(q.r))[q.valid]
                B = B[:, np.linalg.norm(B, axis=0) > 0]
                if B.size:
                    U, sv, _ = np.linalg.svd(B, full_matrices=False)
                    keep = sv > 1e-9 * sv[0]
                    Q = U[:, keep] if keep.any() else None
            self.cache[key] = Q
        return self.cache[key]

    def unstack(self, vec: np.ndarray) -> list[np.ndarray]:
        """A stacked vector back to per-run arrays (NaN on invalid samples)."""
        out = []
        k = 0
        for q in self.res:
            n = int(q.valid.sum())
            a = np.full(len(q.r), np.nan)
            a[q.valid] = vec[k : k + n]
            out.append(a)
            k += n
        return out

    def all(self, name: str) -> np.ndarray:
        """A per-sample attribute of the residuals (``x``, ``v``, ...) stacked."""
        return np.concatenate([np.asarray(getattr(q, name))[q.valid] for q in self.res])

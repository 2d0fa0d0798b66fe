"""The residuals of all runs stacked over their valid samples, with held-out blocks.

Candidate regressors are built per run (unfiltered force columns), filtered with the run's
acceleration kernel K (as the residual's force side is) and stacked like the residual.
The part of a column that the run's estimated GMS start state could take up
(:mod:`feeddrive.physics.gms_start`: the start forces are re-estimated with any new model)
is projected out: a run whose elements never slip cannot tell a constant force from the
friction they hold, and must not count against (or for) a candidate because of it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..fits.compliance import fit_compliance
from ..model_file import ModelFile
from ..paper import N_ELEMENTS_MAX, N_HARMONICS
from ..physics import (
    FrictionProfile,
    GMSParameters,
    PlantParameters,
    compile,
    gms_force,
    held_current,
    load_acceleration,
    load_free_response,
    profile_basis,
    stribeck_drop,
)
from ..residual import RunResidual
from .localise import spatial_spectrum, spectral_peaks

#: Held-out blocks over all runs (contiguous pieces of each run).
DEFAULT_BLOCKS = 10
#: Fewest samples in a held-out block.
MIN_BLOCK = 100


@dataclass
class Context:
    """Stacked residual of every run (valid samples only) and the block of each sample; the
    services a candidate builder of an effect module receives
    (:class:`feeddrive.effects.candidate.CandidateContext`)."""

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

    # ----------------------------------------------------------- services to the candidates
    @property
    def n_elements_max(self) -> int:
        """Most Maxwell-slip elements of the FMU."""
        return N_ELEMENTS_MAX

    @property
    def n_harmonics(self) -> int:
        """Harmonic slots of each position map of the FMU."""
        return N_HARMONICS

    def sliding_fraction(self, q: RunResidual) -> np.ndarray:
        """Share of the friction that slides (sum of nu_i of slipping GMS elements); static
        model: 1 except on stuck samples.  Memoised per context and run."""
        key = ("sliding", id(q))
        if key not in self.cache:
            self.cache[key] = self._sliding(q)
        return self.cache[key]

    def _sliding(self, q: RunResidual) -> np.ndarray:
        if not self.plant.prerolling:
            return (~q.stuck).astype(float)
        prm = self.plant.friction
        _, Fe = gms_force(
            q.x, q.v_f, q.Ts, prm, F0=self.gms_start(q, len(prm.nu)), return_elements=True
        )
        lim = np.outer(prm.level(q.v_f, q.x), np.asarray(prm.nu))
        slipping = np.abs(Fe) >= 0.98 * lim
        return (slipping * np.asarray(prm.nu)).sum(axis=1) / max(sum(prm.nu), 1e-12)

    def sliding_level(self, q: RunResidual) -> np.ndarray:
        """The friction the profile p(x) scales along a run [N]: sgn(v) S(|v|) (the level
        without the model's own profile) times the sliding share; memoised per run."""
        key = ("sliding_level", id(q))
        if key not in self.cache:
            self.cache[key] = (
                np.sign(q.v_f) * self.plant.friction.level(q.v_f) * self.sliding_fraction(q)
            )
        return self.cache[key]

    def gms_start(self, q: RunResidual, n: int) -> np.ndarray | None:
        """The run's estimated GMS start forces (:mod:`feeddrive.physics.gms_start`) when the
        residual's model has ``n`` elements, else None (virgin)."""
        F0 = None if q.start is None else q.start.F0
        return F0 if F0 is not None and len(F0) == n else None

    def gms_force(
        self, q: RunResidual, friction: GMSParameters, F0: ArrayLike | None
    ) -> np.ndarray:
        """GMS friction along run ``q`` (:func:`feeddrive.physics.gms_force`) [N]."""
        return gms_force(q.x, q.v_f, q.Ts, friction, F0=F0)

    def stribeck_drop(self, v: ArrayLike, V_s: float, delta: float) -> np.ndarray:
        """:func:`feeddrive.physics.stribeck_drop`."""
        return stribeck_drop(v, V_s, delta)

    def profile_basis(self, x: ArrayLike, x_start: float, x_end: float, n: int) -> np.ndarray:
        """:func:`feeddrive.physics.profile_basis`."""
        return profile_basis(x, x_start, x_end, n)

    def friction_profile(
        self, x_start: float, x_end: float, c: np.ndarray | Sequence[float]
    ) -> FrictionProfile:
        """:class:`feeddrive.physics.FrictionProfile` with knot values ``c``."""
        return FrictionProfile(float(x_start), float(x_end), tuple(float(v) for v in c))

    def model_profile(self) -> FrictionProfile:
        """The model's friction profile."""
        return FrictionProfile.from_params(self.model.parameters)

    def held_current(self, i: ArrayLike) -> np.ndarray:
        """:func:`feeddrive.physics.held_current`."""
        return held_current(i)

    def load_acceleration(self, a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
        """:func:`feeddrive.physics.load_acceleration`."""
        return load_acceleration(a, Ts, f, zeta)

    def load_free_response(self, a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
        """:func:`feeddrive.physics.load_free_response`."""
        return load_free_response(a, Ts, f, zeta)

    def fit_compliance(
        self, y_runs: list[np.ndarray], stride: int, nuisance: list[np.ndarray | None]
    ) -> tuple[float, float]:
        """(f, zeta) of :func:`feeddrive.fits.compliance.fit_compliance` on the runs'
        accelerations and ``y_runs``; ValueError when no run has an acceleration."""
        fit = fit_compliance(
            [q.a for q in self.res],
            y_runs,
            [q.Ts for q in self.res],
            stride=stride,
            nuisance=nuisance,
        )
        return fit.f, fit.zeta

    def spatial_spectrum(self, weight: str | None) -> tuple[np.ndarray, np.ndarray]:
        """:func:`feeddrive.diagnose.localise.spatial_spectrum` of the residuals."""
        return spatial_spectrum(self.res, weight=weight)

    def spectral_peaks(
        self, lams: np.ndarray, amps: np.ndarray, exclude: Sequence[float], n_peaks: int
    ) -> list[tuple[float, float]]:
        """:func:`feeddrive.diagnose.localise.spectral_peaks`."""
        return spectral_peaks(lams, amps, exclude=exclude, n_peaks=n_peaks)

"""Force ripple K_f(x) and cogging F_cg(x) from constant-speed runs (Sec. 2.3, Eqs. 3-7).

Runs: constant speed +-v with constant loads P (``run.F_load`` or meta 'F_load'/'load'/'P';
absent = 0).  Each run's constant-speed segment is found from the position (acceleration and
deceleration at the ends dropped), its current is resampled onto a common 0.1 mm grid over the
stroke all runs share, and for each load the mean of the two directions is formed,
m_P(x) = (I(x, v, P) + I(x, -v, P)) / 2 = (F_cg(x) + P) / K_f(x)  (Eq. 3).

- ``kf_method='lstsq'`` (default): per grid point, least squares of m_P = alpha + beta P over
  all loads; K_f = 1/beta, F_cg = alpha/beta.  With two loads this is exactly Eq. 4 and Eq. 5.
- ``kf_method='pairs'``: Eq. 4 for every pair of loads, averaged; Eq. 5 averaged over loads.

The sampled curves are then fitted (linear least squares) by Eq. 6 (cubic + 3 harmonics of
lambda = 37.5 mm) and Eq. 7 (quadratic + 3 harmonics), optionally with extra harmonics of given
wavelengths, in SI (x in metres from the stroke origin; c_k in N/m^k or N/(A m^k)).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..data import Run
from ..paper import MAGNET_PITCH_MM, MM, N_HARMONICS
from ..physics import position_maps as maps
from ..physics import run_load_mean
from ..signals import run_label, sample_time
from ._signals import common_grid, current, lstsq_with_stderr, signal, steady_segment, to_grid

PITCH = MAGNET_PITCH_MM * MM  #: magnet pitch, the fundamental wavelength [m]
GRID_STEP = 1e-4  #: the paper's position sampling L_s = 0.1 mm [m]


@dataclass
class MapFit:
    """Linear least-squares fit of one map (Eq. 6 or Eq. 7) and its ablation."""

    name: str  #: "cogging" (F_cg) or "ripple" (K_f)
    parameters: dict[str, float]  #: <name>.c[k], <name>.lambda[j], <name>.a[j], <name>.b[j]
    stderr: dict[str, float]
    poly_order: int
    wavelengths: np.ndarray  #: lambda_j [m]
    rms_full: float  #: rms error of the full fit
    rms_periodic: float  #: rms error of a fit without the polynomial terms
    increase_percent: float  #: 100 (rms_periodic / rms_full - 1) (paper: 93.8 / 13.6)
    periodic_constant: bool  #: whether the periodic-only fit kept a constant term
    residual: np.ndarray

    def __call__(self, x: np.ndarray | float) -> np.ndarray:
        """The fitted map at x [m] (no clamping)."""
        return maps.evaluate(self.name, x, self.parameters, clamp=False)


@dataclass
class MapSamples:
    """K_f and F_cg sampled on the common grid (Eqs. 4-5) with the data behind them."""

    x: np.ndarray  #: grid [m]
    K_f: np.ndarray  #: [N/A]
    F_cg: np.ndarray  #: [N]
    loads: np.ndarray  #: distinct loads P [N]
    mean_current: np.ndarray  #: m_P(x), shape (n_loads, n_grid) [A]
    speeds: dict[str, float]  #: run label -> steady speed [m/s]
    load_source: dict[str, str]  #: run label -> where its load came from


@dataclass
class PositionMapsFit:
    """Result of :func:`identify_position_maps`."""

    samples: MapSamples
    ripple: MapFit
    cogging: MapFit
    parameters: dict[str, float] = field(default_factory=dict)
    stderr: dict[str, float] = field(default_factory=dict)


def _group_runs(
    runs: Sequence[Run],
    grid_step: float,
    method: str,
    window: int,
    rel_tol: float,
    trim: float,
    load_tol: float,
    dc_gain: float | None,
):
    segs = []
    for k, run in enumerate(runs):
        label = f"[{k}] {run_label(run)}"
        Ts = sample_time(run.time, label=label)
        x, i = signal(run, "x"), current(run, dc_gain)
        seg, v = steady_segment(x, Ts, window=window, rel_tol=rel_tol, label=label)
        xs, is_ = x[seg], i[seg]
        keep = (xs >= xs.min() + trim) & (xs <= xs.max() - trim)
        P, src = run_load_mean(run)
        segs.append((label, xs[keep], is_[keep], v, P, src))
    # distinct loads (within load_tol)
    loads: list[float] = []
    for s in segs:
        if not any(abs(s[4] - P) <= load_tol for P in loads):
            loads.append(s[4])
    loads.sort()
    grid = common_grid([(s[1].min(), s[1].max()) for s in segs], grid_step)
    cur: dict[tuple[int, float], list[tuple[str, np.ndarray, float]]] = {}
    for label, xs, is_, v, P, _ in segs:
        li = int(np.argmin([abs(P - q) for q in loads]))
        resampled = to_grid(xs, is_, grid, method, grid_step)
        cur.setdefault((li, np.sign(v)), []).append((label, resampled, v))
    mean = np.zeros((len(loads), len(grid)))
    for li, P in enumerate(loads):
        fw, bw = cur.get((li, 1.0)), cur.get((li, -1.0))
        if not fw or not bw:
            raise ValueError(
                f"position maps: load P = {P:g} N needs runs in both directions "
                f"(have {'+v' if fw else ''}{' -v' if bw else ''})"
            )
        vf = np.mean([abs(r[2]) for r in fw])
        vb = np.mean([abs(r[2]) for r in bw])
        if abs(vf - vb) > 0.1 * max(vf, vb):
            raise ValueError(
                f"position maps: load P = {P:g} N: speeds +{vf:g} and -{vb:g} m/s "
                "differ by more than 10 % (Eq. 3 needs equal |v|)"
            )
        mean[li] = 0.5 * (np.mean([r[1] for r in fw], axis=0) + np.mean([r[1] for r in bw], axis=0))
    return grid, np.array(loads), mean, {s[0]: s[3] for s in segs}, {s[0]: s[5] for s in segs}


def map_samples(
    runs: Sequence[Run],
    grid_step: float = GRID_STEP,
    kf_method: str = "lstsq",
    resample: str = "interp",
    window: int = 201,
    rel_tol: float = 0.25,
    trim: float = 0.5e-3,
    load_tol: float = 0.5,
    dc_gain: float | None = None,
) -> MapSamples:
    """K_f(x) and F_cg(x) on the common grid from constant-speed runs (Eqs. 4 and 5).

    Parameters
    ----------
    runs : constant-speed runs, +-v for each of at least two distinct loads.
    grid_step : grid spacing [m] (0.1 mm); grid points are integer multiples of it.
    kf_method : 'lstsq' or 'pairs' (see module docstring).
    resample : 'interp' (paper: linear interpolation) or 'bin' (mean per grid cell).
    window, rel_tol : constant-speed detection (see ``identify._signals.steady_segment``).
    trim : extra length dropped at both ends of each constant-speed segment [m].
    load_tol : loads closer than this [N] are the same load.
    dc_gain : for runs without a current column, i = dc_gain * u (the recording format).
    """
    grid, loads, mean, speeds, src = _group_runs(
        runs, grid_step, resample, window, rel_tol, trim, load_tol, dc_gain
    )
    if len(loads) < 2:
        raise ValueError(f"position maps: need at least two distinct loads, got {loads.tolist()}")
    if kf_method == "lstsq":
        A = np.column_stack((np.ones_like(loads), loads))
        coef, *_ = np.linalg.lstsq(A, mean, rcond=None)  # (2, n_grid)
        K_f = 1.0 / coef[1]
        F_cg = coef[0] * K_f
    elif kf_method == "pairs":
        kfs = [
            (loads[p] - loads[q]) / (mean[p] - mean[q])  # Eq. 4
            for p in range(len(loads))
            for q in range(p + 1, len(loads))
        ]
        K_f = np.mean(kfs, axis=0)
        F_cg = np.mean([K_f * mean[p] - loads[p] for p in range(len(loads))], axis=0)  # Eq. 5
    else:
        raise ValueError(f"position maps: kf_method must be 'lstsq' or 'pairs', got {kf_method!r}")
    return MapSamples(
        x=grid, K_f=K_f, F_cg=F_cg, loads=loads, mean_current=mean, speeds=speeds, load_source=src
    )


def _design(
    x: np.ndarray,
    poly_order: int,
    wavelengths: np.ndarray,
    scale: float,
    periodic_only: bool = False,
    constant: bool = True,
) -> np.ndarray:
    cols = []
    if not periodic_only:
        cols += [(x / scale) ** k for k in range(poly_order + 1)]
    elif constant:
        cols.append(np.ones_like(x))
    for lam in wavelengths:
        th = 2 * np.pi * x / lam
        cols += [np.cos(th), np.sin(th)]
    return np.column_stack(cols)


def fit_map(
    x: np.ndarray,
    y: np.ndarray,
    name: str,
    poly_order: int | None = None,
    n_harmonics: int = 3,
    pitch: float = PITCH,
    extra_wavelengths: Sequence[float] = (),
    periodic_constant: bool | None = None,
) -> MapFit:
    """Fit Eq. 6 ('cogging') or Eq. 7 ('ripple') to samples y(x), x in metres.

    Parameters
    ----------
    poly_order : polynomial degree (default: 3 for cogging, 2 for ripple).
    n_harmonics : harmonics of ``pitch`` (wavelengths pitch/j, j = 1..n_harmonics).
    extra_wavelengths : further Fourier terms [m] (e.g. 0.025 for the 25 mm ripple term),
        stored in the following slots.
    periodic_constant : whether the periodic-only (ablation) fit keeps a constant; default as
        the FMU's switches: kept for 'ripple' (K_f = c0 + Fourier), not for 'cogging'.
    """
    if name not in maps.POLY_ORDER:
        raise ValueError(f"fit_map: name must be 'cogging' or 'ripple', got {name!r}")
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    po = maps.POLY_ORDER[name] if poly_order is None else int(poly_order)
    lams = np.array([pitch / j for j in range(1, n_harmonics + 1)] + list(extra_wavelengths), float)
    if len(lams) > N_HARMONICS:
        raise ValueError(f"fit_map: {len(lams)} harmonics exceed the FMU's {N_HARMONICS} slots")
    if po > maps.POLY_ORDER[name]:
        raise ValueError(
            f"fit_map: the FMU holds {name}.c[0..{maps.POLY_ORDER[name]}], "
            f"poly_order {po} is too high"
        )
    scale = float(np.max(np.abs(x))) or 1.0
    theta, se, r = lstsq_with_stderr(_design(x, po, lams, scale), y)
    params: dict[str, float] = {}
    stderr: dict[str, float] = {}
    for k in range(maps.POLY_ORDER[name] + 1):
        params[f"{name}.c[{k}]"] = float(theta[k] / scale**k) if k <= po else 0.0
        if k <= po:
            stderr[f"{name}.c[{k}]"] = float(se[k] / scale**k)
    for j in range(1, N_HARMONICS + 1):
        if j <= len(lams):
            ia, ib = po + 1 + 2 * (j - 1), po + 2 + 2 * (j - 1)
            params[f"{name}.lambda[{j}]"] = float(lams[j - 1])
            params[f"{name}.a[{j}]"], params[f"{name}.b[{j}]"] = float(theta[ia]), float(theta[ib])
            stderr[f"{name}.a[{j}]"], stderr[f"{name}.b[{j}]"] = float(se[ia]), float(se[ib])
        else:
            params[f"{name}.lambda[{j}]"] = pitch / j
            params[f"{name}.a[{j}]"] = params[f"{name}.b[{j}]"] = 0.0
    keep_c = (name == "ripple") if periodic_constant is None else bool(periodic_constant)
    Ap = _design(x, po, lams, scale, periodic_only=True, constant=keep_c)
    tp, *_ = np.linalg.lstsq(Ap, y, rcond=None)
    rms_f = float(np.sqrt(np.mean(r**2)))
    rms_p = float(np.sqrt(np.mean((y - Ap @ tp) ** 2)))
    return MapFit(
        name=name,
        parameters=params,
        stderr=stderr,
        poly_order=po,
        wavelengths=lams,
        rms_full=rms_f,
        rms_periodic=rms_p,
        increase_percent=100.0 * (rms_p / rms_f - 1.0) if rms_f > 0 else float("inf"),
        periodic_constant=keep_c,
        residual=r,
    )


def identify_position_maps(
    runs: Sequence[Run],
    n_harmonics: int = 3,
    extra_wavelengths: dict[str, Sequence[float]] | None = None,
    **sample_kw,
) -> PositionMapsFit:
    """Eqs. 4-5 on the runs, then the fits of Eq. 6 (cogging) and Eq. 7 (ripple).

    ``extra_wavelengths`` maps 'cogging'/'ripple' to extra Fourier wavelengths [m];
    ``sample_kw`` goes to :func:`map_samples`.
    """
    extra = extra_wavelengths or {}
    s = map_samples(runs, **sample_kw)
    rip = fit_map(
        s.x, s.K_f, "ripple", n_harmonics=n_harmonics, extra_wavelengths=extra.get("ripple", ())
    )
    cog = fit_map(
        s.x, s.F_cg, "cogging", n_harmonics=n_harmonics, extra_wavelengths=extra.get("cogging", ())
    )
    return PositionMapsFit(
        samples=s,
        ripple=rip,
        cogging=cog,
        parameters={**rip.parameters, **cog.parameters},
        stderr={**rip.stderr, **cog.stderr},
    )

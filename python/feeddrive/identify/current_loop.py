"""Current-loop identification (Sec. 2.2, Eq. 2): PRBS input, ARX + output-error fits.

Model structure for order n and delay d (FMU naming, ``current.a[1..5]``, ``current.b[0..5]``)::

    i[k] = sum_{j=1..n} a_j i[k-j] + sum_{j=d..d+nb-1} b_j u[k-j],   nb = min(n, 6 - d)

i.e. G(z) = z^-d (b_d + b_{d+1} z^-1 + ...) / (1 - a_1 z^-1 - ... - a_n z^-n); the paper's
Eq. 2 is n = 2, d = 2 (one pure delay plus the zero-order-hold sample).  nb is capped so
that every lag fits the FMU's b[0..5] slots.

Procedure: for each order the delay is chosen by the smallest ARX residual (linear least
squares); the ARX estimate starts an output-error refinement (scipy least_squares on the
simulated output, which is unbiased for white measurement noise on i, unlike ARX).  The
order is chosen on a held-out final part of the record (``criterion='validation'``,
default): the smallest order whose simulated-output rms error on the validation part is
within ``tolerance`` (relative) of the best order's.  AIC and FPE of every candidate are
reported as well and may be used instead.  The chosen structure is refitted on the whole
record.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from ..data import Run
from ..physics import simulate_current
from ..signals import run_label, sample_time
from ._signals import jacobian_stderr, signal

MAX_LAG = 5  #: highest u lag the FMU holds (current.b[0..5])
MAX_ORDER = 5  #: highest i lag the FMU holds (current.a[1..5])


@dataclass
class OrderCandidate:
    """One fitted structure: order n, delay d, its coefficients and criteria."""

    order: int
    delay: int
    a: np.ndarray  #: a_1..a_n
    b: np.ndarray  #: b_0..b_{d+nb-1} (zeros below the delay)
    arx_rms: float  #: one-step-ahead ARX residual rms on the estimation part [A]
    rms_estimation: float  #: output-error (simulation) rms on the estimation part [A]
    rms_validation: float  #: simulation rms on the held-out part [A]
    aic: float
    fpe: float


@dataclass
class CurrentLoopFit:
    """Identified current loop G(z) = i/u and its diagnostics."""

    order: int
    delay: int
    Ts: float
    a: np.ndarray
    b: np.ndarray
    parameters: dict[str, float]  #: current.a[1..5], current.b[0..5]
    stderr: dict[str, float]  #: standard errors of the estimated coefficients
    num: np.ndarray  #: numerator of G(z), descending powers of z
    den: np.ndarray  #: denominator of G(z), descending powers of z
    poles: np.ndarray  #: poles of G(z) other than the delay poles at z = 0
    zeros: np.ndarray  #: finite zeros other than z = 0
    poles_s: np.ndarray  #: continuous equivalents ln(z)/Ts [rad/s]
    pole_hz: np.ndarray  #: |s|/(2 pi)
    pole_zeta: np.ndarray  #: -Re(s)/|s|
    dc_gain: float  #: G(1) [A/V]
    rms_residual: float  #: simulated-output rms error on the whole record [A]
    fit_percent: float  #: 100 (1 - |i - i_sim| / |i - mean(i)|)
    criterion: str
    candidates: list[OrderCandidate] = field(default_factory=list)


def _nb(order: int, delay: int) -> int:
    return min(order, MAX_LAG + 1 - delay)


def _regression(u: np.ndarray, i: np.ndarray, n: int, d: int) -> tuple[np.ndarray, np.ndarray, int]:
    nb = _nb(n, d)
    k0 = max(n, d + nb - 1)
    N = len(i)
    cols = [i[k0 - j : N - j] for j in range(1, n + 1)]
    cols += [u[k0 - j : N - j] for j in range(d, d + nb)]
    return np.column_stack(cols), i[k0:], k0


def _theta_to_ab(theta: np.ndarray, n: int, d: int) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(theta[:n], dtype=float)
    b = np.zeros(d + _nb(n, d))
    b[d:] = theta[n:]
    return a, b


def _sim_segment(a, b, u, i, k0: int, k1: int) -> np.ndarray:
    """Simulated output on samples k0..k1-1, started from the measured history."""
    h = max(len(a), len(b) - 1)
    lo = max(k0 - h, 0)
    return simulate_current(a, b, u[k0:k1], i_init=i[lo:k0], u_init=u[lo:k0])


def _output_error(u, i, n, d, theta0, k0, k1):
    h = max(n, d + _nb(n, d) - 1)
    k0 = max(k0, h)

    def resid(theta):
        a, b = _theta_to_ab(theta, n, d)
        r = i[k0:k1] - _sim_segment(a, b, u, i, k0, k1)
        if not np.all(np.isfinite(r)) or np.max(np.abs(r)) > 1e6 * (np.std(i) + 1e-12):
            return np.full(k1 - k0, 1e6 * (np.std(i) + 1.0))
        return r

    sol = least_squares(resid, theta0, method="lm", x_scale="jac")
    return sol.x, sol.fun, sol.jac


def _arx(u, i, n, d):
    A, y, _ = _regression(u, i, n, d)
    theta, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ theta
    return theta, float(np.sqrt(np.mean(r**2)))


def _candidate(u, i, n, delays, n_est) -> OrderCandidate:
    best = None
    for d in delays:
        if _nb(n, d) < 1:
            continue
        theta, rms = _arx(u[:n_est], i[:n_est], n, d)
        if best is None or rms < best[2]:
            best = (d, theta, rms)
    if best is None:
        raise ValueError(f"current loop: no admissible delay for order {n} in {list(delays)}")
    d, theta0, arx_rms = best
    theta, r, _ = _output_error(u, i, n, d, theta0, 0, n_est)
    a, b = _theta_to_ab(theta, n, d)
    N_e, p = len(r), len(theta)
    V = float(r @ r) / N_e
    val = i[n_est:] - _sim_segment(a, b, u, i, n_est, len(i))
    return OrderCandidate(
        order=n,
        delay=d,
        a=a,
        b=b,
        arx_rms=arx_rms,
        rms_estimation=float(np.sqrt(V)),
        rms_validation=float(np.sqrt(np.mean(val**2))),
        aic=float(N_e * np.log(V) + 2 * p),
        fpe=float(V * (1 + p / N_e) / (1 - p / N_e)),
    )


def _select(cands: list[OrderCandidate], criterion: str, tolerance: float) -> OrderCandidate:
    if criterion == "validation":
        best = min(c.rms_validation for c in cands)
        return min(
            (c for c in cands if c.rms_validation <= best * (1 + tolerance)), key=lambda c: c.order
        )
    if criterion in ("aic", "fpe"):
        return min(cands, key=lambda c: getattr(c, criterion))
    raise ValueError(
        f"current loop: criterion must be 'validation', 'aic' or 'fpe', got {criterion!r}"
    )


def fit_current_loop(
    u: np.ndarray,
    i: np.ndarray,
    Ts: float,
    orders: tuple[int, ...] = (1, 2, 3, 4, 5),
    delays: tuple[int, ...] = (0, 1, 2, 3),
    criterion: str = "validation",
    validation_fraction: float = 1 / 3,
    tolerance: float = 0.02,
) -> CurrentLoopFit:
    """Fit G(z) from u [V] and i [A] sampled at Ts [s]; see the module docstring.

    Parameters
    ----------
    u, i : input and measured output, same length.
    orders : candidate denominator orders (1..5).
    delays : candidate input delays d (samples).
    criterion : 'validation' (default), 'aic' or 'fpe' (both on the estimation part).
    validation_fraction : final fraction of the record held out for validation.
    tolerance : relative rms slack of the 'validation' rule.
    """
    u = np.asarray(u, dtype=float)
    i = np.asarray(i, dtype=float)
    if u.shape != i.shape or u.ndim != 1:
        raise ValueError(
            f"current loop: u and i must be 1-D of equal length ({u.shape}, {i.shape})"
        )
    if any(not 1 <= n <= MAX_ORDER for n in orders):
        raise ValueError(f"current loop: orders must lie in 1..{MAX_ORDER}, got {orders}")
    if not 0.05 <= validation_fraction <= 0.7:
        raise ValueError(
            f"current loop: validation_fraction {validation_fraction} outside 0.05..0.7"
        )
    n_est = int(round(len(u) * (1 - validation_fraction)))
    if n_est < 50 or len(u) - n_est < 50:
        raise ValueError(f"current loop: record of {len(u)} samples too short")
    cands = [_candidate(u, i, n, delays, n_est) for n in orders]
    chosen = _select(cands, criterion, tolerance)
    n, d = chosen.order, chosen.delay
    theta0 = np.concatenate((chosen.a, chosen.b[d:]))
    theta, r, jac = _output_error(u, i, n, d, theta0, 0, len(i))
    se = jacobian_stderr(jac, r)
    a, b = _theta_to_ab(theta, n, d)
    return _assemble(a, b, se, n, d, Ts, u, i, criterion, cands)


def _assemble(a, b, se, n, d, Ts, u, i, criterion, cands) -> CurrentLoopFit:
    params: dict[str, float] = {}
    stderr: dict[str, float] = {}
    for j in range(1, MAX_ORDER + 1):
        params[f"current.a[{j}]"] = float(a[j - 1]) if j <= n else 0.0
    for j in range(MAX_LAG + 1):
        params[f"current.b[{j}]"] = float(b[j]) if j < len(b) else 0.0
    for j in range(n):
        stderr[f"current.a[{j + 1}]"] = float(se[j])
    for m, j in enumerate(range(d, len(b))):
        stderr[f"current.b[{j}]"] = float(se[n + m])
    # G(z) = sum b_j z^-j / (1 - sum a_j z^-j); multiply by z^L, L = max(n, len(b)-1)
    L = max(n, len(b) - 1)
    num = np.zeros(L + 1)
    num[: len(b)] = b
    den = np.zeros(L + 1)
    den[0] = 1.0
    den[1 : n + 1] = -a
    num_t, den_t = np.trim_zeros(num, "b"), np.trim_zeros(den, "b")
    poles = np.roots(den_t) if len(den_t) > 1 else np.zeros(0)
    num_l = np.trim_zeros(num_t, "f")
    zeros = np.roots(num_l) if len(num_l) > 1 else np.zeros(0)
    nz = poles[np.abs(poles) > 1e-12]
    s = np.log(nz.astype(complex)) / Ts
    hz = np.abs(s) / (2 * np.pi)
    zeta = -s.real / np.abs(s)
    dc = float(np.sum(b) / (1 - np.sum(a)))
    k0 = max(n, len(b) - 1)
    i_sim = np.concatenate((i[:k0], _sim_segment(a, b, u, i, k0, len(i))))
    err = i - i_sim
    fit = 100 * (1 - np.linalg.norm(err) / np.linalg.norm(i - i.mean()))
    return CurrentLoopFit(
        order=n,
        delay=d,
        Ts=Ts,
        a=a,
        b=b,
        parameters=params,
        stderr=stderr,
        num=num,
        den=den,
        poles=poles,
        zeros=zeros,
        poles_s=s,
        pole_hz=hz,
        pole_zeta=zeta,
        dc_gain=dc,
        rms_residual=float(np.sqrt(np.mean(err**2))),
        fit_percent=float(fit),
        criterion=criterion,
        candidates=cands,
    )


def identify_current_loop(run: Run, **kw) -> CurrentLoopFit:
    """:func:`fit_current_loop` on a PRBS run (columns ``u``, ``i``; Ts from ``time``)."""
    label = run_label(run)
    Ts = sample_time(run.time, label=label)
    return fit_current_loop(signal(run, "u"), signal(run, "i"), Ts, **kw)

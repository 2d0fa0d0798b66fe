"""Hints for a residual no catalogue effect explains: signatures of problems that are not
model effects, each fitted to the final residual and sized by the force it would explain.

A hint is never a model change: it says where to look (the sensor timing, the amplifier,
the mechanics between stage and scale).  Each signature is fitted to the final residual
``r`` of every run and sized like a candidate, by the force it removes,
``F_expl = sqrt((sum r^2 - sum (r - fit)^2) / n)`` [N rms] over all valid samples:

- **drift over run time**: the motor-force gain changing linearly with the time since
  each run's middle, ``r = -g K*F_motor - kappa K*((t - t_mid) F_motor)`` (a force constant
  that drifts as the motor warms, an amplifier gain that drifts); or the residual itself
  trending, ``r = c0 + c K*(t - t_mid)``.  The constant parts (a gain or offset error, which
  the catalogue holds) are fitted with it and not counted: the size is the force the time
  dependence adds.  Size: ``kappa`` [1/s] (as % per minute) or ``c`` [N/s].
- **timing offset** between position and force: a position recorded ``tau`` late sees the
  motion of ``t - tau`` against the force of ``t``, ``r = tau d/dt (K*F_app)`` to first order
  (``F_app`` the applied force, which the model's force balances); fitted from a fraction of
  a sample to a few samples.  Size: ``tau`` [s] (> 0: the position lags the force).
- **play** (a dead zone after reversals between the stage and its scale): the scale stands
  still after each reversal while the stage crosses the play ``b``; the residual is
  re-computed with the position the stage would have had (the reading plus ``b/2`` in the
  direction of motion, crossing over each dwell at the reversals as a constant
  deceleration would) for ``b`` on a grid and refined; ``F_expl`` from the re-computed gap.
  Size: ``b`` [m].
- **resonance band**: the strongest narrow peak of the residual's spectrum above
  ``RESONANCE_F_MIN`` (Welch periodogram, 2 s segments, against its running median over
  ``RESONANCE_MEDIAN_HZ``); the band of half an octave around it, less what the
  background puts there.  Size: the
  peak frequency [Hz] and the band's rms [N].

The best hint is the one explaining the most force; the verdict reports it with its size
and the share of the residual's excess it accounts for (:func:`add_hint`) when it explains
at least the threshold a named effect must explain.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np
from scipy.ndimage import median_filter
from scipy.optimize import minimize_scalar
from scipy.signal import welch

from ..data import Run
from ..model_file import ModelFile
from ..residual import RunResidual, residuals
from .significance import Gate

#: Play grid [m] (the best point is refined on log b).
PLAY_GRID = tuple(np.geomspace(1e-6, 300e-6, 12).tolist())
#: Lowest frequency of a resonance band [Hz] (below: the motion's own frequencies).
RESONANCE_F_MIN = 5.0
#: Width of the running median the spectrum's background is taken as [Hz].
RESONANCE_MEDIAN_HZ = 10.0
#: A spectral peak counts when it stands this many times above its running median.
RESONANCE_PEAK = 5.0
#: Span over which the reading's speed after a dwell is taken [s].
PLAY_SPEED_S = 5e-3
#: Direction changes of the scale are recognised once it moved back by this much [m].
PLAY_HYSTERESIS = 0.5e-6


def _explained(r: np.ndarray, fit: np.ndarray) -> float:
    d = float(r @ r - (r - fit) @ (r - fit))
    return float(np.sqrt(max(d, 0.0) / r.size)) if r.size else 0.0


def _stack(res: Sequence[RunResidual], fn) -> np.ndarray:
    return np.concatenate([np.nan_to_num(np.asarray(fn(q), dtype=float))[q.valid] for q in res])


def _added_regressor(r: np.ndarray, base: np.ndarray, g: np.ndarray) -> tuple[float, float, float]:
    """Least-squares coefficient of ``g`` fitted with ``base``, the force ``g`` adds to what
    ``base`` alone explains and the force both explain [N rms]."""
    if not r.size:
        return 0.0, 0.0, 0.0
    A0 = base[:, None]
    A1 = np.column_stack([base, g])
    th0 = np.linalg.lstsq(A0, r, rcond=None)[0]
    th1 = np.linalg.lstsq(A1, r, rcond=None)[0]
    e0, e1 = r - A0 @ th0, r - A1 @ th1
    d = float(e0 @ e0 - e1 @ e1)
    return float(th1[1]), float(np.sqrt(max(d, 0.0) / r.size)), _explained(r, A1 @ th1)


def _one_regressor(r: np.ndarray, g: np.ndarray) -> tuple[float, float]:
    """Least-squares coefficient of r on g and the force it explains."""
    gg = float(g @ g)
    if gg <= 0:
        return 0.0, 0.0
    c = float(g @ r) / gg
    return c, _explained(r, c * g)


def _centred_time(q: RunResidual) -> np.ndarray:
    t = np.asarray(q.time, dtype=float)
    return t - float(np.mean(t[q.valid]))


def drift_hint(res: Sequence[RunResidual]) -> dict:
    """The better of a motor-force gain drift and a residual trend over run time."""
    r = _stack(res, lambda q: q.r)
    g_gain = _stack(res, lambda q: -q.filt(_centred_time(q) * q.F_motor))
    g_trend = _stack(res, lambda q: q.filt(_centred_time(q)))
    kappa, f_gain, f_gain_all = _added_regressor(
        r, _stack(res, lambda q: -q.filt(q.F_motor)), g_gain
    )
    c, f_trend, f_trend_all = _added_regressor(
        r, _stack(res, lambda q: q.filt(np.ones(len(q.r)))), g_trend
    )
    span = max(float(np.ptp(q.time[q.valid])) for q in res)
    if f_gain >= f_trend:
        return {
            "signature": "drift",
            "form": "motor-force gain",
            "explained_force_N": f_gain,
            "gain_rate_per_s": kappa,
            "gain_percent_per_min": 6000.0 * kappa,
            "gain_change_over_longest_run_percent": 100.0 * kappa * span,
            "explained_with_level_N": f_gain_all,
            "text": (
                f"a drift of the motor-force gain over run time: force per measured "
                f"current (or reference) changing by {6000.0 * kappa:+.3g} %/min "
                f"({100.0 * kappa * span:+.3g} % over {span:.3g} s; with the gain "
                f"error at mid-run it explains {f_gain_all:.3g} N)"
            ),
        }
    return {
        "signature": "drift",
        "form": "residual trend",
        "explained_force_N": f_trend,
        "trend_N_per_s": c,
        "explained_with_level_N": f_trend_all,
        "text": (
            f"a residual trending over run time by {c:+.3g} N/s (with the offset at "
            f"mid-run it explains {f_trend_all:.3g} N)"
        ),
    }


def latency_hint(res: Sequence[RunResidual]) -> dict:
    """The timing offset between position and force (first order in ``tau``)."""
    r = _stack(res, lambda q: q.r)
    g = _stack(res, lambda q: np.gradient(q.filt(q.F_app), q.Ts))
    tau, f = _one_regressor(r, g)
    Ts = float(np.median([q.Ts for q in res]))
    who = "the position lags the force" if tau > 0 else "the force lags the position"
    return {
        "signature": "timing_offset",
        "explained_force_N": f,
        "tau_s": tau,
        "tau_samples": tau / Ts,
        "text": (
            f"a timing offset between position and force: {who} by "
            f"{abs(tau) * 1e3:.3g} ms ({abs(tau) / Ts:.2g} samples)"
        ),
    }


def play_position(
    x: np.ndarray, time: np.ndarray, b: float, hysteresis: float = PLAY_HYSTERESIS
) -> np.ndarray:
    """The position of a stage whose scale reads ``x`` through a play ``b`` [m].

    Moving up the scale trails the stage by b/2 (and moving down, leads it); at each
    reversal the scale stands still (from the sample the reading reached its extreme to the
    last one it held it) while the stage crosses the play: from rest, at constant
    acceleration, to the speed the reading takes up after the dwell (the slope at the
    dwell's end of a parabola fitted over the next ``PLAY_SPEED_S``),
    which takes ``2 b / v`` before the dwell's end (the whole dwell at most): a parabola in
    time from +b/2 to -b/2.  The start of the run counts as a reversal from the middle of
    the play.
    """
    x = np.asarray(x, dtype=float)
    t = np.asarray(time, dtype=float)
    n = x.size
    side = np.zeros(n)  # the direction of motion: -1, 0 (not moved yet), +1
    turns: list[tuple[int, int, float, float]] = []  # (dwell start, dwell end, d_old, d_new)
    d, ext, k_ext = 0, x[0], 0
    for k in range(n):
        xk = x[k]
        if d == 0:
            if abs(xk - x[0]) > hysteresis:
                d = 1 if xk > x[0] else -1
                last = int(np.flatnonzero(np.abs(x[:k] - x[0]) <= 0.5 * hysteresis)[-1])
                turns.append((0, last, 0.0, float(d)))
                ext, k_ext = xk, k
        elif d * (xk - ext) > 0:
            ext, k_ext = xk, k
        elif d * (ext - xk) > hysteresis:
            held = np.flatnonzero(np.abs(x[k_ext:k] - ext) <= 0.5 * hysteresis)
            k_end = k_ext + int(held[-1]) if held.size else k_ext
            turns.append((k_ext, k_end, float(d), float(-d)))
            d, ext, k_ext = -d, xk, k
        side[k] = d
    c = 0.5 * b * side
    m = max(2, int(round(PLAY_SPEED_S / max(float(np.median(np.diff(t))), 1e-300))))
    for ks, ke, d_old, d_new in turns:
        c[ks : ke + 1] = 0.5 * b * d_old
        # crossing from rest to the speed the reading takes up after the dwell: b = v T / 2
        seg = slice(ke, min(ke + m, n - 1) + 1)
        v = abs(float(np.polyfit(t[seg] - t[ke], x[seg], 2)[1])) if t[seg].size >= 3 else 0.0
        t_c = max(t[ke] - 2.0 * b / v, t[ks]) if v > 0 else t[ks]
        cross = (t >= t_c) & (np.arange(n) >= ks) & (np.arange(n) <= ke)
        if t[ke] > t_c:
            sc = (t[cross] - t_c) / (t[ke] - t_c)
            c[cross] = 0.5 * b * (d_old + (d_new - d_old) * sc**2)
        else:
            c[ke] = 0.5 * b * d_new
        # from the dwell's end to the sample the turn is recognised, the side is the new one
        nxt = np.flatnonzero(side[ke + 1 :] == d_new)
        stop = ke + 1 + int(nxt[0]) if nxt.size else n
        c[ke + 1 : stop] = 0.5 * b * d_new
    return x + c


def play_hint(runs: Sequence[Run], model: ModelFile, res: Sequence[RunResidual], kw: dict) -> dict:
    """The play whose re-computed residual is smallest (see the module docstring)."""
    n = sum(int(q.valid.sum()) for q in res)
    sse0 = sum(float(q.r[q.valid] @ q.r[q.valid]) for q in res)

    def sse(log_b: float) -> float:
        b = float(np.exp(log_b))
        moved = [dataclasses.replace(run, x=play_position(run.x, run.time, b)) for run in runs]
        rr = residuals(list(moved), model, **kw)
        return sum(
            float(np.sum(q.r[q.valid & q0.valid] ** 2)) for q, q0 in zip(rr, res, strict=True)
        )

    grid = [(sse(np.log(b)), b) for b in PLAY_GRID]
    k = int(np.argmin([g for g, _ in grid]))
    lo = np.log(PLAY_GRID[max(k - 1, 0)])
    hi = np.log(PLAY_GRID[min(k + 1, len(PLAY_GRID) - 1)])
    best_sse, best_b = grid[k]
    if hi > lo:
        opt = minimize_scalar(
            sse, bounds=(lo, hi), method="bounded", options={"xatol": 0.02, "maxiter": 12}
        )
        if opt.fun < best_sse:
            best_sse, best_b = float(opt.fun), float(np.exp(opt.x))
    f = float(np.sqrt(max(sse0 - best_sse, 0.0) / n)) if n else 0.0
    return {
        "signature": "play",
        "explained_force_N": f,
        "play_m": best_b,
        "text": (
            f"play (a dead zone after reversals) of {best_b * 1e6:.3g} um between the "
            "stage and its scale"
        ),
    }


def resonance_hint(res: Sequence[RunResidual]) -> dict:
    """The strongest narrow peak of the residual's spectrum (see the module docstring)."""
    n_all = sum(int(q.valid.sum()) for q in res)
    best = None
    for q in res:
        r = q.r[q.valid]
        if r.size < 64:
            continue
        f, p = welch(r, fs=1.0 / q.Ts, nperseg=min(r.size, int(round(2.0 / q.Ts))))
        df = float(f[1] - f[0])
        width = max(3, int(round(RESONANCE_MEDIAN_HZ / df)) | 1)
        bg = median_filter(p, size=width, mode="nearest")
        ok = f >= RESONANCE_F_MIN
        if not ok.any():
            continue
        ratio = np.where(ok, p / np.maximum(bg, 1e-300), 0.0)
        k = int(np.argmax(ratio))
        if ratio[k] < RESONANCE_PEAK:
            continue
        f0 = float(f[k])
        band = (f >= f0 * 2**-0.25) & (f <= f0 * 2**0.25)
        var = float(np.sum(np.maximum(p[band] - bg[band], 0.0)) * df)
        e = var * r.size / n_all
        if best is None or e > best[0]:
            best = (e, f0, float(ratio[k]), q.name)
    if best is None:
        return {
            "signature": "resonance",
            "explained_force_N": 0.0,
            "f_Hz": None,
            "text": "no narrow peak in the residual's spectrum",
        }
    e, f0, peak, name = best
    return {
        "signature": "resonance",
        "explained_force_N": float(np.sqrt(e)),
        "f_Hz": f0,
        "peak_ratio": peak,
        "run": name,
        "text": f"a resonance band around {f0:.3g} Hz ({name}: {peak:.3g} x the spectrum "
        "around it)",
    }


def hints(
    runs: Sequence[Run], model: ModelFile, res: Sequence[RunResidual], kw: dict
) -> list[dict]:
    """Every signature fitted to ``res`` (the residual of ``model`` along ``runs``; ``kw``
    the residual's keywords), the one explaining the most force first."""
    out = [drift_hint(res), latency_hint(res), play_hint(runs, model, res, kw), resonance_hint(res)]
    out.sort(key=lambda h: -h["explained_force_N"])
    return out


def add_hint(v: dict, found: list[dict], gate: Gate) -> dict:
    """The verdict ``v`` with the signatures of :func:`hints` (``found``, best first): all of
    them, and the best one as the hint when it explains at least the gate's threshold."""
    v["hints"] = found
    best = found[0] if found else None
    if best is None or best["explained_force_N"] < gate.threshold_N:
        v["hint"] = None
        v["sentence"] += (
            " No signature outside the catalogue (drift, timing offset, play, "
            f"resonance) explains {gate.threshold_N:.3g} N of it."
        )
        return v
    share = best["explained_force_N"] ** 2 / max(v["excess_N"] ** 2, 1e-300)
    v["hint"] = {**best, "share_of_excess": share}
    v["sentence"] += (
        f" Hint (not a model change): {best['text']} would explain "
        f"{best['explained_force_N']:.3g} N rms ({min(share, 1.0):.0%} of the "
        "excess energy)."
    )
    return v

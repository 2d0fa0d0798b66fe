"""Where a force residual lives: regimes, position along the stroke and its spatial spectrum.

Regimes (boolean masks over the valid samples of a run): displacement since the last
reversal of motion (pre-rolling lives within ~0.2 mm), speed (low / middle / high),
acceleration phases, direction, current level, load, position bins along the stroke.  For
each, :func:`localise` reports the rms and mean residual, the share of the residual's energy
and the *concentration* (energy share / sample share; > 1 means the gap lives there).
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np

from ..residual import RunResidual

#: Bins of displacement since reversal [m].
REVERSAL_BINS = (0.0, 20e-6, 100e-6, 500e-6, 5e-3, np.inf)
#: Low speed limit [m/s] (about the Stribeck velocity times a few).
LOW_SPEED = 5e-3
#: Direction changes are recognised once the position moved back by this much [m].
REVERSAL_HYSTERESIS = 0.5e-6


def displacement_since_reversal(
    x: np.ndarray, hysteresis: float = REVERSAL_HYSTERESIS
) -> np.ndarray:
    """|x - x_turn| where x_turn is the last turning point of x [m].

    A turning point is recognised once x has moved back from its running extreme by more
    than ``hysteresis`` (quantisation and noise do not count as reversals); the start of the
    run counts as one.
    """
    xs = np.asarray(x, dtype=float).tolist()
    out = np.empty(len(xs))
    h = hysteresis
    turn = peak = xs[0]
    d = 0
    for k, xk in enumerate(xs):
        if d == 0:
            if xk - turn > h:
                d, peak = 1, xk
            elif turn - xk > h:
                d, peak = -1, xk
        elif d == 1:
            if xk > peak:
                peak = xk
            elif peak - xk > h:
                turn, peak, d = peak, xk, -1
        else:
            if xk < peak:
                peak = xk
            elif xk - peak > h:
                turn, peak, d = peak, xk, 1
        out[k] = abs(xk - turn)
    return out


def regime_masks(q: RunResidual) -> dict[str, np.ndarray]:
    """Boolean masks (over all samples of the run) of every regime; see module docstring."""
    v, a = q.v, np.nan_to_num(q.a)
    speed = np.abs(v)
    vmax = float(np.percentile(speed, 99)) if speed.size else 0.0
    dsr = displacement_since_reversal(q.x)
    m: dict[str, np.ndarray] = {}
    for lo, hi in pairwise(REVERSAL_BINS):
        name = (
            f"since_reversal_{lo * 1e6:g}-{hi * 1e6:g}um"
            if np.isfinite(hi)
            else f"since_reversal_over_{lo * 1e3:g}mm"
        )
        m[name] = (dsr >= lo) & (dsr < hi)
    m["low_speed"] = speed < LOW_SPEED
    m["middle_speed"] = (speed >= LOW_SPEED) & (speed < 0.5 * vmax)
    m["high_speed"] = speed >= max(0.5 * vmax, LOW_SPEED)
    amax = float(np.percentile(np.abs(a), 99))
    acc = np.abs(a) > 0.25 * amax if amax > 0 else np.zeros(len(a), bool)
    m["accelerating"] = acc & (a * v > 0)
    m["decelerating"] = acc & (a * v <= 0)
    m["steady_motion"] = ~acc & (speed >= LOW_SPEED)
    m["forward"] = v > 0
    m["backward"] = v < 0
    if q.F_load.size and np.any(q.F_load != 0):
        m["loaded"] = q.F_load != 0
        m["unloaded"] = q.F_load == 0
    f = np.abs(q.F_motor)
    t1, t2 = np.percentile(f, [33.3, 66.7])
    m["current_low"] = f <= t1
    m["current_mid"] = (f > t1) & (f <= t2)
    m["current_high"] = f > t2
    return m


def position_bins(res: Sequence[RunResidual], n_bins: int = 12) -> list[tuple[float, float]]:
    """Equal bins over the covered stroke of all runs."""
    lo = min(float(np.min(q.x[q.valid])) for q in res)
    hi = max(float(np.max(q.x[q.valid])) for q in res)
    edges = np.linspace(lo, hi + 1e-12, n_bins + 1)
    return list(zip(edges[:-1].tolist(), edges[1:].tolist(), strict=True))


def _stats(r: np.ndarray, mask: np.ndarray, total_sse: float, n_total: int) -> dict:
    rr = r[mask]
    if rr.size == 0:
        return {"n": 0}
    sse = float(rr @ rr)
    share_e = sse / total_sse if total_sse > 0 else 0.0
    share_n = rr.size / n_total
    return {
        "n": int(rr.size),
        "rms": float(np.sqrt(sse / rr.size)),
        "mean": float(rr.mean()),
        "energy_share": share_e,
        "sample_share": share_n,
        "concentration": share_e / share_n if share_n > 0 else 0.0,
    }


def localise(
    res: Sequence[RunResidual], r: Sequence[np.ndarray] | None = None, n_pos_bins: int = 12
) -> dict:
    """Residual statistics per regime and per position bin, over all runs.

    ``r`` replaces the runs' own residuals (e.g. a residual after a candidate's fit).
    Returns {"regimes": {name: stats}, "position": [stats with x_lo, x_hi], "overall": stats}.
    """
    rs = [q.r if r is None else r[j] for j, q in enumerate(res)]
    masks = [regime_masks(q) for q in res]
    allr = np.concatenate([rj[q.valid] for rj, q in zip(rs, res, strict=True)])
    total = float(allr @ allr)
    n = allr.size
    names = sorted(
        {k for mk in masks for k in mk},
        key=lambda k: list(masks[0]).index(k) if k in masks[0] else 99,
    )
    out: dict = {"overall": _stats(allr, np.ones(n, bool), total, n), "regimes": {}}
    for name in names:
        mk = np.concatenate(
            [
                mj.get(name, np.zeros(len(q.r), bool))[q.valid]
                for mj, q in zip(masks, res, strict=True)
            ]
        )
        out["regimes"][name] = _stats(allr, mk, total, n)
    xs = np.concatenate([q.x[q.valid] for q in res])
    out["position"] = []
    for lo, hi in position_bins(res, n_pos_bins):
        st = _stats(allr, (xs >= lo) & (xs < hi), total, n)
        st.update({"x_lo": lo, "x_hi": hi})
        out["position"].append(st)
    return out


def where(loc_before: dict, loc_after: dict, top: int = 3) -> list[dict]:
    """The regimes where the residual energy fell most, per sample (the evidence's 'where')."""
    rows = []
    ob = loc_before["overall"]
    tot_b = ob["rms"] ** 2 * ob["n"]
    for name, b in loc_before["regimes"].items():
        a = loc_after["regimes"].get(name, {})
        if not b.get("n") or not a.get("n"):
            continue
        drop = (b["rms"] ** 2 - a["rms"] ** 2) * b["n"]
        rows.append(
            {
                "regime": name,
                "rms_before": b["rms"],
                "rms_after": a["rms"],
                "share_of_improvement": drop
                / max(tot_b - ob["n"] * loc_after["overall"]["rms"] ** 2, 1e-300),
                "sample_share": b["sample_share"],
                "density": (drop / tot_b) / b["sample_share"] if tot_b > 0 else 0.0,
            }
        )
    rows.sort(key=lambda d: -d["density"])
    return rows[:top]


def spatial_spectrum(
    res: Sequence[RunResidual],
    r: Sequence[np.ndarray] | None = None,
    weight: str | None = None,
    lam_min: float = 2e-3,
    lam_max: float | None = None,
    n: int = 400,
    v_min: float = 1e-3,
) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude of the best-fitting sinusoid in x (optionally times the current) per wavelength.

    Least squares of r on [w cos(2 pi x / lam), w sin(2 pi x / lam)] over moving samples
    (|v| > v_min), w = 1 (cogging-like) or w = i (``weight='i'``, ripple-like, amplitude in
    N/A).  Wavelengths log-spaced from ``lam_min`` to ``lam_max`` (default: the covered
    stroke / 1.5).  Returns (wavelengths [m], amplitudes).
    """
    xs, rs, ws = [], [], []
    for j, q in enumerate(res):
        rr = q.r if r is None else r[j]
        ok = q.valid & (np.abs(q.v) > v_min)
        if weight == "i":
            if q.i is None:
                continue
            w = q.i
        else:
            w = np.ones(len(q.r))
        xs.append(q.x[ok])
        rs.append(rr[ok])
        ws.append(w[ok])
    if not xs or sum(len(z) for z in xs) < 10:
        return np.zeros(0), np.zeros(0)
    x, y, w = (np.concatenate(z) for z in (xs, rs, ws))
    span = float(x.max() - x.min())
    lam_max = lam_max or max(span / 1.5, lam_min * 2)
    lams = np.geomspace(lam_min, lam_max, n)
    step = max(1, len(x) // 6000)
    x, y, w = x[::step], y[::step], w[::step]
    amps = np.empty(n)
    for k0 in range(0, n, 50):
        th = 2 * np.pi * x[None, :] / lams[k0 : k0 + 50, None]
        c, s = w * np.cos(th), w * np.sin(th)
        cc, ss, cs = (c * c).sum(1), (s * s).sum(1), (c * s).sum(1)
        cy, sy = c @ y, s @ y
        det = cc * ss - cs**2
        det = np.where(np.abs(det) > 1e-300, det, np.inf)
        a = (ss * cy - cs * sy) / det
        b = (cc * sy - cs * cy) / det
        amps[k0 : k0 + 50] = np.hypot(a, b)
    return lams, amps


def spectral_peaks(
    lams: np.ndarray,
    amps: np.ndarray,
    exclude: Sequence[float] = (),
    rel_excl: float = 0.04,
    n_peaks: int = 2,
) -> list[tuple[float, float]]:
    """The largest local maxima of a spectrum, away from the ``exclude`` wavelengths."""
    if lams.size < 3:
        return []
    idx = [k for k in range(1, len(amps) - 1) if amps[k] >= amps[k - 1] and amps[k] >= amps[k + 1]]
    idx = [k for k in idx if all(abs(lams[k] / e - 1) > rel_excl for e in exclude if e > 0)]
    idx.sort(key=lambda k: -amps[k])
    out: list[tuple[float, float]] = []
    for k in idx:
        if all(abs(lams[k] / l0 - 1) > rel_excl for l0, _ in out):
            out.append((float(lams[k]), float(amps[k])))
        if len(out) >= n_peaks:
            break
    return out


#: Octave bands of the temporal spectrum of a residual [Hz] (lower edges; the last one ends
#: at the Nyquist frequency).
FREQ_BANDS = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0)


def _excess_stats(r: np.ndarray, s: np.ndarray, mask: np.ndarray, total: float, n: int) -> dict:
    """rms residual, rms floor and the share of the excess energy (r^2 - s^2) in ``mask``."""
    if not mask.any():
        return {"n": 0}
    e = float(np.sum(r[mask] ** 2 - s[mask] ** 2))
    share_n = float(mask.sum()) / n
    share_e = e / total if total > 0 else 0.0
    return {
        "n": int(mask.sum()),
        "rms_N": float(np.sqrt(np.mean(r[mask] ** 2))),
        "floor_N": float(np.sqrt(np.mean(s[mask] ** 2))),
        "excess_share": share_e,
        "sample_share": share_n,
        "concentration": share_e / share_n,
    }


def frequency_bands(
    res: Sequence[RunResidual], r: Sequence[np.ndarray] | None = None
) -> list[dict]:
    """Share of a residual's energy per octave band (:data:`FREQ_BANDS`) of its periodogram,
    over the valid part of every run."""
    energy: dict[tuple[float, float], float] = {}
    for j, q in enumerate(res):
        rr = (q.r if r is None else r[j])[q.valid]
        if rr.size < 16:
            continue
        f = np.fft.rfftfreq(rr.size, q.Ts)
        p = np.abs(np.fft.rfft(rr)) ** 2
        edges = [*FREQ_BANDS, 0.5 / q.Ts]
        for lo, hi in pairwise(edges):
            energy[(lo, hi)] = energy.get((lo, hi), 0.0) + float(p[(f >= lo) & (f < hi)].sum())
    tot = sum(energy.values())
    return [
        {"f_lo_Hz": lo, "f_hi_Hz": hi, "energy_share": e / tot if tot > 0 else 0.0}
        for (lo, hi), e in sorted(energy.items())
    ]


def excess_location(
    res: Sequence[RunResidual], sigma: Sequence[np.ndarray], n_pos_bins: int = 12
) -> dict:
    """Where the part of the residual above the noise floor ``sigma`` (per run, per sample
    [N]) sits: the stroke band, speed regime, direction and travel since reversal with the
    highest concentration of excess energy, the octave band holding most of the residual's
    energy and the strongest spatial wavelength (cogging-like)."""
    masks = [regime_masks(q) for q in res]
    r = np.concatenate([q.r[q.valid] for q in res])
    s = np.concatenate([sj[q.valid] for sj, q in zip(sigma, res, strict=True)])
    n = r.size
    total = float(np.sum(r**2 - s**2))

    def regime(name: str) -> np.ndarray:
        return np.concatenate(
            [
                mj.get(name, np.zeros(len(q.r), bool))[q.valid]
                for mj, q in zip(masks, res, strict=True)
            ]
        )

    def best(names: Sequence[str]) -> dict:
        rows = {k: _excess_stats(r, s, regime(k), total, n) for k in names}
        rows = {k: v for k, v in rows.items() if v.get("n")}
        top = max(rows, key=lambda k: rows[k]["concentration"]) if rows else None
        return {"regime": top, "table": rows}

    xs = np.concatenate([q.x[q.valid] for q in res])
    bins = position_bins(res, n_pos_bins)
    pos = [
        _excess_stats(r, s, (xs >= lo) & (xs < hi), total, n) | {"x_lo": lo, "x_hi": hi}
        for lo, hi in bins
    ]
    conc = np.array([p.get("concentration", 0.0) for p in pos])
    k0 = int(np.argmax(conc))
    lo_k = hi_k = k0
    while lo_k > 0 and conc[lo_k - 1] >= 1.0:
        lo_k -= 1
    while hi_k < len(conc) - 1 and conc[hi_k + 1] >= 1.0:
        hi_k += 1
    band = (xs >= bins[lo_k][0]) & (xs < bins[hi_k][1])
    stroke = {
        "x_lo_m": bins[lo_k][0],
        "x_hi_m": bins[hi_k][1],
        **_excess_stats(r, s, band, total, n),
    }
    since = [k for k in masks[0] if k.startswith("since_reversal")]
    freq = frequency_bands(res)
    lams, amps = spatial_spectrum(res)
    peaks = spectral_peaks(lams, amps, n_peaks=1)
    return {
        "stroke_band": stroke,
        "speed": best(["low_speed", "middle_speed", "high_speed"]),
        "direction": best(["forward", "backward"]),
        "since_reversal": best(since),
        "frequency_band": max(freq, key=lambda b: b["energy_share"]) if freq else None,
        "wavelength": (
            {"wavelength_m": peaks[0][0], "amplitude_N": peaks[0][1]} if peaks else None
        ),
    }

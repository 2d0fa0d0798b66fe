"""Figures of the identification: analogues of the paper's Figs. 5-13 and beyond.

Every ``fig*`` function takes an :class:`~feeddrive.identify.result.IdentificationResult`
and returns a matplotlib Figure (ValueError when the step it shows was not run):

- :func:`fig5_maps`: K_f(x) and F_cg(x) sampled by Eqs. 4-5 (Fig. 5);
- :func:`fig6_dstft_cogging`, :func:`fig8_dstft_ripple`: DSTFT magnitude over position and
  wavelength and its position average (Figs. 6, 8);
- :func:`fig7_cogging_components`, :func:`fig9_ripple_components`: magnitude and unwrapped
  phase along the stroke at 37.5, 18.75, 12.5 (and 25) mm (Figs. 7, 9);
- :func:`fig10_map_fits`: sampled versus fitted curves (Fig. 10);
- :func:`fig11_elements`: the identified GMS elements, W_i against Delta_i (Fig. 11 draws the
  model's elements; here their identified values, with the truth when known);
- :func:`fig12_stribeck`: Eq. 13 points and the fitted Eq. 12 (Fig. 12);
- :func:`fig13_prerolling`: friction against position in pre-rolling, measured and
  identified model, both amplitudes (Fig. 13);

and, beyond the paper's figures, :func:`fig_current_loop` (PRBS response, Eq. 2) and
:func:`fig_attraction` (frictional lag of the variable-speed run, Eq. 14).
:func:`fig_sec4_comparison` draws the Sec. 4 scenario simulated with the identified versus the
true plant.  The effects declare which figure shows them
(:attr:`feeddrive.effects.Effect.figures`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter, ScalarFormatter

from ..effects import figure_owner
from ..identify.attraction import _level, simulate_lag
from ..identify.dstft import DSTFT, dstft
from ..identify.result import IdentificationResult
from ..identify.sec4_check import Sec4Comparison
from ..identify.truth_table import elements
from ..physics import eq1_friction, simulate_current, stribeck_level
from ..physics import position_maps as maps
from ..signals import run_label

MM = 1e3  #: m -> mm for axes
WAVELENGTHS_COGGING = (0.0375, 0.01875, 0.0125)
WAVELENGTHS_RIPPLE = (0.0375, 0.01875, 0.0125, 0.025)


def _need(res: IdentificationResult, figure: Callable[..., plt.Figure]) -> Any:
    """The fit of the step the report figure ``figure`` shows (the step of the effect that
    declares it, :func:`feeddrive.effects.figure_owner`); ValueError when it did not run."""
    ident = figure_owner(figure).identification
    value = getattr(res, ident.step)
    what = ident.label
    if value is None:
        raise ValueError(
            f"figure of {what}: that step was not run ({res.skipped.get(what, 'no result')})"
        )
    return value


def truth_parameters(res: IdentificationResult) -> dict[str, Any] | None:
    """The true model's FMU parameters, when the result has a truth."""
    return res.truth.fmu_parameters() if res.truth is not None else None


def fig5_maps(res: IdentificationResult) -> plt.Figure:
    """K_f(x) and F_cg(x) from Eqs. 4-5 along the stroke (Fig. 5)."""
    s = _need(res, fig5_maps).samples
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    ax[0].plot(s.x * MM, s.K_f, lw=0.8)
    ax[0].set_ylabel("K_f [N/A]")
    ax[1].plot(s.x * MM, s.F_cg, lw=0.8)
    ax[1].set_ylabel("F_cg [N]")
    ax[1].set_xlabel("x [mm]")
    ax[0].set_title(
        f"Force ripple and cogging (Eqs. 4-5, loads {', '.join(f'{P:g}' for P in np.round(s.loads, 2))} N)"
    )
    for a in ax:
        a.grid(alpha=0.3)
    return fig


def _dstft(res: IdentificationResult, which: str, figure: Callable[..., plt.Figure]) -> DSTFT:
    s = _need(res, figure).samples
    y = s.F_cg if which == "cogging" else s.K_f
    return dstft(y, x0=float(s.x[0]), step=float(np.median(np.diff(s.x))))


def _dstft_figure(D: DSTFT, label: str, unit: str, marks: Sequence[float]) -> plt.Figure:
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [1.6, 1]})
    k = np.arange(1, len(D.wavelengths))
    keep = D.wavelengths[k] >= 4e-3  # wavelengths down to 4 mm
    k = k[keep]
    mag = D.magnitude[k]
    im = ax[0].pcolormesh(
        D.positions * MM, D.wavelengths[k] * MM, mag, shading="nearest", cmap="viridis"
    )
    ax[0].set_yscale("log")
    ax[0].set_xlabel("window centre x [mm]")
    ax[0].set_ylabel("wavelength [mm]")
    ax[0].set_title(f"|X|/N of {label}")
    fig.colorbar(im, ax=ax[0], label=f"|X|/N [{unit}]")
    ax[1].semilogx(D.wavelengths[k] * MM, mag.mean(axis=1), ".-", ms=3)
    ax[1].xaxis.set_major_formatter(ScalarFormatter())
    ax[1].xaxis.set_minor_formatter(NullFormatter())
    for lam in marks:
        ax[1].axvline(lam * MM, color="r", ls=":", lw=0.8)
    ax[1].set_xlabel("wavelength [mm]")
    ax[1].set_ylabel(f"mean |X|/N [{unit}]")
    ax[1].set_title("position average (dotted: modelled wavelengths)")
    ax[1].grid(alpha=0.3)
    fig.tight_layout()
    return fig


def fig6_dstft_cogging(res: IdentificationResult) -> plt.Figure:
    """DSTFT of F_cg(x), 750-sample rectangular window (Fig. 6)."""
    return _dstft_figure(
        _dstft(res, "cogging", fig6_dstft_cogging), "F_cg", "N", WAVELENGTHS_COGGING
    )


def fig8_dstft_ripple(res: IdentificationResult) -> plt.Figure:
    """DSTFT of K_f(x) (Fig. 8)."""
    return _dstft_figure(_dstft(res, "ripple", fig8_dstft_ripple), "K_f", "N/A", WAVELENGTHS_RIPPLE)


def _components_figure(D: DSTFT, label: str, unit: str, lams: Sequence[float]) -> plt.Figure:
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for lam in lams:
        mag, ph = D.component(lam)
        ax[0].plot(D.positions * MM, mag, label=f"{lam * MM:g} mm")
        ax[1].plot(D.positions * MM, ph, label=f"{lam * MM:g} mm")
    ax[0].set_ylabel(f"|X|/N [{unit}]")
    ax[1].set_ylabel("unwrapped phase [rad]")
    ax[1].set_xlabel("window centre x [mm]")
    ax[0].set_title(f"Magnitude and phase (re x = 0) of the DSTFT of {label}")
    ax[0].legend(fontsize=8, ncol=len(lams))
    for a in ax:
        a.grid(alpha=0.3)
    return fig


def fig7_cogging_components(res: IdentificationResult) -> plt.Figure:
    """Magnitude and phase of X_F at 37.5, 18.75, 12.5 mm along the stroke (Fig. 7)."""
    return _components_figure(
        _dstft(res, "cogging", fig7_cogging_components), "F_cg", "N", WAVELENGTHS_COGGING
    )


def fig9_ripple_components(res: IdentificationResult) -> plt.Figure:
    """Magnitude and phase of X_K at 37.5, 18.75, 12.5 and 25 mm (Fig. 9)."""
    return _components_figure(
        _dstft(res, "ripple", fig9_ripple_components), "K_f", "N/A", WAVELENGTHS_RIPPLE
    )


def fig10_map_fits(res: IdentificationResult) -> plt.Figure:
    """Sampled and fitted K_f(x), F_cg(x) (and the true maps when known) (Fig. 10)."""
    m = _need(res, fig10_map_fits)
    s, truth = m.samples, truth_parameters(res)
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for a, fit, y, unit in (
        (ax[0], m.ripple, s.K_f, "K_f [N/A]"),
        (ax[1], m.cogging, s.F_cg, "F_cg [N]"),
    ):
        a.plot(s.x * MM, y, lw=0.6, color="0.5", label="Eqs. 4-5")
        a.plot(s.x * MM, fit(s.x), lw=1.2, label=f"fit (rms {fit.rms_full:.3g})")
        if truth is not None:
            a.plot(s.x * MM, maps.evaluate(fit.name, s.x, truth), "k--", lw=0.8, label="true")
        a.set_ylabel(unit)
        a.legend(fontsize=8)
        a.grid(alpha=0.3)
    ax[1].set_xlabel("x [mm]")
    ax[0].set_title("Sampled and fitted maps (Eqs. 6-7)")
    return fig


def fig11_elements(res: IdentificationResult) -> plt.Figure:
    """Identified GMS elements: break-away force W_i against spring extension Delta_i."""
    pr = _need(res, fig11_elements)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.stem(pr.Delta * 1e6, pr.W, basefmt=" ", label="identified")
    truth = truth_parameters(res)
    if truth is not None:
        D, W = elements(truth)
        ax.plot(D * 1e6, W, "rx", ms=9, label="true")
    ax.set_xscale("log")
    ax.set_xlabel("Delta_i [um]")
    ax.set_ylabel("W_i = nu_i F_s [N]")
    ax.set_title(f"GMS elements (N = {len(pr.W)}, sum W_i = {pr.W.sum():.2f} N)")
    ax.legend()
    ax.grid(alpha=0.3, which="both")
    return fig


def fig12_stribeck(res: IdentificationResult) -> plt.Figure:
    """Eq. 13 points and fitted Stribeck curve, log speed axis (Fig. 12)."""
    s = _need(res, fig12_stribeck)
    pts = s.points
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ax.errorbar(
        pts.speed * MM,
        pts.friction,
        yerr=pts.spread,
        fmt="o",
        ms=4,
        capsize=2,
        label="Eq. 13 (mean +- std over position)",
    )
    v = np.geomspace(pts.speed.min() / 2, pts.speed.max() * 1.5, 300)
    ax.plot(v * MM, s.curve(v), label="fit of Eq. 12")
    truth = truth_parameters(res)
    if truth is not None:
        F = (
            stribeck_level(
                v,
                truth["friction.F_s"],
                truth["friction.F_c"],
                truth["friction.V_s"],
                truth["friction.delta"],
            )
            + truth["friction.sigma2"] * v
        )
        ax.plot(v * MM, F, "k--", lw=0.8, label="true")
    ax.set_xscale("log")
    ax.set_xlabel("v [mm/s]")
    ax.set_ylabel("F_f [N]")
    ax.set_title("Stribeck curve")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return fig


def fig13_prerolling(res: IdentificationResult) -> plt.Figure:
    """Friction against position in pre-rolling: measured (Eq. 1) and the identified
    Maxwell-slip model, for both amplitudes (Fig. 13)."""
    pr = _need(res, fig13_prerolling)
    fig, ax = plt.subplots(1, len(pr.curves), figsize=(11, 4.2))
    ax = np.atleast_1d(ax)
    for a, (tag, (x, F, model)) in zip(ax, pr.curves.items(), strict=True):
        a.plot((x - x.mean()) * 1e6, F, lw=0.6, color="0.5", label="measured (Eq. 1)")
        a.plot((x - x.mean()) * 1e6, model, lw=1.0, label="identified model")
        a.set_xlabel("x - mean [um]")
        a.set_ylabel("F_f [N]")
        a.set_title(f"{tag} amplitude: rms {pr.rms[tag]:.3g} N")
        a.legend(fontsize=8)
        a.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def fig_current_loop(res: IdentificationResult, seconds: float = 0.1) -> plt.Figure:
    """Measured current of the PRBS run and the identified G(z)'s simulation."""
    c = _need(res, fig_current_loop)
    run = max(res.groups["prbs"], key=lambda r: len(r.time))
    u, i = np.asarray(run.u, float), np.asarray(run.i, float)
    i_sim = simulate_current(c.a, c.b, u)
    t = np.asarray(run.time, float)
    k0 = int((run.meta or {}).get("prbs_start", 0))
    sl = slice(k0, min(len(t), k0 + int(seconds / c.Ts)))
    fig, ax = plt.subplots(figsize=(8, 3.8))
    ax.plot(t[sl], i[sl], lw=0.7, color="0.5", label="measured i")
    ax.plot(t[sl], i_sim[sl], lw=1.0, label=f"G(z), order {c.order}, delay {c.delay}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("i [A]")
    ax.set_title(f"Current loop (Eq. 2): fit {c.fit_percent:.1f} %")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def fig_attraction(res: IdentificationResult) -> plt.Figure:
    """Friction of the variable-speed run (Eq. 1, viscous part removed), the Stribeck level
    s(v) and the lagged friction of Eq. 14 with the identified C."""
    at = _need(res, fig_attraction)
    run = max(res.groups["variable_speed"], key=lambda r: len(r.time))
    p = res.model.parameters
    if run.i is None:
        raise ValueError(f"{run_label(run)}: the variable-speed run has no current column")
    F, v, _K, Ts = eq1_friction(
        run.time, run.x, run.i, p["m"], p, p, run.F_load if run.F_load is not None else 0.0
    )
    G = F - p["friction.sigma2"] * v
    s = _level(v, p)
    t = np.asarray(run.time, float)
    x = np.asarray(run.x, float)
    ok = np.isfinite(G) & (v > 2e-4)
    ok &= np.abs(x - x[np.argmax(ok)]) >= 5e-4  # after the break-away (as the fit)
    idx = np.flatnonzero(ok)
    fig, ax = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    ax[0].plot(t[ok], G[ok], lw=0.5, color="0.5", label="F_f - sigma2 v (Eq. 1)")
    ax[0].plot(t[ok], s[ok], lw=0.8, label="s(v) (no lag)")
    ax[1].plot(t[ok], (G - s)[ok], lw=0.5, color="0.5", label="measured lag G - s(v)")
    if at.resolved and np.isfinite(at.C) and idx.size:
        seg = slice(idx[0], idx[-1] + 1)
        Gs = simulate_lag(s[seg], 1.0 / at.C, float(s[idx[0]]), Ts)
        ax[0].plot(t[seg], Gs, lw=1.0, label=f"Eq. 14, C = {at.C:.4g} N/s")
        ax[1].plot(t[seg], Gs - s[seg], lw=1.0, label="Eq. 14 lag")
    ax[1].set_xlabel("t [s]")
    ax[0].set_ylabel("force [N]")
    ax[1].set_ylabel("lag [N]")
    ax[0].set_title(f"Frictional lag (Eq. 14): {at.message}", fontsize=9)
    for a in ax:
        a.legend(fontsize=8)
        a.grid(alpha=0.3)
    return fig


def fig_sec4_comparison(cmp: Sec4Comparison) -> plt.Figure:
    """Tracking error of the Sec. 4 cases: true plant versus identified plant (same
    controller and feedforward, designed on the identified model)."""
    cases = list(cmp.truth.errors)
    fig, ax = plt.subplots(len(cases), 1, figsize=(9, 2.3 * len(cases)), sharex=True)
    t = cmp.truth.time
    for a, case in zip(np.atleast_1d(ax), cases, strict=True):
        a.plot(t, cmp.truth.errors[case] * 1e6, lw=0.8, label="true plant")
        a.plot(t, cmp.predicted.errors[case] * 1e6, "--", lw=0.8, label="identified plant")
        a.set_ylabel("e [um]")
        a.set_title(case, fontsize=9)
        a.grid(alpha=0.3)
    np.atleast_1d(ax)[0].legend(fontsize=8)
    np.atleast_1d(ax)[-1].set_xlabel("t [s]")
    fig.tight_layout()
    return fig

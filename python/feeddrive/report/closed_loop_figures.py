"""Figures of the closed-loop reproductions: analogues of the paper's Figs. 14 and 16."""

from __future__ import annotations

from string import ascii_lowercase

import matplotlib.pyplot as plt
import numpy as np


def fig14(sec3, window: float = 0.2) -> plt.Figure:
    """Top reversal of the 30 mm sinusoid: measured vs each simulated model (Fig. 14 a-c; one panel per model)."""
    run = sec3.measured
    top = sec3.top_reversal
    Ts = run.time[1] - run.time[0]
    w = int(round(window / Ts))
    sl = slice(max(0, top - w), top + w + 1)
    names = list(sec3.simulated)
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.4), sharey=True)
    for ax, name, tag in zip(np.atleast_1d(axes), names, ascii_lowercase, strict=False):
        x_top = run.x[top]
        ax.plot(run.time[sl], (run.x[sl] - x_top) * 1e6, "k-", lw=1.6, label="measured")
        ax.plot(
            sec3.simulated[name]["time"][sl],
            (sec3.simulated[name]["x"][sl] - x_top) * 1e6,
            "r--",
            lw=1.2,
            label="simulated",
        )
        ax.set_title(f"({tag}) {name}", fontsize=9)
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("x - x(top) [um]")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def sim_minus_measured(sec3) -> plt.Figure:
    """x_sim - x_meas over the whole run for each model."""
    fig, ax = plt.subplots(figsize=(9, 3.2))
    for name, s in sec3.simulated.items():
        ax.plot(s["time"], (s["x"] - sec3.measured.x) * 1e6, lw=0.8, label=name)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("x_sim - x_meas [um]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def fig16(sec4) -> plt.Figure:
    """Tracking error against time for each feedforward (Fig. 16 a-c; one panel per case)."""
    cases = list(sec4.errors)
    fig, axes = plt.subplots(len(cases), 1, figsize=(9, 2.4 * len(cases)), sharex=True, sharey=True)
    for ax, name, tag in zip(np.atleast_1d(axes), cases, ascii_lowercase, strict=False):
        t, e = sec4.time, sec4.errors[name]
        ax.plot(t, e * 1e6, "k-", lw=0.7)
        ax.set_title(f"({tag}) {name}", fontsize=9)
        ax.set_ylabel("e [um]")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[-1].set_xlabel("t [s]")
    fig.tight_layout()
    return fig


def reversal_closeups(sec4, window: float = 0.3) -> plt.Figure:
    """Error near each reference reversal, all feedforward cases overlaid."""
    revs = sec4.reversal_indices
    fig, axes = plt.subplots(1, len(revs), figsize=(4 * max(1, len(revs)), 3.2), squeeze=False)
    Ts = sec4.time[1] - sec4.time[0]
    w = int(round(window / Ts))
    for ax, r in zip(axes[0], revs, strict=True):
        sl = slice(max(0, r - w), r + w + 1)
        for name, e in sec4.errors.items():
            ax.plot(sec4.time[sl], e[sl] * 1e6, lw=1, label=name)
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("e [um]")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    return fig

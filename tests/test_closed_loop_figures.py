"""The closed-loop figures draw one labelled panel per simulated model or feedforward case,
however many there are."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from feeddrive.report.closed_loop_figures import fig14, fig16

NAMES = ["paper model", "without aperiodic cogging", "static friction", "fourth model"]


def _titles(fig: plt.Figure) -> list[str]:
    return [ax.get_title() for ax in fig.axes]


def test_fig14_has_a_panel_per_model() -> None:
    t = np.arange(0.0, 1.0, 1e-3)
    x = 0.015 * np.sin(2 * np.pi * t)
    sim = {n: {"time": t, "x": x + 1e-6 * k} for k, n in enumerate(NAMES)}
    sec3 = SimpleNamespace(measured=SimpleNamespace(time=t, x=x), top_reversal=250, simulated=sim)
    fig = fig14(sec3)
    assert _titles(fig) == [f"({tag}) {n}" for tag, n in zip("abcd", NAMES, strict=True)]
    plt.close(fig)


def test_fig16_has_a_panel_per_case() -> None:
    t = np.arange(0.0, 1.0, 1e-3)
    sec4 = SimpleNamespace(time=t, errors={n: 1e-6 * np.sin(t + k) for k, n in enumerate(NAMES)})
    fig = fig16(sec4)
    assert _titles(fig) == [f"({tag}) {n}" for tag, n in zip("abcd", NAMES, strict=True)]
    plt.close(fig)

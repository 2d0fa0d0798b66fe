"""Paper Sec. 4 (Figs. 15-16): state-space control with ZPETC pre-filter on a 5 mm / 6 s
sinusoid, without feedforward, with static (Tustin) friction feedforward and with GMS
feedforward (both with cogging and ripple compensation).  The feedforward runs on the
paper's nominal parameters; the simulated plant differs from them by PERTURBATION (a real
machine is never the model), so GMS feedforward cannot cancel friction exactly."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..control.feedforward import DEFAULT_V_EPS, FeedforwardOptions, FrictionFeedforward
from ..harness.controllers import state_space_spec
from ..harness.references import reversals, sinusoid
from ..harness.runs import run_closed_loop
from ..paper import paper_parameters
from .tracking_error import summarise

AMPLITUDE, PERIOD, CENTRE, DURATION = 0.005, 6.0, 0.150, 12.5
#: half-width [s] of the window around each reversal; the rest of the run is "elsewhere"
REVERSAL_WINDOW = 0.4

#: How the simulated machine differs from the nominal model the feedforward uses (relative).
PERTURBATION = {
    "friction.F_s": 1.08,
    "friction.F_c": 1.08,
    "friction.V_s": 1.2,
    "friction.sigma2": 1.1,
    "friction.k[1]": 0.8,
    "friction.k[2]": 0.8,
    "friction.k[3]": 0.8,
    "friction.k[4]": 0.8,
    "friction.k[5]": 0.8,
    "m": 1.03,
    **{f"cogging.{ab}[{j}]": 1.05 for ab in "ab" for j in (1, 2, 3)},
}
CASES: dict[str, FrictionFeedforward | None] = {
    "no feedforward": None,
    "static friction feedforward": "static",
    "GMS feedforward": "gms",
}
PAPER = {
    "no feedforward": (27.0, 13.0),
    "static friction feedforward": (23.0, 6.0),
    "GMS feedforward": (11.0, 4.0),
}


def perturbed_plant(nominal: dict | None = None) -> dict:
    """The nominal parameters times PERTURBATION."""
    p = dict(nominal or paper_parameters())
    for k, f in PERTURBATION.items():
        p[k] = p[k] * f
    return p


@dataclass
class Sec4Result:
    time: np.ndarray
    errors: dict[str, np.ndarray] = field(default_factory=dict)
    rows: list[dict[str, float | str]] = field(default_factory=list)
    reversal_indices: list[int] = field(default_factory=list)
    walls: dict[str, float] = field(default_factory=dict)
    #: whether the plant was ``perturbed_plant(nominal)`` (the default of :func:`reproduce`)
    perturbed: bool = True

    def table(self) -> str:
        lines = [
            "Sec. 4 (Fig. 16): 5 mm / 6 s sinusoid, tracking error e = x_ref - x",
            f"{'case':30s} {'reversal peak [um]':>19s} {'paper':>6s} {'band elsewhere [um]':>20s} "
            f"{'paper':>6s} {'rms [um]':>9s}",
        ]
        for r in self.rows:
            band, paper_band = f"+-{r['band_um']:.1f}", f"+-{r['paper_band_um']:.0f}"
            lines.append(
                f"{r['case']:30s} {r['reversal_peak_um']:19.1f} {r['paper_reversal_um']:6.0f} "
                f"{band:>20s} {paper_band:>6s} {r['rms_um']:9.2f}"
            )
        if not self.perturbed:
            lines.append("plant and nominal parameters given by the caller")
            return "\n".join(lines)
        lines.append(
            "plant perturbation vs feedforward nominal: "
            + ", ".join(
                f"{k} x{v:g}" for k, v in PERTURBATION.items() if not k.startswith("cogging")
            )
            + ", cogging a/b x1.05"
        )
        return "\n".join(lines)


def reproduce(
    v_eps: float | None = None,
    plant: Mapping[str, Any] | None = None,
    nominal: Mapping[str, Any] | None = None,
) -> Sec4Result:
    """Run the three cases and summarise their errors at reversals and elsewhere.

    Parameters
    ----------
    v_eps : velocity threshold of the friction feedforward [m/s] (its default when None).
    plant : FMU parameters of the simulated machine (default: ``perturbed_plant(nominal)``).
    nominal : parameters the controller and the feedforward are designed on (default: the
        paper's).  E.g. an identified model as ``nominal`` with the true model, then the
        identified one, as ``plant`` compares the identified model's prediction with the truth.
    """
    ref = sinusoid(AMPLITUDE, PERIOD, CENTRE, DURATION)
    nominal = dict(paper_parameters() if nominal is None else nominal)
    perturbed = plant is None
    plant = perturbed_plant(nominal) if plant is None else dict(plant)
    out = Sec4Result(
        time=ref.time, reversal_indices=[int(r) for r in reversals(ref.x)], perturbed=perturbed
    )
    for case, friction in CASES.items():
        opts = (
            None
            if friction is None
            else FeedforwardOptions(friction=friction, v_eps=v_eps or DEFAULT_V_EPS)
        )
        spec = state_space_spec(nominal, feedforward=opts)  # feedforward on ``nominal``
        res = run_closed_loop(plant, spec, ref)
        e = ref.x - res["x"]
        out.errors[case] = e
        out.walls[case] = float(res["wall"])
        s = summarise(e, ref.x, ref.Ts, half_width=REVERSAL_WINDOW)
        out.rows.append(
            {
                "case": case,
                "reversal_peak_um": s.reversal_peak * 1e6,
                "paper_reversal_um": PAPER[case][0],
                "band_um": s.band * 1e6,
                "paper_band_um": PAPER[case][1],
                "rms_um": s.rms * 1e6,
            }
        )
    return out

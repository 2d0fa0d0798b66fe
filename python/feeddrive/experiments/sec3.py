"""Paper Sec. 3 (Fig. 14): a measured position-controlled sinusoid (30 mm, 6 s) against
simulations of the full model, the model without aperiodic cogging and the model with static
friction instead of GMS.  The "measurement" is the full model with sensor effects (100 nm
quantisation, real current noise, fixed seed), written as a recording."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..data import RECORDING_DECIMALS, Run, write_run
from ..effects import paper_scenarios
from ..harness.controllers import state_space_spec
from ..harness.references import sinusoid
from ..harness.runs import closed_loop_run, run_closed_loop
from ..harness.sensors import Sensors
from ..paper import paper_parameters

#: The simulated models by label: the full model, then each effect's paper scenario that
#: switches it off (:attr:`feeddrive.effects.Effect.scenario`, catalogue order).
VARIANTS: dict[str, dict[str, bool]] = {"full model": {}, **paper_scenarios()}
AMPLITUDE, PERIOD, CENTRE = 0.030, 6.0, 0.150


@dataclass
class Sec3Result:
    measured: Run
    simulated: dict[str, dict[str, np.ndarray]]
    rows: list[dict[str, float | str]] = field(default_factory=list)
    top_reversal: int = 0

    def table(self) -> str:
        lines = [
            "Sec. 3 (Fig. 14): 30 mm / 6 s sinusoid, simulation vs 'measurement'",
            f"{'model':34s} {'top-reversal peak |x_sim - x_meas| [um]':>40s} {'rms over run [um]':>18s}",
        ]
        for r in self.rows:
            lines.append(f"{r['model']:34s} {r['reversal_peak_um']:40.2f} {r['rms_um']:18.2f}")
        return "\n".join(lines)


def reproduce(out_dir: Path | None = None, seed: int = 3, window: float = 0.3) -> Sec3Result:
    """Run the Sec. 3 reproduction; with ``out_dir`` also write the measured run there."""
    ref = sinusoid(AMPLITUDE, PERIOD, CENTRE, PERIOD)
    truth = paper_parameters()
    spec = state_space_spec()
    run, _ = closed_loop_run(
        truth,
        spec,
        ref,
        Sensors(seed=seed),
        experiment="sec3_sinusoid",
        amplitude=AMPLITUDE,
        period=PERIOD,
        centre=CENTRE,
    )
    if out_dir is not None:
        write_run(run, Path(out_dir) / "sec3_measured.csv", RECORDING_DECIMALS)
    top = int(np.argmax(ref.x))
    w = int(round(window / ref.Ts))
    res = Sec3Result(measured=run, simulated={}, top_reversal=top)
    for name, change in VARIANTS.items():
        p = dict(truth)
        p.update(change)
        sim = run_closed_loop(p, spec, ref)
        d = sim["x"] - run.x
        res.simulated[name] = {"time": sim["time"], "x": sim["x"], "F_friction": sim["F_friction"]}
        res.rows.append(
            {
                "model": name,
                "reversal_peak_um": float(np.abs(d[top - w : top + w + 1]).max() * 1e6),
                "rms_um": float(np.sqrt(np.mean(d**2)) * 1e6),
            }
        )
    return res

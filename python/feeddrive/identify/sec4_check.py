"""Does the identified model predict the true machine?  The paper's Sec. 4 scenario with the
controller and feedforward designed on the identified model, simulated once with the
identified model as plant (the prediction) and once with the true model (the machine).

The criterion: the tracking-error peak at every reversal of the reference agrees
within :data:`REVERSAL_TOL` (2 um) in each of the three cases (no feedforward, static
friction feedforward, GMS feedforward).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..experiments import sec4
from ..experiments.tracking_error import reversal_mask, summarise
from ..harness.references import sinusoid

REVERSAL_TOL = 2e-6  #: m


@dataclass
class Sec4Comparison:
    """Per case: reversal peaks of the truth and of the prediction, and their difference."""

    truth: sec4.Sec4Result
    predicted: sec4.Sec4Result
    rows: list[dict[str, Any]] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return all(r["max peak difference [um]"] <= REVERSAL_TOL * 1e6 for r in self.rows)

    def text(self) -> str:
        lines = [
            "Sec. 4 scenario, controller and feedforward on the identified model: "
            "true plant vs identified plant (reversal peaks of e = x_ref - x) [um]"
        ]
        for r in self.rows:
            lines.append(
                f"  {r['case']:30s} true {r['true peaks [um]']:24s} identified "
                f"{r['identified peaks [um]']:24s} max diff {r['max peak difference [um]']:.2f}"
                f" (tol {REVERSAL_TOL * 1e6:g}), max |e_true - e_id| near reversals "
                f"{r['max |e_true - e_id| near reversals [um]']:.2f}"
            )
        return "\n".join(lines)


def compare_sec4(identified: Mapping[str, Any], truth: Mapping[str, Any]) -> Sec4Comparison:
    """Run Sec. 4 with ``identified`` as nominal, plant = ``truth`` and plant = ``identified``
    (FMU parameters)."""
    real = sec4.reproduce(plant=truth, nominal=identified)
    pred = sec4.reproduce(plant=identified, nominal=identified)
    ref = sinusoid(sec4.AMPLITUDE, sec4.PERIOD, sec4.CENTRE, sec4.DURATION)
    near, _ = reversal_mask(ref.x, ref.Ts)
    out = Sec4Comparison(truth=real, predicted=pred)
    for case in sec4.CASES:
        a = np.array(summarise(real.errors[case], ref.x, ref.Ts).reversal_peaks)
        b = np.array(summarise(pred.errors[case], ref.x, ref.Ts).reversal_peaks)
        d = real.errors[case] - pred.errors[case]
        out.rows.append(
            {
                "case": case,
                "true peaks [um]": ", ".join(f"{v * 1e6:.2f}" for v in a),
                "identified peaks [um]": ", ".join(f"{v * 1e6:.2f}" for v in b),
                "max peak difference [um]": float(np.max(np.abs(a - b)) * 1e6),
                "max |e_true - e_id| near reversals [um]": float(np.max(np.abs(d[near])) * 1e6),
            }
        )
    return out

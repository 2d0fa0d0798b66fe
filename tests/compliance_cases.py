"""Closed-loop runs of a drive carrying a load on a spring, for the compliance-band tests:
the paper's drive with ``compliance`` on, under one of the harness's controllers (``pid``,
``pid_lead``, ``state_space``) and one excitation (``sinusoid``, ``point_to_point``,
``prbs``), 100 nm scale, 5 mA current noise, encoder on the slide.

Each excitation is spread over its runs, so that every held-out block of the diagnosis holds
some of it (a resonance rung in one block only cannot be told from chance):

- ``sinusoid``: 10 mm at 1 Hz (a reversal every 0.5 s: the friction's step at each reversal
  and the start ring the load) and 4 mm at 4 Hz;
- ``point_to_point``: 10 mm trapezoidal moves at 20 and 50 mm/s, 3 m/s^2, 0.15 s dwell;
- ``prbs``: the stage held by the loop, a maximum-length sequence (order 11, 2 samples a
  bit, +-0.3 V) added to the controller's output for two periods, and the 1 Hz sinusoid.
"""

from __future__ import annotations

import numpy as np

from feeddrive.data import Run
from feeddrive.harness import (
    Reference,
    Sensors,
    back_and_forth,
    closed_loop_run,
    pid_lead_spec,
    pid_spec,
    prbs,
    sinusoid,
    state_space_spec,
)
from feeddrive.model_file import ModelFile, paper_model

PAPER = paper_model()
M = float(PAPER.parameters["m"])
SPECS = {"pid": pid_spec, "pid_lead": pid_lead_spec, "state_space": state_space_spec}
Ts = 5e-4


def loaded(f: float, zeta: float, ratio: float) -> ModelFile:
    """The paper's drive with a load of ``ratio`` x its mass on a spring at f [Hz], zeta."""
    return PAPER.with_effect(
        "compliance",
        True,
        **{"compliance.m2": ratio * M, "compliance.f": f, "compliance.zeta": zeta},
    )


def _sensors(seed: int) -> Sensors:
    return Sensors(quantum=1e-7, current_noise=0.005, seed=seed, noise_on_stage=False)


def _references(excitation: str) -> list[tuple[str, Reference, np.ndarray | None]]:
    sin1 = ("sinusoid_1Hz", sinusoid(0.01, 1.0, 0.15, 5.0), None)
    if excitation == "sinusoid":
        return [sin1, ("sinusoid_4Hz", sinusoid(0.004, 0.25, 0.15, 4.0), None)]
    if excitation == "point_to_point":
        moves = back_and_forth([0.02, 0.05] * 3, stroke=0.01, x0=0.145, accel=3.0, dwell=0.15)
        return [("moves", moves, None), sin1]
    if excitation == "prbs":
        seq = prbs(11, amplitude=0.3, hold=2, periods=2)
        u_ff = np.concatenate([np.zeros(200), seq])
        n = len(u_ff) - 1
        hold = Reference(Ts, np.full(n + 1, 0.15), np.zeros(n + 1), np.zeros(n + 1))
        return [("prbs", hold, u_ff), sin1]
    raise ValueError(f"excitation {excitation!r}: one of sinusoid, point_to_point, prbs")


def case_runs(truth: ModelFile, controller: str, excitation: str, seed: int = 1) -> list[Run]:
    """The runs of one case (module docstring)."""
    spec = SPECS[controller]()
    p = truth.fmu_parameters()
    return [
        closed_loop_run(p, spec, ref, _sensors(seed + j), name=name, u_ff=u_ff)[0]
        for j, (name, ref, u_ff) in enumerate(_references(excitation))
    ]

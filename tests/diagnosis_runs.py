"""Closed-loop runs of a true model for the diagnosis tests: the harness's PID, noise on the
current measurement only (DATA.md runs with their sidecars)."""

from __future__ import annotations

from feeddrive.data import Run
from feeddrive.harness import (
    Reference,
    Sensors,
    back_and_forth,
    closed_loop_run,
    pid_spec,
    sinusoid,
)
from feeddrive.model_file import ModelFile


def simulate_run(
    truth: ModelFile,
    ref: Reference,
    current_noise: float = 0.0,
    quantum: float = 1e-7,
    seed: int = 0,
    name: str = "sim",
    spec: dict | None = None,
) -> Run:
    """The truth in closed loop under the harness's PID (or ``spec``)."""
    sensors = Sensors(quantum=quantum, current_noise=current_noise, seed=seed, noise_on_stage=False)
    return closed_loop_run(truth.fmu_parameters(), spec or pid_spec(), ref, sensors, name=name)[0]


def sinusoid_reference(duration: float, period: float = 6.0) -> Reference:
    """30 mm sinusoid at mid-stroke, starting at rest at the lower end."""
    return sinusoid(0.03, period, 0.15, duration)


def make_runs(
    truth: ModelFile,
    seed: int,
    noise: float = 0.005,
    quantum: float = 1e-7,
    cs: bool = True,
    sin_period: float = 6.0,
    cs_seed_offset: int = 100,
) -> list[Run]:
    """Closed-loop sinusoid (+ back-and-forth constant-speed run, seed + ``cs_seed_offset``)."""
    runs = [
        simulate_run(
            truth,
            sinusoid_reference(sin_period, period=sin_period),
            current_noise=noise,
            quantum=quantum,
            seed=seed,
            name="sinusoid",
        )
    ]
    if cs:
        runs.append(
            simulate_run(
                truth,
                back_and_forth([0.003, 0.01, 0.03], stroke=0.01),
                current_noise=noise,
                quantum=quantum,
                seed=seed + cs_seed_offset,
                name="constant_speed",
            )
        )
    return runs

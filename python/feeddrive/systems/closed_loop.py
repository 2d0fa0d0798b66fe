"""The closed loop as a system: two FMUs, their start values, the connections.

Connections: plant ``x`` -> controller ``x_meas``, controller ``u`` -> plant ``u``.  The
reference is the controller FMU's internal generator (``ref.source`` 1), so the system has no
external input.  Start values: the plant's parameters, ``x`` = the reference's first value,
``solver.tol`` (the tolerance the harness gives through fmi2SetupExperiment, which an engine
may not), the controller's parameter set (:func:`~..harness.controller_fmu.controller_fmu_parameters`)
and ``x_meas`` = the same first value.

Delay convention: ``delay`` is the computation delay of the harness run the system
reproduces (the controller spec's ``delay``).  Our Gauss-Seidel masters and fmpy's container
FMU hand u over within the step: the controller FMU's ``ctrl.delay`` is ``delay``.  The Jacobi
engines (libcosim, Ecos, fmpy's ``simulate_ssp``) hand outputs over after the step: at
h = Ts that is one sample, so their files carry ``ctrl.delay`` = ``delay`` - 1 (a system with
``delay`` 1 runs them at h = Ts and reproduces the harness with delay 1); a system with
``delay`` 0 runs them at h = Ts/``jacobi_substeps`` (a delay of h the harness does not have).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..control.feedforward import FeedforwardOptions, FrictionFeedforward
from ..experiments import sec3, sec4
from ..fmu import fmu_path
from ..harness.controller_fmu import controller_fmu_parameters, controller_fmu_path, sinusoid_source
from ..harness.controllers import state_space_spec
from ..paper import paper_parameters

Values = dict[str, float | int | bool]
#: (start component, start connector, end component, end connector)
CONNECTIONS = (("plant", "x", "controller", "x_meas"), ("controller", "u", "plant", "u"))


@dataclass
class ClosedLoopSystem:
    """Everything an engine needs: FMU files, start values per component, timing."""

    name: str
    plant: Values
    controller: Values
    x0: float
    stop_time: float
    Ts: float = 5e-4
    plant_fmu: Path = field(default_factory=fmu_path)
    controller_fmu: Path = field(default_factory=controller_fmu_path)
    tolerance: float = 1e-6
    #: macro steps per sample Ts of the Jacobi engines (libcosim, simulate_ssp): their
    #: outputs reach the inputs one macro step late; with a whole Ts the loop designed for
    #: no delay is unstable, so 10 unless ``delay`` is 1 (then 1: h = Ts)
    jacobi_substeps: int = 10
    #: the computation delay [samples] of the harness run the system reproduces
    delay: int = 0

    @property
    def n(self) -> int:
        """Number of controller samples (of Ts)."""
        return int(round(self.stop_time / self.Ts))

    @property
    def jacobi_step(self) -> float:
        """The Jacobi engines' macro step [s] (the container FMU's is Ts)."""
        return self.Ts / self.jacobi_substeps

    def ctrl_delay(self, jacobi: bool) -> int:
        """The controller FMU's ``ctrl.delay`` in a Jacobi engine (``jacobi``) or in a master
        that hands u over within the step."""
        return self.delay - 1 if jacobi and self.jacobi_substeps == 1 and self.delay else self.delay

    def start_values(self, jacobi: bool = False) -> dict[str, Values]:
        """Start values by component name (``plant``, ``controller``) for a Jacobi engine
        (``jacobi``) or not (see the module's delay convention)."""
        plant: Values = {**self.plant, "x": self.x0, "v": 0.0, "solver.tol": self.tolerance}
        ctrl: Values = {**self.controller, "x_meas": self.x0}
        if self.delay:
            ctrl["ctrl.delay"] = self.ctrl_delay(jacobi)
        return {"plant": plant, "controller": ctrl}


def _system(
    name: str,
    plant: Mapping[str, float | int | bool],
    spec: Mapping,
    amplitude: float,
    period: float,
    centre: float,
    duration: float,
) -> ClosedLoopSystem:
    ctrl = controller_fmu_parameters(
        spec, reference=sinusoid_source(amplitude, period, centre, duration), quantum=1e-7
    )
    delay = int(spec.get("delay", 0))
    return ClosedLoopSystem(
        name=name,
        plant=dict(plant),
        controller=ctrl,
        x0=centre - amplitude,
        stop_time=duration,
        Ts=float(ctrl["Ts"]),
        jacobi_substeps=1 if delay else 10,
        delay=delay,
    )


def sec3_system(delay: int = 0) -> ClosedLoopSystem:
    """Sec. 3: state space + ZPETC on the paper's plant, 30 mm / 6 s sinusoid, 100 nm scale;
    ``delay`` samples of computation delay (designed for)."""
    spec = {**state_space_spec(), "delay": delay} if delay else state_space_spec()
    return _system(
        "sec3" if not delay else f"sec3_delay{delay}",
        paper_parameters(),
        spec,
        sec3.AMPLITUDE,
        sec3.PERIOD,
        sec3.CENTRE,
        sec3.PERIOD,
    )


def sec4_system(
    friction: FrictionFeedforward = "gms", duration: float = sec4.DURATION, delay: int = 0
) -> ClosedLoopSystem:
    """Sec. 4: feedforward (``friction`` static/gms, with cogging and ripple) on the paper's
    nominal parameters, the perturbed plant, 5 mm / 6 s sinusoid, 100 nm scale; ``delay``
    samples of computation delay."""
    spec = state_space_spec(paper_parameters(), feedforward=FeedforwardOptions(friction=friction))
    if delay:
        spec["delay"] = delay
    return _system(
        f"sec4_{friction}" + (f"_delay{delay}" if delay else ""),
        sec4.perturbed_plant(),
        spec,
        sec4.AMPLITUDE,
        sec4.PERIOD,
        sec4.CENTRE,
        duration,
    )

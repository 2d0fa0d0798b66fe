"""The paper's closed-loop results that ``feeddrive run`` reports: the controller's design,
one timed run of the 30 mm / 6 s sinusoid, Sec. 3 (:mod:`.sec3`) and Sec. 4 (:mod:`.sec4`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..control.state_space import StateSpaceController
from ..harness.controllers import make_controller, state_space_spec
from ..harness.references import Reference, sinusoid
from ..harness.runs import run_closed_loop
from ..paper import paper_parameters
from . import sec3, sec4


@dataclass
class Reproduction:
    """What :func:`reproduce_paper` computed."""

    design: str  #: the state-space controller's design report
    run_line: str  #: wall time, events and steps of one 30 mm / 6 s run
    sec3: sec3.Sec3Result
    sec4: sec4.Sec4Result


def _nothing() -> None:
    return None


def reproduce_paper(
    out_dir: Path | None = None, step: Callable[[], object] = _nothing
) -> Reproduction:
    """Design the controller, time one closed-loop run, reproduce Secs. 3 and 4.

    ``out_dir``: where Sec. 3 writes its measured run (none written without it).  ``step``
    is called after each of the three stages (design and timed run, Sec. 3, Sec. 4).
    """
    ctrl = make_controller(
        state_space_spec(), Reference(5e-4, np.array([0.15, 0.15]), np.zeros(2), np.zeros(2))
    )
    if not isinstance(ctrl, StateSpaceController):
        raise TypeError(f"the state-space spec made a {type(ctrl).__name__}")
    design = ctrl.format_report()
    step()
    ref = sinusoid(sec3.AMPLITUDE, sec3.PERIOD, sec3.CENTRE, sec3.PERIOD)
    one = run_closed_loop(paper_parameters(), state_space_spec(), ref)
    wall = float(one["wall"])
    run_line = (
        f"30 mm / 6 s closed-loop sinusoid (co-simulation, Python controller at 2 kHz): "
        f"wall {wall * 1e3:.0f} ms ({6.0 / wall:.0f}x real time), "
        f"{int(one['state_events'])} friction events ({int(one['stats.n_stick'])} "
        f"element sticks, {int(one['stats.n_slip'])} slips), "
        f"{int(one['stats.n_steps'])} integrator steps"
    )
    r3 = sec3.reproduce(out_dir)
    step()
    r4 = sec4.reproduce()
    step()
    return Reproduction(design=design, run_line=run_line, sec3=r3, sec4=r4)

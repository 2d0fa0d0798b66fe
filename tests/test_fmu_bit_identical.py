"""A refused call changes nothing, to the bit, and the FMI 3.0 early return leaves the FMI 2.0
step's trajectory unchanged, to the bit (both builds of the plant, co-simulation):

* a tunable set refused at recompilation (friction.F_c above friction.F_s) leaves the solver's
  caches as they were: the trajectory after it is the one without the attempt;
* with earlyReturnAllowed (and eventModeUsed) the FMI 3.0 plant gives the FMI 2.0 plant's x at
  every communication point of an open-loop drive, from startTime 0 and from other start times.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from feeddrive.fmu import FMUError, Plant
from feeddrive.fmu3 import set_values

H = 1e-3  # s, communication step
VERSIONS = ("2.0", "3.0")


@pytest.fixture(params=VERSIONS, ids=["fmi2", "fmi3"])
def path(request, fmu2_path: Path, fmu3_path: Path) -> Path:
    return fmu2_path if request.param == "2.0" else fmu3_path


# ------------------------------------------------------------------ refused calls change nothing


def test_refused_tunable_set_changes_nothing(path: Path) -> None:
    """friction.F_c above friction.F_s at 0.05 s is refused (fmi2Error / fmi3Error) and the
    trajectory on to 0.15 s is the one without the attempt, to the bit (clearing the solver's
    caches at the refusal would move x by 1.6e-13 m)."""

    def run(attempt: bool) -> np.ndarray:
        p = Plant({}, path=path)
        p.start({"u": 1.5})
        xs = []
        for k in range(150):
            if attempt and k == 50:
                with pytest.raises(FMUError):
                    p.set({"friction.F_c": 30.0})
                assert "friction.F_c = 30 exceeds friction.F_s" in p.messages[-1]
            p.set({"u": 1.5 * math.sin(2 * math.pi * 8 * k * H)})
            p.do_step(k * H, H)
            xs.append(p.get(["x"])["x"])
        p.close()
        return np.array(xs)

    np.testing.assert_array_equal(run(True), run(False))


@pytest.mark.parametrize("t0", [0.0, 1.0, 0.3])
def test_early_return_bit_identical_to_fmi2(fmu2_path: Path, fmu3_path: Path, t0: float) -> None:
    """Open-loop drive u = 1.2 V sin(2 pi 3 t) over 0.6 s in steps of 1 ms from startTime t0:
    the FMI 3.0 plant with early return (and event mode) gives the FMI 2.0 plant's x at every
    communication point to the bit (the step after an early return goes on from the integrator's
    tau; going on from lastSuccessfulTime - t0, t0 + tau rounded, moves x by up to 1e-13 m from
    t0 = 1 s)."""
    n = 600

    def u_of(t: float) -> float:
        return 1.2 * math.sin(2 * math.pi * 3 * (t - t0))

    p = Plant({}, path=fmu2_path)
    p.start({"u": u_of(t0)}, t0=t0)
    x2 = [p.get(["x"])["x"]]
    for k in range(n):
        t = t0 + k * H
        p.set({"u": u_of(t)})
        p.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=(t0 + (k + 1) * H) - t)
        x2.append(p.get(["x"])["x"])
    p.close()
    md = read_model_description(str(fmu3_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    for em in (False, True):
        f = FMU3Slave(
            guid=md.guid,
            unzipDirectory=extract(str(fmu3_path)),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="er",
        )
        f.instantiate(eventModeUsed=em, earlyReturnAllowed=True)
        set_values(f, md, {"u": u_of(t0)})
        f.enterInitializationMode(tolerance=1e-6, startTime=t0)
        f.exitInitializationMode()
        if em:
            f.updateDiscreteStates()
            f.enterStepMode()
        x3, n_early = [f.getFloat64([vr["x"]])[0]], 0
        for k in range(n):
            t, t_end = t0 + k * H, t0 + (k + 1) * H
            f.setFloat64([vr["u"]], [u_of(t)])
            while True:
                need, _, early, t_last = f.doStep(t, t_end - t)
                if need:
                    f.enterEventMode()
                    f.updateDiscreteStates()
                    f.enterStepMode()
                if not early:
                    break
                n_early, t = n_early + 1, t_last
            x3.append(f.getFloat64([vr["x"]])[0])
        f.terminate()
        f.freeInstance()
        dx = float(np.max(np.abs(np.array(x3) - np.array(x2))))
        print(
            f"t0 = {t0} s, event mode {em}: {n_early} early returns, max |dx| vs FMI 2.0 = {dx:.3g} m"
        )
        assert n_early > 10 and dx == 0.0

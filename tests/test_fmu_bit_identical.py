"""A refused call changes nothing, to the bit (both builds of the plant, co-simulation):

* a tunable set refused at recompilation (friction.F_c above friction.F_s) leaves the solver's
  caches as they were: the trajectory after it is the one without the attempt;
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from feeddrive.fmu import Plant

H = 1e-3                      # s, communication step
VERSIONS = ("2.0", "3.0")


@pytest.fixture(params=VERSIONS, ids=["fmi2", "fmi3"])
def path(request, fmu2_path: Path, fmu3_path: Path) -> Path:
    return fmu2_path if request.param == "2.0" else fmu3_path


# ------------------------------------------------------------------ refused calls change nothing

def test_refused_tunable_set_changes_nothing(path: Path) -> None:
    """friction.F_c above friction.F_s at 0.05 s is refused (fmi2Error / fmi3Error) and the
    trajectory on to 0.15 s is the one without the attempt, to the bit (it differed by
    1.6e-13 m: the refusal cleared the solver's caches)."""
    def run(attempt: bool) -> np.ndarray:
        p = Plant({}, path=path)
        p.start({"u": 1.5})
        xs = []
        for k in range(150):
            if attempt and k == 50:
                with pytest.raises(Exception):
                    p.set({"friction.F_c": 30.0})
                assert "friction.F_c = 30 exceeds friction.F_s" in p.messages[-1]
            p.set({"u": 1.5 * math.sin(2 * math.pi * 8 * k * H)})
            p.do_step(k * H, H)
            xs.append(p.get(["x"])["x"])
        p.close()
        return np.array(xs)
    np.testing.assert_array_equal(run(True), run(False))

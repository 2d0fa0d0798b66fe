"""What co-simulation keeps from one sample to the next changes no result (both builds of the
plant): the maps and the Stribeck level of the step's end point, the event update after a
per-sample step whose end indicators all tested positive (the current-loop sample alone), and an
output read that leaves the derivatives uncomputed.

An FMU-state round trip after every step drops all of these (a restored instance starts with
none), so the drive with round trips takes every check and evaluation afresh: x, v, the friction
force, the current and the stick/slip counts agree with the plain drive to the bit, and
der(friction.F) (the plain drive's from the step's own level, the restored one's from libm's
pow/exp) within 1e-9 N/s.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from feeddrive.fmu import Plant

EXACT = ["x", "v", "F_friction", "i", "stats.n_stick", "stats.n_slip", "stats.n_state_events"]
DER = [f"der(friction.F[{j}])" for j in range(1, 6)]


def _drive(path: Path, h: float, round_trip: bool) -> tuple[np.ndarray, np.ndarray]:
    """u = 1.5 V sin(2 pi 8 t) for 0.3 s (reversals: stick, break-away, slip), read after every step:
    first the outputs without a derivative (as a controller reads), then the derivatives."""
    p = Plant({}, path=path)
    p.start({"u": 0.0})
    exact, der = [], []
    for k in range(int(round(0.3 / h))):
        p.set({"u": 1.5 * math.sin(2 * math.pi * 8 * k * h)})
        p.do_step(k * h, h)
        if round_trip:
            s = p.get_state()
            p.set_state(s)
        e = p.get(EXACT)
        exact.append([e[n] for n in EXACT])
        d = p.get(DER)
        der.append([d[n] for n in DER])
    p.close()
    return np.array(exact), np.array(der)


def test_kept_values_change_nothing(path: Path) -> None:
    """One step per current-loop sample (h = Ts): to the bit."""
    plain, der_plain = _drive(path, 5e-4, False)
    fresh, der_fresh = _drive(path, 5e-4, True)
    assert plain[-1, EXACT.index("stats.n_slip")] >= 4  # the drive breaks away and sticks again
    np.testing.assert_array_equal(plain, fresh)
    assert np.max(np.abs(der_plain - der_fresh)) <= 1e-9
    assert np.max(np.abs(der_plain)) > 1.0  # the derivatives are not all ~0


def test_kept_values_inside_a_step(path: Path) -> None:
    """Two samples per step (h = 2 Ts: the event update inside fmi2DoStep follows a per-sample step):
    the same switches at the same samples; x within 1e-12 m (a round trip between steps of 2 Ts
    moves x by 2e-13 m by itself: the restored step does not start from the identical solver
    history)."""
    plain, _ = _drive(path, 1e-3, False)
    fresh, _ = _drive(path, 1e-3, True)
    counts = [EXACT.index(n) for n in ("stats.n_stick", "stats.n_slip", "stats.n_state_events")]
    assert plain[-1, EXACT.index("stats.n_slip")] >= 4
    np.testing.assert_array_equal(plain[:, counts], fresh[:, counts])
    assert np.max(np.abs(plain[:, 0] - fresh[:, 0])) <= 1e-12


@pytest.fixture(params=["2.0", "3.0"], ids=["fmi2", "fmi3"])
def path(request, fmu2_path: Path, fmu3_path: Path) -> Path:
    return fmu2_path if request.param == "2.0" else fmu3_path

"""Physical plausibility of a measured run: positions, speeds, accelerations and currents a
feed drive can have, so that a run in the wrong units is refused before any work.

A recording is in SI.  The commonest mistakes are positions in mm (or encoder counts, or
um) and currents in mA; the loader cannot see them (every value is a finite number), and
the tools then answer with nonsense (a 5 kN residual, a matrix that is not positive
definite).  Each rule below is a bound no feed drive reaches, far from any real recording,
and each is crossed by a factor of 1000 when the unit is wrong:

- **position** within the model's stroke widened by ``STROKE_MARGIN`` strokes on each side
  (0 .. 0.3 m gives -3 .. 3.3 m).  Room for a scale whose zero is not the stroke's end and
  for a longer machine than the model's; a recording in mm of any motion away from the
  first 3 mm of the stroke leaves it.
- **speed** (position difference over ``WINDOW_S``) at most ``V_MAX`` = 20 m/s: the fastest
  linear-motor axes reach 5-10 m/s, feed drives and ball screws 0.1-2 m/s (EMPS 0.13 m/s,
  the paper's runs 0.1 m/s).  In mm, any motion faster than 20 mm/s leaves it.
- **acceleration** (second difference over ``WINDOW_S``) at most ``A_MAX`` = 2000 m/s^2
  (200 g; linear-motor stages reach 10-50 g).  The difference over 10 ms averages
  quantisation steps, encoder glitches and ringing: one 1 um glitch reads 0.01 m/s^2.
- **current** at most ``I_MAX`` = 1000 A and the amplifier reference ``u`` at most
  ``U_MAX`` = 1000 V: servo amplifiers of feed drives give up to a few hundred A peak and
  take a +-10 V reference; a current in mA of any run above 1 A leaves it.

The one line names the file, the column, the value, the rule and the likely unit mistake
(the factor of 1000 that would bring the run inside the rule).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .data import DataError, Run
from .paper import STROKE

#: Margin around the stroke, in strokes on each side.
STROKE_MARGIN = 10.0
#: Largest plausible speed [m/s].
V_MAX = 20.0
#: Largest plausible acceleration [m/s^2].
A_MAX = 2000.0
#: Largest plausible motor current [A] and amplifier reference [V].
I_MAX = 1000.0
U_MAX = 1000.0
#: Span of the differences that estimate speed and acceleration [s].
WINDOW_S = 0.01


def _path(run: Run) -> Path:
    return run.path if run.path is not None else Path(run.name or "run")


def _unit_guess(value: float, limit: float, names: tuple[str, ...]) -> str:
    """The first of ``names`` (units 1e3, 1e6, ... times too small) that brings ``value``
    within ``limit``."""
    for k, unit in enumerate(names, 1):
        if abs(value) / 10.0 ** (3 * k) <= limit:
            return unit
    return names[-1]


def _window(run: Run) -> int:
    Ts = float(np.median(np.diff(run.time)))
    return int(min(max(1, round(WINDOW_S / Ts)), max(1, (run.n - 1) // 2)))


def check_units(run: Run, stroke: tuple[float, float] = STROKE) -> None:
    """Refuse a run whose positions, speeds, accelerations or currents no feed drive has
    (see the module docstring); ``stroke``: the model's ``stroke.x_min``, ``stroke.x_max``
    [m].  Raises :class:`DataError` naming the file, the line, the column and the likely
    unit mistake."""
    path = _path(run)
    lo, hi = float(min(stroke)), float(max(stroke))
    span = max(hi - lo, 1e-3)
    x = np.asarray(run.x, dtype=float)
    x_lo, x_hi = lo - STROKE_MARGIN * span, hi + STROKE_MARGIN * span
    out = np.flatnonzero((x < x_lo) | (x > x_hi))
    if out.size:
        k = int(out[np.argmax(np.abs(x[out]))])
        unit = _unit_guess(
            max(abs(x[k] - lo), abs(x[k] - hi)), (STROKE_MARGIN + 1) * span, ("mm", "um", "nm")
        )
        raise DataError(
            path,
            k + 2,
            "x",
            f"position {x[k]:g} m is far outside the model's stroke "
            f"{lo:g} .. {hi:g} m (allowed {x_lo:g} .. {x_hi:g} m): positions in {unit}? "
            "the recording format (docs/data-format.md) wants metres",
        )
    n = _window(run)
    dt = run.time[n:] - run.time[:-n]
    v = (x[n:] - x[:-n]) / dt
    k = int(np.argmax(np.abs(v)))
    if abs(v[k]) > V_MAX:
        unit = _unit_guess(v[k], V_MAX, ("mm", "um", "nm"))
        raise DataError(
            path,
            k + 2,
            "x",
            f"speed {abs(v[k]):.4g} m/s between lines {k + 2} and "
            f"{k + n + 2} is beyond {V_MAX:g} m/s (no feed drive moves that fast): "
            f"positions in {unit}? the recording format (docs/data-format.md) wants metres",
        )
    if run.n > 2 * n:
        t = np.asarray(run.time, dtype=float)
        h1, h2 = t[n:-n] - t[: -2 * n], t[2 * n :] - t[n:-n]
        a = 2.0 * ((x[2 * n :] - x[n:-n]) / h2 - (x[n:-n] - x[: -2 * n]) / h1) / (h1 + h2)
        k = int(np.argmax(np.abs(a)))
        if abs(a[k]) > A_MAX:
            unit = _unit_guess(a[k], A_MAX, ("mm", "um", "nm"))
            raise DataError(
                path,
                k + n + 2,
                "x",
                f"acceleration {abs(a[k]):.4g} m/s^2 around line "
                f"{k + n + 2} is beyond {A_MAX:g} m/s^2 (no feed drive accelerates "
                f"that hard): positions in {unit}? the recording format (docs/data-format.md) wants metres",
            )
    for name, limit, units, si in (
        ("i", I_MAX, ("mA", "uA"), "amperes"),
        ("u", U_MAX, ("mV", "uV"), "volts"),
    ):
        arr = getattr(run, name)
        if arr is None:
            continue
        k = int(np.argmax(np.abs(arr)))
        if abs(arr[k]) > limit:
            unit = _unit_guess(arr[k], limit, units)
            what = "current" if name == "i" else "amplifier reference"
            raise DataError(
                path,
                k + 2,
                name,
                f"{what} {arr[k]:g} is beyond +-{limit:g} "
                f"{'A' if name == 'i' else 'V'} (no feed-drive amplifier gives that): "
                f"{name} in {unit}? the recording format (docs/data-format.md) wants {si}",
            )

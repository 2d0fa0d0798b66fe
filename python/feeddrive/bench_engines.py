"""`make bench` rows of the co-simulation engines: the 6 s Sec. 3 loop with the controller FMU
at h = Ts (the system with one sample of computation delay, which the Jacobi engines' handover
is), each beside the engine's own floor, the same engine stepping a trivial pair of FMUs with
the same steps and the same call (:mod:`feeddrive.systems.floor`).  The floor is what the
engine spends per macro step whatever the FMUs do; the loop beyond it is ours (the plant's
integrator, the controller's law, the transfer of the connected values).

- libcosim on the SSP package: its fixed step on the calling thread (``numWorkerThreads="0"``
  in the SSD, the only form in which libcosim 0.11 takes a thread count).
- libcosim on the OSP structure: its default worker pool (the OSP format names no count).
- fmpy's container FMU under ``simulate_fmu``: extraction, instantiation and fmpy's Python
  loop (one ``doStep`` and one ``getReal`` per step) are the floor.
- Ecos (``ecospy``): ``step_until``; it walks every variable of every model twice per step
  (``apply_sets``), so its floor grows with the FMUs' variable count: the pair's two
  controller FMUs declare 2 x 441, the loop's plant and controller 192 + 441, and the loop
  runs below the pair's floor.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path

from .systems import run_container, sec3_system, write_all
from .systems.ecos import time_ecos
from .systems.engines import time_libcosim_osp, time_libcosim_ssp
from .systems.floor import (
    time_container_pair,
    time_ecos_pair,
    time_libcosim_pair,
    time_libcosim_pair_ssp,
)

Row = tuple[str, str, str]


def _best(measure: Callable[[], float], repeats: int) -> float:
    """Best wall [s] of ``repeats`` calls; NaN when the engine is not installed."""
    try:
        return min(measure() for _ in range(repeats))
    except ImportError:
        return float("nan")


def engine_row(what: str, wall: float, floor: float, wall_python: float, n: int) -> Row:
    """One engine: our figure, the engine's floor beside it, the loop beyond the floor, and
    the target (1/3 of the Python-controller run) met, or what stops it."""
    target = wall_python / 3
    if wall != wall:
        return (what, "not measured (engine not installed: pip install 'python[test]')", "")
    cell = (
        f"{wall * 1e3:.0f} ms ({wall / wall_python:.2f} x the Python-controller run, "
        f"{wall / n * 1e6:.1f} us per step)"
    )
    if floor == floor:
        cell += f"; the engine's floor {floor * 1e3:.0f} ms ({floor / n * 1e6:.1f} us per step), "
        cell += (
            f"ours beyond it {(wall - floor) * 1e3:.0f} ms"
            if wall > floor
            else "the loop at or below it (nothing of ours measurable)"
        )
    goal = f"<= {target * 1e3:.0f} ms (1/3)"
    if wall <= target:
        verdict = "met"
    elif floor == floor and floor > target:
        verdict = f"missed: the engine's floor alone is {floor * 1e3:.0f} ms"
    elif floor == floor:
        verdict = (
            f"missed: the floor leaves {(target - floor) * 1e3:.0f} ms to the FMUs, "
            f"the loop takes {(wall - floor) * 1e3:.0f} ms beyond it"
        )
    else:
        verdict = "missed"
    return (what, cell, f"{goal}: {verdict}")


def engine_rows(wall_python: float, repeats: int = 5) -> list[Row]:
    """The four engine rows (libcosim SSP and OSP, the container FMU, Ecos) and a header."""
    s = sec3_system(delay=1)
    with tempfile.TemporaryDirectory() as tmp_:
        tmp = Path(tmp_)
        files = write_all(s, tmp / "loop")
        pairs = [
            (
                "  libcosim, SSP package, fixed step on the calling thread (numWorkerThreads 0)",
                lambda: time_libcosim_ssp(files["ssp"], s.stop_time),
                lambda: time_libcosim_pair_ssp(tmp / "pair_ssp", s.n, s.Ts),
            ),
            (
                "  libcosim, OSP structure (its default worker pool: the format names no count)",
                lambda: time_libcosim_osp(files["osp"].parent, s.stop_time),
                lambda: time_libcosim_pair(tmp / "pair_osp", s.n, s.Ts),
            ),
            (
                "  fmpy container FMU under simulate_fmu (ctrl.delay 1)",
                lambda: float(run_container(files["container"], s.n, s.Ts)["wall"]),
                lambda: time_container_pair(tmp / "pair_container", s.n, s.Ts),
            ),
            (
                "  Ecos, step_until",
                lambda: time_ecos(s),
                lambda: time_ecos_pair(s.n, s.Ts),
            ),
        ]
        rows: list[Row] = [
            (
                f"6 s closed loop (delay 1) in co-simulation engines at h = Ts, best of {repeats}; "
                "floor: the same engine on a trivial pair of FMUs (two gains), same steps",
                "",
                "",
            )
        ]
        for what, loop, pair in pairs:
            rows.append(
                engine_row(what, _best(loop, repeats), _best(pair, repeats), wall_python, s.n)
            )
    return rows

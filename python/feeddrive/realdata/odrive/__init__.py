"""Position-spectrum analysis of the measured ODrive cogging maps and slow runs (rotary BLDC).

Data (``DIR/realdata/odrive-cogging``, ``--shared DIR``): holding-current maps Iq(x) [A] over one revolution
(8192 encoder counts) and slow runs (time [s], position [counts], Iq [A]).  As in Sec. 2.3 of
the paper: full-revolution line spectrum; a rectangular-window DSTFT along the revolution
(``scipy.signal.ShortTimeFFT``) whose tracks are compared with the same transform of the
constant line model, so that window leakage is not mistaken for variation; the crosstalk line
(drops without the neighbouring motor, ``iso_16``); repeatability; friction from forward minus
reverse maps; slow runs: Iq against the map at the run's position, velocity ripple.

The modules, in the order of the analysis: :mod:`.recordings` (the data set, loaded
and checked), :mod:`.spectrum` (full-revolution lines), :mod:`.along_revolution` (the DSTFT
along the revolution), :mod:`.trials` (repeated maps), :mod:`.forward_reverse` (friction),
:mod:`.slow_runs`, :mod:`.findings` (:func:`analyse`) and :mod:`.text` (the report).
"""

from .along_revolution import (
    N_WINDOW_POSITIONS,
    PERIODIC_TOL,
    WINDOW_COUNTS,
    LineTrack,
    PositionSpectrum,
    Stationarity,
    position_stft,
    stationarity,
)
from .findings import N_TRACKED, OdriveFindings, analyse, slow_summary
from .forward_reverse import FrictionFindings, friction
from .recordings import (
    COUNTS_PER_REV,
    FORWARD_16,
    ISOLATED_MAP,
    MAP_FOLDER,
    REFERENCE_MAP,
    REPEAT_TRIALS,
    REVERSE_16,
    SLOW_FOLDERS,
    CoggingMap,
    SlowRun,
    load_map,
    load_maps,
    load_slow_run,
    map_grid,
)
from .slow_runs import RESAMPLE_S, SETTLE_S, SlowRunFindings, slow_run, steady_part, velocity
from .spectrum import (
    LINE_FLOOR,
    N_LINES,
    Line,
    family,
    line_orders,
    revolution_spectrum,
    synthesise,
    top_lines,
)
from .text import findings_text
from .trials import TrialComparison, best_shift, compare_trial

__all__ = [
    "COUNTS_PER_REV",
    "MAP_FOLDER",
    "SLOW_FOLDERS",
    "REFERENCE_MAP",
    "ISOLATED_MAP",
    "REPEAT_TRIALS",
    "FORWARD_16",
    "REVERSE_16",
    "N_LINES",
    "N_TRACKED",
    "LINE_FLOOR",
    "WINDOW_COUNTS",
    "N_WINDOW_POSITIONS",
    "PERIODIC_TOL",
    "SETTLE_S",
    "RESAMPLE_S",
    "CoggingMap",
    "SlowRun",
    "map_grid",
    "load_map",
    "load_maps",
    "load_slow_run",
    "Line",
    "revolution_spectrum",
    "top_lines",
    "line_orders",
    "synthesise",
    "family",
    "PositionSpectrum",
    "position_stft",
    "LineTrack",
    "Stationarity",
    "stationarity",
    "TrialComparison",
    "compare_trial",
    "FrictionFindings",
    "friction",
    "SlowRunFindings",
    "steady_part",
    "velocity",
    "slow_run",
    "best_shift",
    "OdriveFindings",
    "analyse",
    "slow_summary",
    "findings_text",
]

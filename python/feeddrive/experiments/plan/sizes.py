"""The numbers that size the plan's runs: speeds, lengths, levels and periods of each run
kind, and the least of each that ``identify`` needs."""

from __future__ import annotations

from ...paper import MAGNET_PITCH_MM, MM

PITCH = MAGNET_PITCH_MM * MM  #: magnet pitch [m]
#: shortest stroke [m] the loaded constant-speed runs must share for the maps (Eqs. 6-7):
#: two magnet pitches (``identify``'s ``min_map_span``)
MAP_SPAN = 2 * PITCH
#: speed of the constant-speed runs for the maps [m/s] (Eq. 3 cancels friction symmetric in
#: v, so the speed is free: 10 mm/s crosses 0.3 m in 30 s)
MAP_SPEED = 10e-3
#: the Stribeck runs' candidate speeds are the campaign's (constant_speed.STRIBECK_SPEEDS)
MIN_STRIBECK_SPEEDS = 6  #: Eq. 12's fit needs >= 6 speeds (both directions each)
STRIBECK_CRUISE = 60.0  #: cruise time aimed at [s], ...
STRIBECK_MAX_LENGTH = 0.24  #: ... within one pitch .. this length [m]
MIN_CRUISE = (1.0, 3e-3)  #: a speed needs a cruise of >= 1 s and >= 3 mm to count
RAMP_ACCEL = 0.5  #: acceleration of the constant-speed ramps [m/s^2] (capped by a_max)
DWELL = 0.5  #: rest before and after each constant-speed move [s]
SPEED_TOL = 0.1  #: relative distance within which two speeds are the same
PRBS_AMPLITUDE = 0.3  #: PRBS level +- [V] added to the controller's output
PRBS_ORDER, PRBS_PERIODS, PRBS_SETTLE = 11, 4, 0.1
FORCE_MARGIN = 2e-3  #: the open-loop run stops this close to a stroke end [m]
FORCE_PERIOD = 0.2  #: square-wave period aimed at [s]
#: travel between the open-loop run's reversals [m]: ``identify``'s mass step leaves out
#: 1 mm after each reversal and every sample slower than 10 mm/s
MASS_TRAVEL = 4e-3
FORCE_DURATION = 2.0  #: length of the square wave [s]
FORCE_FRICTION_FACTOR = 2.0  #: the open-loop force must reach this multiple of F_s
VAR_SPEED = (1e-3, 20e-3)  #: speed range of the variable-speed run [m/s], period below
VAR_PERIOD = 0.5
VAR_MIN_TOP = 5e-3  #: its top speed must reach this [m/s] (S(v) must change)
PREROLLING_PERIOD, PREROLLING_PERIODS = 4.0, 3.0
PREROLLING_SPARE = 10e-6  #: the small amplitude keeps this from Delta_N-1 and Delta_N [m]

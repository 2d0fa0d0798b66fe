"""Position-spectrum analysis of the measured ODrive cogging maps and slow runs (rotary BLDC).

Data (``DIR/realdata/odrive-cogging``, ``--shared DIR``): holding-current maps Iq(x) [A] over one revolution
(8192 encoder counts) and slow runs (time [s], position [counts], Iq [A]).  As in Sec. 2.3 of
the paper: full-revolution line spectrum; a rectangular-window DSTFT along the revolution
(``scipy.signal.ShortTimeFFT``) whose tracks are compared with the same transform of the
constant line model, so that window leakage is not mistaken for variation; the crosstalk line
(drops without the neighbouring motor, ``iso_16``); repeatability; friction from forward minus
reverse maps; slow runs: Iq against the map at the run's position, velocity ripple.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import optimize, signal

from ..inputs import open_input

COUNTS_PER_REV = 8192
MAP_FOLDER = "coggingmap_0"
SLOW_FOLDERS = ("slow2", "slow2_slower")
REFERENCE_MAP = "a_16"  # forward map whose lines the README quotes
ISOLATED_MAP = "iso_16"  # forward map with the neighbouring motor moved away
REPEAT_TRIALS = ("b_16", "d_16", "c_16")
FORWARD_16 = ("a_16", "b_16", "c_16", "d_16")
REVERSE_16 = ("e_16r", "rev_16")
N_LINES = 5  # lines reported (the README quotes five)
N_TRACKED = 6  # lines tracked along the revolution (adds 84/rev = lcm(12, 14))
LINE_FLOOR = 10.0  # a line: amplitude >= LINE_FLOOR x median amplitude of all orders;
# in a_16 this keeps only multiples of 7 or 12 (0.031 A floor)
WINDOW_COUNTS = COUNTS_PER_REV // 2  # shortest window separating 12/rev from 14/rev (1/W = 2/rev)
N_WINDOW_POSITIONS = 64
PERIODIC_TOL = 0.25  # max |DSTFT - constant-line DSTFT| / line amplitude for "periodic";
# the repeatable sweeps a, b, c, d, e stay <= 0.14 on all tracked lines
SETTLE_S = 0.5  # slow runs: time dropped after the start transient's minimum
RESAMPLE_S = 1e-3  # uniform grid for the Iq-lag filter (samples are ~2.3 ms apart)

_MAP_NAME = re.compile(
    r"^cogging_measure_final_(?P<trial>[a-z]+)_(?P<step>\d+)(?P<r>r?)(?P<interp>_interp)?\.npy$"
)


# ----------------------------------------------------------------------------- loading
@dataclass(frozen=True)
class CoggingMap:
    """One measured holding-current map: Iq [A] at the measured encoder counts."""

    name: str
    step: int
    reverse: bool
    counts: np.ndarray
    current: np.ndarray


@dataclass(frozen=True)
class SlowRun:
    """One slow velocity-controlled run, sampled at non-uniform times."""

    name: str
    time: np.ndarray
    position: np.ndarray
    current: np.ndarray


def map_grid(step: int, reverse: bool) -> np.ndarray:
    """Encoder counts measured by a sweep with ``step``; a reverse sweep visits 8191, 8191-step, ..."""
    if step <= 0 or COUNTS_PER_REV % step:
        raise ValueError(f"step {step} does not divide {COUNTS_PER_REV} counts")
    first = (COUNTS_PER_REV - 1) % step if reverse else 0
    return np.arange(first, COUNTS_PER_REV, step)


def _load_npy(path: Path) -> np.ndarray:
    """The array of a ``.npy`` regular file (a FIFO or a device is refused, see
    :func:`feeddrive.inputs.open_input`); ValueError naming the file when it is no array."""
    with open_input(path, encoding=None) as f:
        try:
            data = np.load(f, allow_pickle=False)
        except EOFError:
            raise ValueError(f"{path}: empty or cut short: not a .npy array") from None
    if not isinstance(data, np.ndarray):
        raise ValueError(f"{path}: not a .npy array")
    return data


def load_map(path: str | Path) -> CoggingMap:
    """Load ``cogging_measure_final_<trial>_<step>[r].npy``; keep only the measured entries."""
    path = Path(path)
    m = _MAP_NAME.match(path.name)
    if m is None:
        raise ValueError(f"{path}: name is not cogging_measure_final_<trial>_<step>[r].npy")
    if m["interp"]:
        raise ValueError(f"{path}: an interpolated (filled-in) map, not a measurement")
    data = _load_npy(path)
    if data.shape != (COUNTS_PER_REV,) or data.dtype.kind != "f":
        raise ValueError(
            f"{path}: expected float array of shape ({COUNTS_PER_REV},), "
            f"got {data.dtype} {data.shape}"
        )
    if (bad := np.flatnonzero(~np.isfinite(data))).size:
        raise ValueError(f"{path}: non-finite current at count {bad[0]}")
    step, reverse = int(m["step"]), bool(m["r"]) or m["trial"] == "rev"
    grid = map_grid(step, reverse)
    stray = np.flatnonzero(np.isin(np.arange(COUNTS_PER_REV), grid, invert=True) & (data != 0))
    if stray.size:
        raise ValueError(
            f"{path}: {stray.size} non-zero entries off the {step}-count grid "
            f"(first at count {stray[0]}); the step in the name does not fit"
        )
    unmeasured = np.flatnonzero(data[grid] == 0)
    if unmeasured.size > grid.size // 100:
        raise ValueError(
            f"{path}: {unmeasured.size} of {grid.size} grid entries are 0 "
            f"(first at count {grid[unmeasured[0]]}): sweep incomplete"
        )
    name = path.name.removeprefix("cogging_measure_final_").removesuffix(".npy")
    return CoggingMap(name, step, reverse, grid, data[grid].copy())


def load_maps(folder: str | Path) -> dict[str, CoggingMap]:
    """All measured maps (``*_interp`` skipped) in ``folder/coggingmap_0``, keyed by e.g. ``a_16``."""
    d = Path(folder) / MAP_FOLDER
    if not d.is_dir():
        raise FileNotFoundError(f"{d}: cogging-map folder not found")
    maps = [
        load_map(p)
        for p in sorted(d.glob("cogging_measure_final_*.npy"))
        if not p.name.endswith("_interp.npy")
    ]
    return {m.name: m for m in maps}


def load_slow_run(path: str | Path) -> SlowRun:
    """Load a slow run: float array (3, N), rows time [s], position [counts], Iq [A]."""
    path = Path(path)
    data = _load_npy(path)
    if data.ndim != 2 or data.shape[0] != 3 or data.shape[1] < 100 or data.dtype.kind != "f":
        raise ValueError(
            f"{path}: expected float array of shape (3, N>=100), got {data.dtype} {data.shape}"
        )
    for row, what in enumerate(("time", "position", "current")):
        if (bad := np.flatnonzero(~np.isfinite(data[row]))).size:
            raise ValueError(f"{path}: non-finite {what} at sample {bad[0]}")
    if (back := np.flatnonzero(np.diff(data[0]) <= 0)).size:
        raise ValueError(f"{path}: time not increasing at sample {back[0] + 1}")
    return SlowRun(f"{path.parent.name}/{path.stem}", *(data[i].copy() for i in range(3)))


# ----------------------------------------------------------------------------- spectra
@dataclass(frozen=True)
class Line:
    """Spectral line: I(x) contains amplitude*cos(2 pi order x / 8192 + phase)."""

    order: int
    amplitude: float
    phase_deg: float


def revolution_spectrum(m: CoggingMap) -> np.ndarray:
    """Complex amplitudes c_k, k = 0..n/2, with I(x) = Re sum_k c_k exp(2j pi k x / 8192).

    The phase is referred to count 0 whatever the grid offset (reverse sweeps start at 15).
    """
    n = m.current.size
    c = np.fft.rfft(m.current) / n
    c[1:] *= 2.0
    if n % 2 == 0:
        c[-1] /= 2.0
    k = np.arange(c.size)
    return c * np.exp(-2j * np.pi * k * m.counts[0] / COUNTS_PER_REV)


def top_lines(spec: np.ndarray, count: int = N_LINES) -> tuple[Line, ...]:
    """The ``count`` largest lines (order >= 1), largest first."""
    orders = np.argsort(np.abs(spec[1:]))[::-1][:count] + 1
    return tuple(_line(spec, int(k)) for k in orders)


def _line(spec: np.ndarray, k: int) -> Line:
    return Line(k, float(abs(spec[k])), float(np.degrees(np.angle(spec[k]))))


def line_orders(spec: np.ndarray) -> np.ndarray:
    """Orders whose amplitude is >= LINE_FLOOR x the median amplitude (robust noise floor)."""
    amp = np.abs(spec[1:])
    return np.flatnonzero(amp >= LINE_FLOOR * np.median(amp)) + 1


def synthesise(spec: np.ndarray, orders: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Constant line model: mean plus the given orders of ``spec``, evaluated at ``counts``."""
    ph = 2j * np.pi * np.outer(counts, orders) / COUNTS_PER_REV
    return spec[0].real + (np.exp(ph) @ spec[orders]).real


def family(order: int, n_orders: int) -> np.ndarray:
    """Odd multiples of ``order`` below ``n_orders`` (a field shifted by half its period flips them)."""
    return np.arange(order, n_orders, 2 * order)


# ----------------------------------------------------------------------------- DSTFT
@dataclass(frozen=True)
class PositionSpectrum:
    """Short-time spectrum along the revolution: ``amplitude[q, j]`` is the complex amplitude of
    order q in the window centred at ``centres[j]`` [counts], demodulated so that a line of
    constant amplitude and phase gives the same value at every centre."""

    centres: np.ndarray
    orders: np.ndarray
    amplitude: np.ndarray


def position_stft(
    values: np.ndarray, counts: np.ndarray, window_counts: int = WINDOW_COUNTS
) -> PositionSpectrum:
    """Rectangular-window DSTFT of a map sampled on a uniform grid over one revolution.

    The map is periodic, so the windows wrap around the revolution (the data are tiled).
    """
    n = values.size
    step = COUNTS_PER_REV // n
    if counts.size != n or n * step != COUNTS_PER_REV or np.any(np.diff(counts) != step):
        raise ValueError(
            f"map of {n} points on counts {counts[:2]}... is not a uniform revolution grid"
        )
    width = window_counts // step
    sft = signal.ShortTimeFFT(np.ones(width), hop=max(n // N_WINDOW_POSITIONS, 1), fs=n, mfft=n)
    x = np.tile(values, 3)
    s = sft.stft(x)
    centre = np.rint(sft.t(x.size) * n).astype(int)  # t is in revolutions
    keep = (centre >= n) & (centre < 2 * n)
    centres = counts[0] + step * (centre[keep] - n)
    q = np.rint(sft.f).astype(int)
    scale = np.where(q == 0, 1.0, 2.0)[:, None] / width
    demod = np.exp(-2j * np.pi * np.outer(q, centres) / COUNTS_PER_REV)
    return PositionSpectrum(centres, q, s[:, keep] * scale * demod)


@dataclass(frozen=True)
class LineTrack:
    """One line along the revolution: DSTFT magnitude range, the range the constant line model
    gives through the same window (leakage), and the largest departure from that model
    relative to the full-revolution amplitude."""

    order: int
    amplitude: float
    dstft_range: tuple[float, float]
    model_range: tuple[float, float]
    deviation: float

    @property
    def periodic(self) -> bool:
        return self.deviation <= PERIODIC_TOL


@dataclass(frozen=True)
class Stationarity:
    """Periodic / not periodic along the revolution for one map (window: half a revolution)."""

    map_name: str
    tracks: tuple[LineTrack, ...]
    local_mean_range: tuple[float, float]  # zero-frequency term of the DSTFT [A]
    local_mean_drift: float  # its peak-to-peak not reproduced by the line model [A]
    residual_rms: float  # rms of map minus constant line model [A]


def stationarity(m: CoggingMap, lines: np.ndarray, orders: tuple[int, ...]) -> Stationarity:
    """Track ``orders`` and the zero-frequency term of map ``m`` along the revolution.

    The constant line model holds the orders ``lines`` (the reference map's lines) with this
    map's own amplitudes and phases; it is passed through the same window, so its leakage is
    not mistaken for variation.  A line whose amplitude or phase wanders along the revolution
    spreads into neighbouring orders (sidebands) that the model does not hold.
    """
    spec = revolution_spectrum(m)
    model = synthesise(spec, lines, m.counts)
    meas, mod = position_stft(m.current, m.counts), position_stft(model, m.counts)
    tracks = []
    for q in orders:
        a, b = meas.amplitude[q], mod.amplitude[q]
        tracks.append(
            LineTrack(
                int(q),
                float(abs(spec[q])),
                _range(np.abs(a)),
                _range(np.abs(b)),
                float(np.max(np.abs(a - b)) / abs(spec[q])),
            )
        )
    dc = meas.amplitude[0].real
    return Stationarity(
        m.name,
        tuple(tracks),
        _range(dc),
        float(np.ptp(dc - mod.amplitude[0].real)),
        float(np.std(m.current - model)),
    )


def _range(v: np.ndarray) -> tuple[float, float]:
    return float(np.min(v)), float(np.max(v))


# ----------------------------------------------------------------------------- trials, friction
@dataclass(frozen=True)
class TrialComparison:
    """A repeated forward map against the reference map."""

    name: str
    correlation: float  # as measured
    correlation_half_turn: float  # trial rolled by 4096 counts
    rms_difference: float  # after the better of the two alignments [A]
    crosstalk: Line  # the crosstalk line of this trial (phase vs count 0)
    odd_coherence: float  # +1: odd non-crosstalk orders as in the reference; -1: half-turn shift


def compare_trial(ref: CoggingMap, m: CoggingMap, crosstalk_order: int) -> TrialComparison:
    """Correlate ``m`` with ``ref`` as measured and shifted by half a turn; test which fits the
    odd orders that are not crosstalk (a half-turn shift flips every odd order)."""
    if not np.array_equal(ref.counts, m.counts):
        raise ValueError(f"{m.name}: grid differs from {ref.name}")
    half = np.roll(m.current, m.current.size // 2)
    r0, r1 = np.corrcoef(ref.current, m.current)[0, 1], np.corrcoef(ref.current, half)[0, 1]
    d = ref.current - (m.current if r0 >= r1 else half)
    sr, sm = revolution_spectrum(ref), revolution_spectrum(m)
    k = np.array([j for j in range(1, sr.size - 1, 2) if j % crosstalk_order])
    coh = np.sum((sm[k] * np.conj(sr[k])).real) / np.sum(np.abs(sr[k]) ** 2)
    return TrialComparison(
        m.name,
        float(r0),
        float(r1),
        float(np.std(d - d.mean())),
        _line(sm, crosstalk_order),
        float(coh),
    )


@dataclass(frozen=True)
class FrictionFindings:
    """Forward minus reverse holding current (= 2 x friction / Kt)."""

    forward: str  # matched pair: same crosstalk line in both maps
    reverse: str
    mean_difference: float  # [A]
    pair_means: tuple[float, float, float]  # min, mean, max over all forward x reverse pairs [A]
    difference_std: float  # position-dependent part of the matched pair [A]
    difference_lines: tuple[Line, ...]
    offset_counts: float  # fitted direction-dependent position offset (fwd - rev) [counts]
    offset_r2: float  # share of the difference variance it explains
    residual_std: float  # what is left [A]
    noise_std: float  # white point-to-point noise of the difference, from the
    # orders above 1/4 of the grid rate (no lines there) [A]


def friction(maps: dict[str, CoggingMap], crosstalk_order: int) -> FrictionFindings:
    """Forward/reverse difference; the matched pair has the closest crosstalk line, so the
    neighbour-dependent 7/rev part cancels and what remains is friction and hysteresis."""
    spec = {k: revolution_spectrum(maps[k]) for k in FORWARD_16 + REVERSE_16}
    means = [
        maps[f].current.mean() - maps[r].current.mean() for f in FORWARD_16 for r in REVERSE_16
    ]
    fwd, rev = min(
        ((f, r) for f in FORWARD_16 for r in REVERSE_16),
        key=lambda p: abs(spec[p[0]][crosstalk_order] - spec[p[1]][crosstalk_order]),
    )
    f, r = maps[fwd], maps[rev]
    r_on_f = np.interp(f.counts, r.counts, r.current, period=COUNTS_PER_REV)
    d = f.current - r_on_f
    # direction-dependent rest position: I_f(x) - I_r(x) ~ D + s dI/dx (spectral derivative)
    mean_map = np.fft.rfft(0.5 * (f.current + r_on_f))
    k = np.arange(mean_map.size)
    slope = np.fft.irfft(mean_map * 2j * np.pi * k / COUNTS_PER_REV, f.current.size)
    coef, *_ = np.linalg.lstsq(np.column_stack([np.ones_like(d), slope]), d, rcond=None)
    res = d - coef[0] - coef[1] * slope
    dspec = np.fft.rfft(d) / d.size
    dspec[1:] *= 2.0
    hi = np.abs(dspec[dspec.size // 2 : -1])
    return FrictionFindings(
        fwd,
        rev,
        float(d.mean()),
        (float(min(means)), float(np.mean(means)), float(max(means))),
        float(d.std()),
        top_lines(dspec, 4),
        float(coef[1]),
        float(1.0 - res.var() / d.var()),
        float(res.std()),
        float(np.sqrt(np.sum(hi**2))),
    )


# ----------------------------------------------------------------------------- slow runs
@dataclass(frozen=True)
class SlowRunFindings:
    """One slow run (steady part): speed, velocity ripple and Iq against the static map."""

    name: str
    speed: float  # mean velocity [rev/s]
    velocity_std: float  # std of velocity [counts/s]
    r_static: float  # corr(Iq, map at the run's position)
    lag_s: float  # first-order lag of Iq behind map(position(t)) that fits best
    r_lagged: float  # corr(Iq, lagged map)
    r_lagged_no_crosstalk: float  # same with the crosstalk family removed from the map


def steady_part(run: SlowRun) -> np.ndarray:
    """Mask of the steady ramp: drop the start (some runs first swing back from the previous
    run's end, through a minimum) up to SETTLE_S after the minimum of the first quarter."""
    return run.time >= run.time[np.argmin(run.position[: run.time.size // 4])] + SETTLE_S


def velocity(time: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Velocity [counts/s]: second-order differences on the non-uniform time stamps."""
    return np.gradient(position, time)


def _lag_correlation(
    t: np.ndarray, pos: np.ndarray, cur: np.ndarray, m: CoggingMap, values: np.ndarray, tau: float
) -> float:
    tu = np.arange(t[0], t[-1], RESAMPLE_S)
    mu = np.interp(np.interp(tu, t, pos) % COUNTS_PER_REV, m.counts, values, period=COUNTS_PER_REV)
    num, den, _ = signal.cont2discrete(
        (np.array([1.0]), np.array([tau, 1.0])), RESAMPLE_S, method="zoh"
    )
    num = np.ravel(num)
    y, _ = signal.lfilter(num, den, mu, zi=signal.lfilter_zi(num, den) * mu[0])
    return float(np.corrcoef(cur, np.interp(t, tu, y))[0, 1])


def slow_run(run: SlowRun, m: CoggingMap, crosstalk_order: int) -> SlowRunFindings:
    """Analyse one run against map ``m`` (forward map, same encoder frame)."""
    keep = steady_part(run)
    t, pos, cur = run.time[keep], run.position[keep], run.current[keep]
    v = velocity(t, pos)
    static = np.interp(pos % COUNTS_PER_REV, m.counts, m.current, period=COUNTS_PER_REV)
    fit = optimize.minimize_scalar(
        lambda tau: -_lag_correlation(t, pos, cur, m, m.current, tau),
        bounds=(1e-3, 0.5),
        method="bounded",
        options={"xatol": 1e-3},
    )
    spec = revolution_spectrum(m)
    spec[family(crosstalk_order, spec.size)] = 0.0
    clean = synthesise(spec, np.arange(1, spec.size), m.counts)
    return SlowRunFindings(
        run.name,
        float((pos[-1] - pos[0]) / (t[-1] - t[0]) / COUNTS_PER_REV),
        float(v.std()),
        float(np.corrcoef(cur, static)[0, 1]),
        float(fit.x),
        float(-fit.fun),
        _lag_correlation(t, pos, cur, m, clean, float(fit.x)),
    )


# ----------------------------------------------------------------------------- findings
def best_shift(ref: CoggingMap, m: CoggingMap) -> tuple[int, float]:
    """Circular shift [counts] that best aligns ``m`` with ``ref`` (same grid), and its correlation."""
    a, b = ref.current - ref.current.mean(), m.current - m.current.mean()
    xc = np.fft.irfft(np.fft.rfft(a) * np.conj(np.fft.rfft(b)), a.size)  # xc[s] = a . roll(b, s)
    s = int(np.argmax(xc))
    return s * m.step, float(xc[s] / np.sqrt(a @ a * (b @ b)))


@dataclass(frozen=True)
class OdriveFindings:
    """Everything :func:`analyse` finds (counts, A, s)."""

    reference: str
    lines: tuple[Line, ...]  # top lines of the reference forward map
    grid_check: float  # max rel. change of those amplitudes over steps 4..32
    isolated_lines: tuple[Line, ...]  # the same orders in iso_16
    isolated_shift: tuple[int, float]  # iso_16 registration vs reference [counts], correlation
    crosstalk_order: int  # the line that drops most without the neighbour
    stationarity: tuple[Stationarity, ...]
    trials: tuple[TrialComparison, ...]
    friction: FrictionFindings
    slow: tuple[SlowRunFindings, ...]


def analyse(folder: str | Path) -> OdriveFindings:
    """Run the whole analysis on the data folder (``.../realdata/odrive-cogging``)."""
    folder = Path(folder)
    maps = load_maps(folder)
    for need in (REFERENCE_MAP, ISOLATED_MAP, *REPEAT_TRIALS, *REVERSE_16):
        if need not in maps:
            raise FileNotFoundError(f"{folder / MAP_FOLDER}: map {need} missing")
    ref = maps[REFERENCE_MAP]
    spec = revolution_spectrum(ref)
    lines = top_lines(spec)
    orders = tuple(ln.order for ln in lines)
    others = [
        revolution_spectrum(mm)
        for k, mm in maps.items()
        if k.startswith("a_") and k != REFERENCE_MAP
    ]
    grid = max(abs(abs(s[q]) / abs(spec[q]) - 1.0) for s in others for q in orders)
    iso_spec = revolution_spectrum(maps[ISOLATED_MAP])
    iso = tuple(_line(iso_spec, q) for q in orders)
    xt = min(orders, key=lambda q: abs(iso_spec[q]) / abs(spec[q]))
    tracked = tuple(ln.order for ln in top_lines(spec, N_TRACKED))
    stat = tuple(
        stationarity(maps[k], line_orders(spec), tracked)
        for k in (REFERENCE_MAP, *REPEAT_TRIALS, ISOLATED_MAP, *REVERSE_16)
    )
    trials = tuple(compare_trial(ref, maps[k], xt) for k in REPEAT_TRIALS)
    runs = []
    for sub in SLOW_FOLDERS:
        d = folder / sub
        if not d.is_dir():
            raise FileNotFoundError(f"{d}: slow-run folder not found")
        runs += [slow_run(load_slow_run(p), ref, xt) for p in sorted(d.glob("*.npy"))]
    return OdriveFindings(
        ref.name,
        lines,
        float(grid),
        iso,
        best_shift(ref, maps[ISOLATED_MAP]),
        int(xt),
        stat,
        trials,
        friction(maps, xt),
        tuple(runs),
    )


def slow_summary(f: OdriveFindings) -> dict[str, dict[str, float]]:
    """Slow-run numbers averaged over trials, keyed ``"<folder>/<kind>"`` (kind: nocomp, comp,
    crosstalk_nocomp, crosstalk_comp)."""
    groups: dict[str, list[SlowRunFindings]] = {}
    for s in f.slow:
        groups.setdefault(s.name.rsplit("_", 1)[0], []).append(s)
    fields = ("speed", "velocity_std", "r_static", "lag_s", "r_lagged", "r_lagged_no_crosstalk")
    return {
        k: {a: float(np.mean([getattr(s, a) for s in v])) for a in fields} | {"n": len(v)}
        for k, v in groups.items()
    }


def findings_text(f: OdriveFindings) -> str:
    """Short human-readable report of :func:`analyse`'s findings."""
    q, fr = f.crosstalk_order, f.friction
    amp = {ln.order: ln.amplitude for ln in f.lines}
    iso = {ln.order: ln.amplitude for ln in f.isolated_lines}
    stay = 100 * max(abs(iso[k] / a - 1) for k, a in amp.items() if k != q)
    clean = [s for s in f.stationarity if all(t.periodic for t in s.tracks)]
    odd = [s for s in f.stationarity if s not in clean]
    out = [
        f"ODrive BLDC (rotary), 8192 counts/rev, holding current Iq [A]; forward map {f.reference}",
        f"Summary: periodic (constant along the revolution in {', '.join(s.map_name for s in clean)}): "
        + ", ".join(f"{t.order}/rev" for t in f.stationarity[0].tracks)
        + f"; their zero-frequency term does not drift (<= {max(s.local_mean_drift for s in clean):.3f}"
        f" A p-p). Not periodic: the {q}/rev line is crosstalk (changes with the neighbour); "
        + "; ".join(
            f"{s.map_name}: lines "
            + ",".join(str(t.order) for t in s.tracks if not t.periodic)
            + f" wander, local mean drifts {s.local_mean_drift:.2f} A p-p"
            for s in odd
        )
        + ".",
        "Periodic lines, full revolution [order/rev: A]: "
        + ", ".join(f"{ln.order}: {ln.amplitude:.3f}" for ln in f.lines)
        + f" (grids 4..32 counts agree within {100 * f.grid_check:.1f} %)",
        f"Crosstalk: without the neighbouring motor (iso_16) the {q}/rev line drops "
        f"{amp[q]:.2f} -> {iso[q]:.2f} A, the others change by {stay:.0f} % at most; across "
        "sessions the same line reads "
        + ", ".join(f"{t.name} {t.crosstalk.amplitude:.2f} A" for t in f.trials)
        + f": an external force that a slot-harmonic cogging model would wrongly absorb "
        f"(iso_16 is also registered {f.isolated_shift[0]} counts away, r = {f.isolated_shift[1]:.2f})",
    ]
    out.append(
        "Along the revolution (DSTFT, rectangular window 1/2 rev, compared with the constant "
        f"lines through the same window; periodic if deviation <= {PERIODIC_TOL}):"
    )
    for s in f.stationarity:
        non = [t for t in s.tracks if not t.periodic]
        out.append(
            f"  {s.map_name:7s} deviation "
            + " ".join(f"{t.order}:{t.deviation:.2f}" for t in s.tracks)
            + (" -> NOT periodic " + ",".join(str(t.order) for t in non) if non else " -> periodic")
            + f"; local mean {s.local_mean_range[0]:+.2f}..{s.local_mean_range[1]:+.2f} A of which "
            f"{s.local_mean_drift:.3f} A p-p is not line leakage; residual rms {s.residual_rms:.3f} A"
        )
    for t in f.trials:
        out.append(
            f"Repeat {t.name}: r = {t.correlation:+.3f} as measured, {t.correlation_half_turn:+.3f} "
            f"shifted 4096 counts; rms diff {t.rms_difference:.3f} A; odd non-{q}k orders "
            f"coherence {t.odd_coherence:+.2f} (-1 would mean a true half-turn shift)"
        )
    out.append(
        f"Friction: forward - reverse = {fr.mean_difference:.3f} A ({fr.forward} - {fr.reverse}, "
        f"matched {q}/rev line; all 8 pairs {fr.pair_means[0]:.2f}..{fr.pair_means[2]:.2f}, "
        f"mean {fr.pair_means[1]:.2f}) = 2 F/Kt. Position-dependent part std "
        f"{fr.difference_std:.3f} A, lines "
        + ", ".join(f"{ln.order}: {ln.amplitude:.3f}" for ln in fr.difference_lines)
        + f"; {100 * fr.offset_r2:.0f} % of its variance is a {fr.offset_counts:.1f}-count "
        f"rest-position offset between directions; the rest {fr.residual_std:.3f} A vs white "
        f"point noise {fr.noise_std:.3f} A (from orders > 128/rev): "
        + (
            "no position-dependent friction above the noise"
            if fr.residual_std < 1.2 * fr.noise_std
            else "a position-dependent remainder above the noise"
        )
    )
    summ = slow_summary(f)
    for sub in SLOW_FOLDERS:
        n, c = summ[f"{sub}/nocomp"], summ[f"{sub}/comp"]
        out.append(
            f"Slow runs {sub} ({n['speed']:.3f} rev/s): velocity ripple std (np.gradient on "
            f"the non-uniform time stamps) {n['velocity_std']:.0f} -> {c['velocity_std']:.0f} "
            f"counts/s with the map as feed-forward (gap shrinks "
            f"x{n['velocity_std'] / c['velocity_std']:.1f})"
        )
        for k in ("nocomp", "comp", "crosstalk_nocomp", "crosstalk_comp"):
            if (row := summ.get(f"{sub}/{k}")) is not None:
                out.append(
                    f"  {k:16s} ({row['n']} run(s)): r(Iq, map at position) {row['r_static']:.3f}; "
                    f"behind a {1000 * row['lag_s']:.0f} ms first-order lag {row['r_lagged']:.3f}; "
                    f"map without odd {q}k/rev {row['r_lagged_no_crosstalk']:.3f}"
                    + (f"; velocity std {row['velocity_std']:.0f}" if "crosstalk" in k else "")
                )
    lags = [summ[f"{sub}/{k}"]["lag_s"] for sub in SLOW_FOLDERS for k in ("nocomp", "comp")]
    if max(lags) < 1.25 * min(lags):
        out.append(
            f"The Iq lag is the same at both speeds ({1000 * min(lags):.0f}..{1000 * max(lags):.0f}"
            " ms): a filter on the reported Iq, so the lower r(Iq, map) at the higher speed is "
            "that filter, not motor dynamics."
        )
    return "\n".join(out)

"""Discrete short-time Fourier transform of a position map (Sec. 2.3.2, Figs. 6-9).

X(n, k) = sum_m y[m] w[n - m] exp(-j 2 pi k m / N) with a rectangular window of 750 samples
(75 mm at L_s = 0.1 mm) and N = 750, computed with scipy.signal.ShortTimeFFT.

Normalisation and phase convention (stated because the paper's figures plot |X|/N):

- ``spectrum`` holds X(n, k) / N.  Bin k corresponds to the wavelength lambda_k = N L_s / k.
- The phase is referred to the stroke origin x = 0 (the origin of Eqs. 6-7), not to the
  window: a stationary term a cos(2 pi x / lambda) + b sin(2 pi x / lambda) whose wavelength
  falls on bin k gives X/N = (a - j b) / 2 at every window position, i.e. magnitude
  |a + j b| / 2 (one side band) and phase atan2(-b, a), both constant along the stroke.
- Bin 0 is the window mean (the "zero-frequency term"), real.

Only windows lying entirely inside the data are returned (no zero padding).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import ShortTimeFFT

WINDOW = 750  #: window length and FFT length N of the paper (samples)
STEP = 1e-4  #: L_s, position sampling [m]


@dataclass
class DSTFT:
    """DSTFT of a uniformly sampled map."""

    positions: np.ndarray  #: window centres [m]
    wavelengths: np.ndarray  #: lambda_k = N L_s / k [m] (inf for k = 0)
    spectrum: np.ndarray  #: X(n, k) / N, shape (n_bins, n_positions), phase re x = 0
    N: int
    step: float

    @property
    def magnitude(self) -> np.ndarray:
        """|X| / N."""
        return np.abs(self.spectrum)

    def bin_of(self, wavelength: float, rel_tol: float = 0.02) -> int:
        """Index of the bin whose wavelength is ``wavelength`` [m] (within rel_tol)."""
        if wavelength == np.inf or wavelength <= 0:
            return 0
        k = int(round(self.N * self.step / wavelength))
        if (
            k < 1
            or k >= len(self.wavelengths)
            or abs(self.wavelengths[k] - wavelength) > rel_tol * wavelength
        ):
            raise ValueError(
                f"DSTFT: no bin at wavelength {wavelength:g} m "
                f"(N = {self.N}, step = {self.step:g} m)"
            )
        return k

    def component(self, wavelength: float) -> tuple[np.ndarray, np.ndarray]:
        """Magnitude |X|/N and unwrapped phase [rad] at ``wavelength`` vs position."""
        X = self.spectrum[self.bin_of(wavelength)]
        return np.abs(X), np.unwrap(np.angle(X))

    def components(
        self, wavelengths: tuple[float, ...] = (0.0375, 0.01875, 0.0125, 0.025)
    ) -> dict[float, tuple[np.ndarray, np.ndarray]]:
        """:meth:`component` for several wavelengths (default: the paper's 37.5, 18.75,
        12.5 mm and the 25 mm ripple term)."""
        return {lam: self.component(lam) for lam in wavelengths}

    def zero_frequency(self) -> np.ndarray:
        """The zero-frequency term X(n, 0)/N (the local mean over one window) vs position."""
        return self.spectrum[0].real

    def peaks(self, count: int = 3, min_wavelength: float = 0.0) -> np.ndarray:
        """Wavelengths [m] of the ``count`` largest bins (k >= 1) of the position-averaged |X|/N."""
        mean = self.magnitude[1:].mean(axis=1)
        lam = self.wavelengths[1:]
        mean = np.where(lam >= min_wavelength, mean, -np.inf)
        order = np.argsort(mean)[::-1][:count]
        return lam[order]


def dstft(
    y: np.ndarray,
    x0: float = 0.0,
    step: float = STEP,
    window: int = WINDOW,
    nfft: int | None = None,
    hop: int = 1,
) -> DSTFT:
    """DSTFT of samples y at positions x0 + n*step (rectangular window of ``window`` samples).

    Parameters
    ----------
    y : uniformly sampled map (e.g. F_cg or K_f on the 0.1 mm grid).
    x0 : position of y[0] [m]; the phase is referred to x = 0.
    step : sample spacing L_s [m].
    window : rectangular window length (750 in the paper).
    nfft : FFT length N (default = window).
    hop : window advance in samples.
    """
    y = np.asarray(y, dtype=float)
    N = int(window if nfft is None else nfft)
    if len(y) < window:
        raise ValueError(f"DSTFT: {len(y)} samples are fewer than the window of {window}")
    sft = ShortTimeFFT(
        np.ones(window),
        hop=hop,
        fs=1.0 / step,
        mfft=N,
        scale_to=None,
        phase_shift=0,
        fft_mode="onesided",
    )
    X = sft.stft(y)
    p_lo = sft.lower_border_end[1]
    p_hi = sft.upper_border_begin(len(y))[1]
    sl = slice(p_lo - sft.p_min, p_hi - sft.p_min)
    centres = x0 + sft.t(len(y))[sl]
    # ShortTimeFFT refers each slice's phase to its centre; refer it to x = 0 instead
    X = X[:, sl] / N * np.exp(-2j * np.pi * np.outer(sft.f, centres))
    k = np.arange(len(sft.f))
    with np.errstate(divide="ignore"):
        lam = np.where(k > 0, N * step / np.maximum(k, 1), np.inf)
    return DSTFT(positions=centres, wavelengths=lam, spectrum=X, N=N, step=step)

"""The sampled linear design model of the feed drive: current loop G(z) (Eq. 2) in series with
the ZOH-discretised double integrator K_f0/(m s^2).  Input u [V], output x [m].

State order of the design model (all at sample k)::

    [x, v, xi_1 .. xi_g, u[k-1] .. u[k-d]]

``xi`` is the controllable-canonical realisation (``scipy.signal.tf2ss``) of the proper part
G'(z) of G(z) = z^-d G'(z); ``d`` is the pure input delay beyond one sample (the leading zero
``current.b[j]`` less one).  For the paper's Eq. 2 (b0 = b1 = 0) d = 1 and G' is second order,
so the design model has 5 states.  The current i[k] is held between samples (it is a sampled
system), so the series connection is exact for the plant's linear part: the "e^{-sTs}" of the
continuous description is the delay already contained in G(z).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from scipy import signal

from ..physics import CurrentLoop


@dataclass(frozen=True)
class DesignModel:
    """Sampled design model u [V] -> x [m] (state order in the module docstring).

    Attributes
    ----------
    A, B, C, D : state-space matrices (n x n, n x 1, 1 x n, 1 x 1).
    Ts : sample time [s].
    n_dyn : number of dynamic states [x, v, xi] (estimated by an observer).
    n_delay : number of pure input-delay states u[k-1..k-d] (known to a controller).
    K_f0 : force constant used [N/A];  m : mass [kg];  G1 : current-loop DC gain [A/V].
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    Ts: float
    n_dyn: int
    n_delay: int
    K_f0: float
    m: float
    G1: float
    tf_num: np.ndarray
    tf_den: np.ndarray
    #: the controller's computation delay [samples] among the ``n_delay`` input delays
    delay: int = 0

    @property
    def n(self) -> int:
        """Total number of states."""
        return self.A.shape[0]

    @property
    def volts_per_newton(self) -> float:
        """u per unit motor force at DC, 1 / (K_f0 G(1)) [V/N]."""
        return 1.0 / (self.K_f0 * self.G1)

    @property
    def dlti(self) -> signal.StateSpace:
        """The model as a ``scipy.signal`` discrete state space (dt = Ts)."""
        return signal.StateSpace(self.A, self.B, self.C, self.D, dt=self.Ts)

    def markov(self, n: int) -> np.ndarray:
        """The first ``n`` Markov parameters h[0..n-1] (impulse response of u -> x)."""
        h = np.empty(n)
        h[0] = self.D[0, 0]
        Ak_B = self.B.copy()
        for k in range(1, n):
            h[k] = (self.C @ Ak_B)[0, 0]
            Ak_B = self.A @ Ak_B
        return h

    def tf(self) -> tuple[np.ndarray, np.ndarray]:
        """Exact transfer function u -> x, (num, den) in descending powers of z.

        num = (Ts^2/2)(K_f0/m)(z + 1) * B_G(z),  den = (z - 1)^2 * A_G(z): the ZOH double
        integrator times G(z) written in positive powers of z.
        """
        return self.tf_num.copy(), self.tf_den.copy()

    def freqresp(self, f: np.ndarray) -> np.ndarray:
        """Complex frequency response u -> x at frequencies ``f`` [Hz]."""
        return ss_freqresp(self.A, self.B, self.C, self.D, self.Ts, f)


def ss_freqresp(
    A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray, Ts: float, f: np.ndarray
) -> np.ndarray:
    """C (zI - A)^-1 B + D at z = exp(j 2 pi f Ts) for a SISO discrete system (vectorised)."""
    z = np.exp(1j * 2.0 * np.pi * np.asarray(f, dtype=float) * Ts)
    n = A.shape[0]
    M = z[:, None, None] * np.eye(n)[None] - A[None]
    X = np.linalg.solve(M, np.broadcast_to(B, (len(z),) + B.shape))
    return (C[None] @ X)[:, 0, 0] + D[0, 0]


def design_model(params: Mapping[str, float], delay: int = 0) -> DesignModel:
    """Build the sampled design model from FMU-named parameters (SI).

    Uses ``m``, ``Ts``, ``ripple.c[0]`` (K_f0) and ``current.a[1..5]``, ``current.b[0..5]``.
    The double integrator K_f0/(m s^2) from i to x is discretised with
    ``scipy.signal.cont2discrete`` (ZOH: i is held between samples).  ``delay`` (0 or 1)
    samples of computation delay are added to the input delays: u computed at t_k reaches
    the amplifier at t_k+delay.
    """
    if delay not in (0, 1):
        raise ValueError(f"design_model.py: delay = {delay!r}: allowed 0 or 1 sample")
    for key in ("m", "Ts", "ripple.c[0]"):
        if key not in params:
            raise KeyError(f"design_model.py: parameter {key!r} missing")
    m, Ts, K_f0 = float(params["m"]), float(params["Ts"]), float(params["ripple.c[0]"])
    if m <= 0 or Ts <= 0 or K_f0 <= 0:
        raise ValueError(
            f"design_model.py: need m > 0, Ts > 0, ripple.c[0] > 0 "
            f"(got m={m}, Ts={Ts}, ripple.c[0]={K_f0})"
        )
    loop = CurrentLoop.from_parameters(params)
    if not any(loop.b):
        raise ValueError("design_model.py: current.b[0..5] are all zero, G(z) = 0")
    num, den = loop.polynomials()
    G1 = float(num.sum() / den.sum())
    # mechanical part: i -> [x, v]
    Am, Bm, _, _, _ = signal.cont2discrete(
        (
            np.array([[0.0, 1.0], [0.0, 0.0]]),
            np.array([[0.0], [K_f0 / m]]),
            np.array([[1.0, 0.0]]),
            np.zeros((1, 1)),
        ),
        Ts,
        method="zoh",
    )
    # G(z) = z^-d0 B'(z^-1)/A(z^-1); keep one sample of it in G' (strictly proper) if d0 >= 1
    d0 = int(np.argmax(num != 0.0))
    d_g = max(d0 - 1, 0)
    num_g = num[d_g:]  # G' = z^-(d0-d_g) B'/A in powers of z^-1
    d = d_g + delay  # input delays: G's beyond G', the controller's
    L = max(len(num_g), len(den))
    num_g = np.pad(num_g, (0, L - len(num_g)))
    den_g = np.pad(den, (0, L - len(den)))  # same length -> descending powers of z
    if L > 1:
        Ag, Bg, Cg, Dg = signal.tf2ss(np.trim_zeros(num_g, "f"), den_g)
    else:
        Ag, Bg, Cg, Dg = (
            np.zeros((0, 0)),
            np.zeros((0, 1)),
            np.zeros((1, 0)),
            np.array([[num_g[0] / den_g[0]]]),
        )
    ng = Ag.shape[0]
    n_dyn = 2 + ng
    Ap = np.zeros((n_dyn, n_dyn))
    Ap[:2, :2] = Am
    Ap[:2, 2:] = Bm @ Cg
    Ap[2:, 2:] = Ag
    Bp = np.vstack([Bm @ Dg, Bg])  # input: u[k-d]
    n = n_dyn + d
    A = np.zeros((n, n))
    B = np.zeros((n, 1))
    A[:n_dyn, :n_dyn] = Ap
    if d == 0:
        B[:n_dyn] = Bp
    else:
        A[:n_dyn, n - 1 : n] = Bp  # u[k-d] is the last delay state
        B[n_dyn, 0] = 1.0
        for j in range(1, d):
            A[n_dyn + j, n_dyn + j - 1] = 1.0
    C = np.zeros((1, n))
    C[0, 0] = 1.0
    Lg = max(len(num), len(den))
    g_num = np.trim_zeros(np.pad(num, (0, Lg - len(num))), "f")
    g_den = np.pad(den, (0, Lg - len(den)))
    tf_num = np.convolve(0.5 * Ts**2 * K_f0 / m * np.array([1.0, 1.0]), g_num)
    tf_den = np.convolve(np.array([1.0, -2.0, 1.0] + [0.0] * delay), g_den)
    return DesignModel(
        A=A,
        B=B,
        C=C,
        D=np.zeros((1, 1)),
        Ts=Ts,
        n_dyn=n_dyn,
        n_delay=d,
        K_f0=K_f0,
        m=m,
        G1=G1,
        tf_num=tf_num,
        tf_den=tf_den,
        delay=delay,
    )


class SteppedController(Protocol):
    """What :func:`simulate_linear` calls of a controller."""

    def reset(self) -> None: ...

    def step(self, x_meas: float, k: int) -> float: ...


def simulate_linear(
    model: DesignModel,
    controller: SteppedController,
    n_steps: int,
    x0: float = 0.0,
    quantum: float | None = None,
    force: Callable[[int, float, float], float] | Sequence[float] | None = None,
) -> dict[str, np.ndarray]:
    """Run ``controller`` (``reset()``/``step(x_meas, k)``) in closed loop with the design model.

    Parameters
    ----------
    model : the plant (its linear design model).
    controller : object with ``reset()`` and ``step(x_meas, k) -> u``.
    n_steps : number of samples.
    x0 : initial position [m] (at rest).
    quantum : measurement resolution [m] (e.g. 1e-7); None = exact.
    force : a disturbance force [N] opposing the motion term (m a = K_f0 i - F), either an
        array F[k] held over sample k, or a callable F(k, x, v) evaluated at the sample.

    Returns
    -------
    dict with arrays ``x`` (true position at the samples), ``x_meas``, ``u``, ``v``.
    """
    A, B = model.A, model.B
    # a force held over the sample acts on the ZOH double integrator 1/(m s^2)
    _, Bm, *_ = signal.cont2discrete(
        (
            np.array([[0.0, 1.0], [0.0, 0.0]]),
            np.array([[0.0], [1.0 / model.m]]),
            np.eye(2),
            np.zeros((2, 1)),
        ),
        model.Ts,
        method="zoh",
    )
    Bf = np.zeros(model.n)
    Bf[:2] = -Bm[:, 0]
    X = np.zeros(model.n)
    X[0] = x0
    xs = np.empty(n_steps)
    xm = np.empty(n_steps)
    us = np.empty(n_steps)
    vs = np.empty(n_steps)
    controller.reset()
    for k in range(n_steps):
        xs[k], vs[k] = X[0], X[1]
        y = X[0] if quantum is None else quantum * np.floor(X[0] / quantum + 0.5)
        xm[k] = y
        u = controller.step(float(y), k)
        us[k] = u
        if force is None:
            F = 0.0
        elif callable(force):
            F = force(k, X[0], X[1])
        else:
            F = force[k]
        X = A @ X + B[:, 0] * u + Bf * F
    return {"x": xs, "x_meas": xm, "u": us, "v": vs}

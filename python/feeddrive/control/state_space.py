"""State feedback with integral action and a current estimator, by pole placement.

Design (on the sampled design model of :mod:`design_model`, states [x, v, xi, u-delays]):

- augmented model: integrator q[k+1] = q[k] + Ts (y[k] - r[k]);
- state feedback u = -K X - k_q q, K from ``scipy.signal.place_poles`` on the augmented model;
- current estimator (Franklin & Powell) for the dynamic states x_p = [x, v, xi]:
  x_hat = x_bar + L (y - C x_bar),  x_bar[k+1] = A_p x_hat + B_p u[k-d],
  error dynamics eig(A_p - L C A_p) placed with ``place_poles`` on (A_p^T, (C A_p)^T).
  The delay states u[k-1..k-d] are the controller's own past outputs, known exactly.

The reference r enters the integrator and the position feedback, u = -K_x (x_hat - r) - ...,
so the closed loop from reference to output is T(z) = B_P(z)(K_x (z - 1) + k_q Ts)/A_cl(z)
with the plant's zeros B_P(z) (see :meth:`StateSpaceController.closed_loop_tf`); the ZPETC
pre-filter (:mod:`zpetc`) makes it zero-phase.  The observer modes are not excited by the
reference (separation), so they do not appear in T(z).

Default poles (chosen for margins GM > 6 dB, PM > 30 deg and a friction-induced reversal
error of the paper's order, ~23 um in a Python simulation of the design model with the GMS
friction of Table 2/3): mechanical (x, v, q) pair at 20 Hz with damping 0.8 and a real pole
at 15 Hz; the current-loop poles and the delay pole stay where they are (0.702 +- 0.0316j,
0).  With Eq. 2 this gives force-equivalent gains Kp ~ 6.1e5 N/m, Kv ~ 6.5e3 N s/m,
Ki ~ 2.2e7 N/(m s) (a design of the paper's order: 6e5, 6.7e3, 2e7).  Observer: mechanical pair at
200 Hz with damping 0.7, current-loop states at z = 0.2 and 0.1.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from .design_model import DesignModel, design_model, ss_freqresp
from .feedforward import feedforward
from .lti_step import compile_step
from .margins import Margins, frequency_grid, loop_margins
from .zpetc import ZPETC

DEFAULT_MECH_HZ = 20.0
DEFAULT_MECH_ZETA = 0.8
DEFAULT_MECH_REAL_HZ = 15.0
DEFAULT_OBS_HZ = 200.0
DEFAULT_OBS_ZETA = 0.7
DEFAULT_OBS_CURRENT = (0.2, 0.1)
DEFAULT_U_LIMITS = (-10.0, 10.0)  #: amplifier reference range [V]


def s_to_z(s: ArrayLike, Ts: float) -> np.ndarray:
    """Map continuous poles s [rad/s] to z = exp(s Ts)."""
    return np.exp(np.asarray(s, dtype=complex) * Ts)


def z_to_hz_zeta(z: ArrayLike, Ts: float) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequency [Hz] and damping of discrete poles via s = ln(z)/Ts (z = 0: inf, 1)."""
    z = np.atleast_1d(np.asarray(z, dtype=complex))
    f = np.full(z.shape, np.inf)
    zeta = np.ones(z.shape)
    nz = np.abs(z) > 0
    s = np.log(z[nz]) / Ts
    w = np.abs(s)
    f[nz] = w / (2 * np.pi)
    zeta[nz] = np.where(w > 0, -s.real / np.where(w > 0, w, 1.0), 1.0)
    return f, zeta


def _pair_and_real(f_hz: float, zeta: float, f_real_hz: float) -> np.ndarray:
    w = 2 * np.pi * f_hz
    wd = w * np.sqrt(max(1.0 - zeta**2, 0.0))
    return np.array([-zeta * w + 1j * wd, -zeta * w - 1j * wd, -2 * np.pi * f_real_hz])


def _current_loop_poles(model: DesignModel) -> np.ndarray:
    Ag = model.A[2 : model.n_dyn, 2 : model.n_dyn]
    return np.linalg.eigvals(Ag) if Ag.size else np.zeros(0)


def _delay_poles(d: int) -> np.ndarray:
    # single input: place_poles needs distinct poles; d = 1 for Eq. 2
    return np.linspace(0.0, 0.02 * (d - 1), d) if d > 0 else np.zeros(0)


def default_poles(
    model: DesignModel,
    f_hz: float = DEFAULT_MECH_HZ,
    zeta: float = DEFAULT_MECH_ZETA,
    f_real_hz: float = DEFAULT_MECH_REAL_HZ,
) -> np.ndarray:
    """Closed-loop poles (z) for the augmented model [X, q] (n + 1 poles).

    Mechanical (x, v, q): a pair at ``f_hz`` with damping ``zeta`` and a real pole at
    ``f_real_hz``; current-loop and delay poles at their open-loop places.
    """
    mech = s_to_z(_pair_and_real(f_hz, zeta, f_real_hz), model.Ts)
    return np.concatenate((mech, _current_loop_poles(model), _delay_poles(model.n_delay)))


def default_observer_poles(
    model: DesignModel,
    f_hz: float = DEFAULT_OBS_HZ,
    zeta: float = DEFAULT_OBS_ZETA,
    current_poles: tuple[float, float] = DEFAULT_OBS_CURRENT,
) -> np.ndarray:
    """Estimator poles (z) for the dynamic states [x, v, xi] (``n_dyn`` poles).

    Mechanical pair at ``f_hz`` with damping ``zeta``; the current-loop states get real poles
    spread evenly over ``current_poles`` (fast: their estimate then follows the measured
    motion, which gains phase margin over leaving them at the open-loop poles).
    """
    mech = s_to_z(_pair_and_real(f_hz, zeta, f_hz)[:2], model.Ts)
    ng = model.n_dyn - 2
    cur = (
        np.linspace(current_poles[0], current_poles[1], ng)
        if ng > 1
        else np.full(ng, 0.5 * (current_poles[0] + current_poles[1]))
    )
    return np.concatenate((mech, cur))


def _place(A: np.ndarray, B: np.ndarray, poles: np.ndarray, what: str) -> np.ndarray:
    """``scipy.signal.place_poles`` with a check that eig(A - B K) are the requested poles."""
    n = A.shape[0]
    if len(poles) != n:
        raise ValueError(
            f"state_space.py: {what}: {len(poles)} poles given, the model has {n} states"
        )
    K = signal.place_poles(A, B, poles).gain_matrix
    got = np.sort_complex(np.linalg.eigvals(A - B @ K))
    want = np.sort_complex(np.asarray(poles, dtype=complex))
    err = float(np.max(np.abs(got - want)))
    if err > 1e-6:
        raise ValueError(f"state_space.py: {what}: pole placement inaccurate (max error {err:.2e})")
    return K


class StateSpaceController:
    """State feedback + integral action + current estimator, sampled at the model's Ts.

    Parameters
    ----------
    model : the design model (:func:`design_model.design_model` on nominal parameters).
    reference : x_ref[k] [m] sampled at Ts (held at its last value beyond the end).
    poles : closed-loop poles (z) of the augmented model [X, q] (``model.n + 1``);
        default :func:`default_poles`.
    observer_poles : estimator poles (z), ``model.n_dyn``; default :func:`default_observer_poles`.
    u_ff : feedforward voltage u_ff[k] added to the output (see :mod:`feedforward`); the
        estimator is driven by the applied voltage less u_ff.
    u_limits : output clamp [V].
    prefilter : "zpetc" (default) to track ``reference`` through a ZPETC pre-filter of the
        closed loop (``self.command`` is the filtered reference), or None to feed
        ``reference`` to the loop directly.
    zpetc_radius : oscillatory zeros of T(z) (Re z < 0) are cancelled by the ZPETC only if
        |z| is below this (see :class:`zpetc.ZPETC`).
    """

    def __init__(
        self,
        model: DesignModel,
        reference: ArrayLike,
        *,
        poles: Sequence[complex] | np.ndarray | None = None,
        observer_poles: Sequence[complex] | np.ndarray | None = None,
        u_ff: ArrayLike | None = None,
        u_limits: tuple[float, float] = DEFAULT_U_LIMITS,
        prefilter: str | None = "zpetc",
        zpetc_radius: float = 0.9,
    ) -> None:
        self.model = model
        self.Ts = model.Ts
        self.poles = np.asarray(default_poles(model) if poles is None else poles, dtype=complex)
        self.observer_poles = np.asarray(
            default_observer_poles(model) if observer_poles is None else observer_poles,
            dtype=complex,
        )
        if np.any(np.abs(self.poles) >= 1) or np.any(np.abs(self.observer_poles) >= 1):
            raise ValueError("state_space.py: requested poles must lie inside the unit circle")
        self.u_limits = (float(u_limits[0]), float(u_limits[1]))
        self._design()
        self._build_lti()
        self.prefilter = prefilter
        self.zpetc = None
        self.reference = np.asarray(reference, dtype=float).copy()
        if self.reference.ndim != 1 or self.reference.size == 0:
            raise ValueError("state_space.py: reference must be a non-empty 1-D array")
        if prefilter == "zpetc":
            self.zpetc = ZPETC.from_controller(self, radius=zpetc_radius)
            self.command = self.zpetc.filter(self.reference)
        elif prefilter is None:
            self.command = self.reference.copy()
        else:
            raise ValueError(
                f"state_space.py: prefilter must be 'zpetc' or None, got {prefilter!r}"
            )
        self.set_feedforward(u_ff)
        self.reset()

    @classmethod
    def from_params(
        cls,
        params: Mapping[str, float],
        reference: ArrayLike,
        feedforward_options: Any = None,
        v_ref: ArrayLike | None = None,
        a_ref: ArrayLike | None = None,
        **kw: Any,
    ) -> StateSpaceController:
        """Design model, feedforward and controller from one nominal parameter dict.

        ``feedforward_options``: None for no feedforward, else a
        :class:`feedforward.FeedforwardOptions`; ``kw`` go to the constructor.
        """
        model = design_model(params)
        u_ff = None
        if feedforward_options is not None:
            u_ff = feedforward(
                np.asarray(reference, dtype=float),
                model.Ts,
                params,
                feedforward_options,
                v_ref=v_ref,
                a_ref=a_ref,
            ).u
        return cls(model, reference, u_ff=u_ff, **kw)

    # ----------------------------------------------------------------- design
    def _design(self) -> None:
        md = self.model
        n, nd, Ts = md.n, md.n_dyn, md.Ts
        Aa = np.zeros((n + 1, n + 1))
        Aa[:n, :n] = md.A
        Aa[n, :n] = Ts * md.C[0]
        Aa[n, n] = 1.0
        Ba = np.vstack([md.B, [[0.0]]])
        Ka = _place(Aa, Ba, self.poles, "state feedback")[0]
        self.A_aug, self.B_aug = Aa, Ba
        self.K = Ka[:n].copy()  #: state-feedback gains on X [V per SI state unit]
        self.k_q = float(Ka[n])  #: integral gain [V / (m s)]
        Ap = md.A[:nd, :nd]
        Cp = md.C[:, :nd]
        if abs(np.linalg.det(Ap)) < 1e-12:
            raise ValueError(
                "state_space.py: current estimator needs a nonsingular A_p; G(z) "
                "has poles at z = 0 beyond a pure input delay (current.a/b)"
            )
        L = _place(Ap.T, (Cp @ Ap).T, self.observer_poles, "observer").T
        self.L = L[:, 0].copy()  #: current-estimator gain

    def _build_lti(self) -> None:
        md = self.model
        n, nd, d, Ts = md.n, md.n_dyn, md.n_delay, md.Ts
        Ap, Cp = md.A[:nd, :nd], md.C[0, :nd]
        Bp = md.A[:nd, n - 1] if d else md.B[:nd, 0]
        Kp, Kh = self.K[:nd], self.K[nd:]
        M = np.eye(nd) - np.outer(self.L, Cp)
        ns = nd + 1 + d
        Ac = np.zeros((ns, ns))
        By, Br, Bu, Cc = np.zeros(ns), np.zeros(ns), np.zeros(ns), np.zeros(ns)
        Ac[:nd, :nd] = Ap @ M
        By[:nd] = Ap @ self.L
        if d:
            Ac[:nd, ns - 1] = Bp
        else:
            Bu[:nd] = Bp
        Ac[nd, nd] = 1.0
        By[nd], Br[nd] = Ts, -Ts
        if d:
            Bu[nd + 1] = 1.0
            for j in range(1, d):
                Ac[nd + 1 + j, nd + j] = 1.0
        Cc[:nd] = -Kp @ M
        Cc[nd] = -self.k_q
        Cc[nd + 1 :] = -Kh
        Dy = float(-Kp @ self.L)
        Dr = float(self.K[0])  # position feedback acts on x_hat - r
        self.lti: dict[str, Any] = {
            "Ac": Ac,
            "By": By,
            "Br": Br,
            "Bu": Bu,
            "Cc": Cc,
            "Dy": Dy,
            "Dr": Dr,
        }
        self._fn = compile_step(Ac, By, Br, Bu, Cc, Dy, Dr, *self.u_limits)

    # -------------------------------------------------------------- analysis
    def closed_loop_tf(self) -> tuple[np.ndarray, np.ndarray]:
        """T(z) = y/r of the design closed loop: (num, den) in descending powers of z.

        State feedback keeps the plant's zeros B_P(z); an input added to u reaches y as
        B_P(z)(z - 1)/A_cl(z) (the integrator's pole becomes a zero), and the reference
        enters as K_x r + k_q Ts r/(z - 1), so T = B_P(z) (K_x (z - 1) + k_q Ts) / A_cl(z)
        with A_cl the characteristic polynomial of the designed closed loop.  T(1) = 1 by
        integral action; the numerator is scaled to make that exact despite round-off.
        With a computation delay (``model.delay``) the loop runs the sample at t_k on the
        measurement of t_k-1 and the reference of t_k: the design's extra z^-1 is not between
        r and x, T is multiplied by z.
        """
        num_p, _ = self.model.tf()
        num = np.convolve(num_p, [self.K[0], self.k_q * self.Ts - self.K[0]])
        num = np.convolve(num, [1.0] + [0.0] * self.model.delay)
        ev = np.linalg.eigvals(self.A_aug - self.B_aug @ self.K_aug[None, :])
        den = np.real(np.poly(ev))
        num = num * (np.real(np.prod(1.0 - ev)) / np.polyval(num, 1.0))
        return num, den

    @property
    def K_aug(self) -> np.ndarray:
        """[K, k_q]."""
        return np.concatenate((self.K, [self.k_q]))

    def closed_loop_matrix(self) -> np.ndarray:
        """State matrix of plant (design model) + controller as implemented (r = 0, no clamp)."""
        md, c = self.model, self.lti
        A, B, C = md.A, md.B, md.C
        top = np.hstack([A + c["Dy"] * B @ C, B @ c["Cc"][None, :]])
        bot = np.hstack(
            [np.outer(c["By"] + c["Bu"] * c["Dy"], C[0]), c["Ac"] + np.outer(c["Bu"], c["Cc"])]
        )
        return np.vstack([top, bot])

    def controller_freqresp(self, f: np.ndarray) -> np.ndarray:
        """Frequency response of the feedback law y -> u (r = 0, u_ff = 0)."""
        c = self.lti
        A = c["Ac"] + np.outer(c["Bu"], c["Cc"])
        B = (c["By"] + c["Bu"] * c["Dy"])[:, None]
        return ss_freqresp(A, B, c["Cc"][None, :], np.array([[c["Dy"]]]), self.Ts, f)

    def loop_freqresp(self, f: np.ndarray) -> np.ndarray:
        """Loop transfer function L = -C(z) P(z) broken at the plant input."""
        return -self.controller_freqresp(f) * self.model.freqresp(f)

    def margins(self) -> Margins:
        """Gain/phase/modulus margins of the loop (numerical, dense log grid to Nyquist)."""
        f = frequency_grid(self.Ts)
        return loop_margins(f, self.loop_freqresp(f))

    def report(self) -> dict[str, Any]:
        """Gains, closed-loop poles (z, Hz, damping) and stability margins."""
        md = self.model
        fn = md.K_f0 * md.G1  # N per V at DC

        def poles_table(p: np.ndarray) -> list[dict[str, Any]]:
            f, z = z_to_hz_zeta(p, self.Ts)
            return [
                {"z": complex(pi), "f_hz": float(fi), "zeta": float(zi)}
                for pi, fi, zi in zip(p, f, z, strict=True)
            ]

        return {
            "K": self.K.tolist(),
            "k_q": self.k_q,
            "L": self.L.tolist(),
            "force_equivalent": {
                "Kp_N_per_m": self.K[0] * fn,
                "Kv_Ns_per_m": self.K[1] * fn,
                "Ki_N_per_ms": self.k_q * fn,
            },
            "poles": poles_table(self.poles),
            "observer_poles": poles_table(self.observer_poles),
            "margins": self.margins().as_dict(),
            "zpetc_preview": None if self.zpetc is None else self.zpetc.preview,
        }

    def format_report(self) -> str:
        """The :meth:`report` as readable text."""
        r = self.report()
        fe, mg = r["force_equivalent"], r["margins"]
        lines = [
            "State-space controller (state feedback + integral + current estimator)",
            f"  K = {np.array2string(np.asarray(r['K']), precision=5)}  k_q = {r['k_q']:.5g}",
            f"  force-equivalent: Kp = {fe['Kp_N_per_m']:.4g} N/m, "
            f"Kv = {fe['Kv_Ns_per_m']:.4g} N s/m, Ki = {fe['Ki_N_per_ms']:.4g} N/(m s)",
            f"  L = {np.array2string(np.asarray(r['L']), precision=5)}",
        ]
        for key, title in (("poles", "closed-loop poles"), ("observer_poles", "observer poles")):
            lines.append(f"  {title}:")
            for p in r[key]:
                lines.append(
                    f"    z = {p['z'].real:+.6f}{p['z'].imag:+.6f}j   "
                    f"{p['f_hz']:8.2f} Hz  zeta = {p['zeta']:.3f}"
                )
        lines.append(
            f"  margins: GM = {mg['gain_margin_db']:.2f} dB at "
            f"{mg['gain_margin_hz']:.1f} Hz, lower GM = "
            f"{mg['lower_gain_margin_db']:.2f} dB at {mg['lower_gain_margin_hz']:.2f} Hz,"
            f" PM = {mg['phase_margin_deg']:.1f} deg at {mg['crossover_hz']:.2f} Hz, "
            f"min|1+L| = {mg['modulus_margin']:.3f}"
        )
        if r["zpetc_preview"] is not None:
            lines.append(f"  ZPETC preview: {r['zpetc_preview']} samples")
        return "\n".join(lines)

    # -------------------------------------------------------------- running
    def set_feedforward(self, u_ff: ArrayLike | None) -> None:
        """Set u_ff[k] [V] (None: no feedforward); zero beyond the end of the array."""
        self.u_ff = None if u_ff is None else np.asarray(u_ff, dtype=float).copy()
        self._uff = [] if self.u_ff is None else self.u_ff.tolist()
        self._n_ff = len(self._uff)

    def reset(self) -> None:
        """Zero the controller state; the estimate is initialised at the first measurement."""
        self._s = [0.0] * self.lti["Ac"].shape[0]
        self._r = self.command.tolist()
        self._n_r = len(self._r)
        self._r_last = self._r[-1]
        self._fresh = True

    def step(self, x_meas: float, k: int) -> float:
        """Controller output u [V] at sample k for the measured position ``x_meas`` [m]."""
        if self._fresh:
            self._s[0] = x_meas  # estimate starts at the measured position, at rest
            self._fresh = False
        r = self._r[k] if k < self._n_r else self._r_last
        uff = self._uff[k] if k < self._n_ff else 0.0
        return self._fn(self._s, x_meas, r, uff)

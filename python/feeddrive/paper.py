"""The paper's numbers (Villegas et al., 2014) and their one conversion to SI.

Tables 1-3 are printed for x in millimetres and velocities in mm/s; this module is the
only place where they are converted.  Everything else in the project (the FMU defaults in
``modelDescription.xml``, model files, controllers, identification) uses SI and FMU
parameter names such as ``friction.F_s`` or ``cogging.a[1]``.
"""

from __future__ import annotations

from .effects import EFFECTS, effect_ids, switchable

MM = 1e-3  #: metres per millimetre

#: Table 1 as printed (x in mm): polynomial c_k and Fourier a_k, b_k (k = 1..3, lambda = 37.5 mm).
TABLE1_MM = {
    "cogging": {
        "c": [-1.95, -0.046, 6.6e-4, -1.3e-6],
        "a": [14.1, -11.22, 13.04],
        "b": [-13.78, 0.1, 11.58],
    },
    "ripple": {"c": [69.88, 0.009, -3.53e-5], "a": [-1.34, -0.23, -0.56], "b": [0.54, 0.55, 1.26]},
}
MAGNET_PITCH_MM = 37.5
#: Table 2 as printed: F_s, F_c [N], V_s [mm/s], delta [-], sigma2 [N s/mm].
TABLE2 = {"F_s": 26.1, "F_c": 21.6, "V_s": 3.1, "delta": 0.6, "sigma2": 0.054}
#: Table 3 as printed: nu [-], k [N/mm].  Sum(nu) = 0.997 as printed.
TABLE3 = {"nu": [0.17, 0.13, 0.30, 0.017, 0.38], "k": [1152.07, 377.23, 215.33, 9.39, 87.66]}
MASS = 16.1  #: kg
#: Attraction parameter: printed "10.8 M/s"; the default is 1.08e4 N/s (docs/model.md says why).
C_DEFAULT = 1.08e4
C_LITERAL = 10.8
TS = 5e-4  #: s, current-loop and controller sample time
#: Eq. 2 as a difference equation i[k] = sum a_j i[k-j] + sum b_j u[k-j].
CURRENT_A = [1.404, -0.4938]
CURRENT_B = [0.0, 0.0, 0.057909, 0.057909 * 0.7461]  # b3 = b2 * 0.7461 exactly
STROKE = (0.0, 0.300)  #: m
N_HARMONICS = 8  #: Fourier slots per map in the FMU
N_ELEMENTS_MAX = 10  #: GMS element slots in the FMU

#: Every id of the effect catalogue, in catalogue order (from the registry :mod:`feeddrive.effects`).
EFFECT_IDS = effect_ids()
#: Effects that exist as FMU switches (``mass`` is always on: its value is fitted).
SWITCHABLE_EFFECTS = [e.id for e in switchable()]
#: Effects beyond the paper (the catalogue's "common effects of real drives" and the project's
#: own ``position_friction`` and ``compliance``): off in its model.
BEYOND_PAPER = tuple(e.id for e in EFFECTS if not e.in_paper)
PAPER_EFFECTS = {e.id: e.in_paper for e in switchable()}
#: Knot slots of the friction-level profile (effect position_friction).
N_PROFILE_KNOTS = 16
#: Compliance defaults (off): a 2 kg load on a 40 Hz spring, 5 % damping, encoder on the slide.
COMPLIANCE_DEFAULTS = {
    "compliance.m2": 2.0,
    "compliance.f": 40.0,
    "compliance.zeta": 0.05,
    "compliance.sensor_side": 0,
}


def nu_defaults() -> list[float]:
    """Table 3's nu with nu_N = 1 - sum(nu_i, i < N) (Eq. 18), as docs/model.md fixes."""
    nu = list(TABLE3["nu"][:-1])
    return nu + [round(1.0 - sum(nu), 12)]


def paper_parameters() -> dict[str, float | int | bool]:
    """All FMU parameters at the paper's values, in SI, keyed by FMU variable name."""
    p: dict[str, float | int | bool] = {"m": MASS, "Ts": TS}
    for j in range(1, 6):
        p[f"current.a[{j}]"] = CURRENT_A[j - 1] if j <= len(CURRENT_A) else 0.0
    for j in range(6):
        p[f"current.b[{j}]"] = CURRENT_B[j] if j < len(CURRENT_B) else 0.0
    for name in ("cogging", "ripple"):
        t = TABLE1_MM[name]
        for k, c in enumerate(t["c"]):
            p[f"{name}.c[{k}]"] = c / MM**k  # x in mm -> x in m
        for j in range(1, N_HARMONICS + 1):
            p[f"{name}.lambda[{j}]"] = MAGNET_PITCH_MM * MM / j
            p[f"{name}.a[{j}]"] = t["a"][j - 1] if j <= 3 else 0.0
            p[f"{name}.b[{j}]"] = t["b"][j - 1] if j <= 3 else 0.0
    p["friction.F_s"] = TABLE2["F_s"]
    p["friction.F_c"] = TABLE2["F_c"]
    p["friction.V_s"] = TABLE2["V_s"] * MM
    p["friction.delta"] = TABLE2["delta"]
    p["friction.sigma2"] = TABLE2["sigma2"] / MM
    p["friction.C"] = C_DEFAULT
    p["friction.N"] = len(TABLE3["nu"])
    nu = nu_defaults()
    for j in range(1, N_ELEMENTS_MAX + 1):
        p[f"friction.nu[{j}]"] = nu[j - 1] if j <= len(nu) else 0.0
        p[f"friction.k[{j}]"] = TABLE3["k"][j - 1] / MM if j <= len(nu) else 1.0e5
    p["offset.F"] = 0.0
    p["asymmetry.dF"] = 0.0
    p["asymmetry.dsigma2"] = 0.0
    p["stroke.x_min"], p["stroke.x_max"] = STROKE
    p.update(COMPLIANCE_DEFAULTS)
    for e in switchable():
        p[f"effects.{e.id}"] = e.in_paper
    p["friction_profile.x_start"], p["friction_profile.x_end"] = STROKE
    p["friction_profile.n"] = N_PROFILE_KNOTS
    for j in range(1, N_PROFILE_KNOTS + 1):
        p[f"friction_profile.c[{j}]"] = 0.0
    return p

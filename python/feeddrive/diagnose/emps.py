"""The EMPS benchmark's rigid baseline as a model file (shared/realdata/emps/README.md).

    F = M a + Fv v + Fc sgn(v) + offset,   F = gtau * u,   gtau = 35.15 N/V

(Janot, Gautier, Brunot 2019: M = 95.1 kg, Fv = 203.5 N s/m, Fc = 20.4 N, offset = -3.16 N,
IDIM-LS).  In the project's sign convention (m a = F - F_f - offset.F) the offset enters as
offset.F = -3.16 N.  A ball-screw drive: no cogging, no force ripple, no current measured
(ideal current source, the force is gtau * u); memoryless Coulomb + viscous friction (no
pre-rolling, no Stribeck drop: F_s = F_c), symmetric.
"""

from __future__ import annotations

from ..effects import emps_baseline
from ..model_file import ModelFile, paper_model

#: Drive gain of the EMPS data [N/V] (``gtau`` of the benchmark).
EMPS_FORCE_GAIN = 35.15


def emps_baseline_model() -> ModelFile:
    """The authors' IDIM-LS baseline as a model file (see module docstring)."""
    base = paper_model()
    effects = dict.fromkeys(base.effects, False)
    effects.update(dict.fromkeys(emps_baseline(), True))
    params = dict(base.parameters)
    # no linear-motor maps on a ball screw: clear them so that a candidate switching one on
    # starts from nothing (wavelengths only from the residual's spectrum)
    for k in params:
        if k.startswith(("cogging.c", "cogging.a", "cogging.b", "ripple.a", "ripple.b")) or k in (
            "ripple.c[1]",
            "ripple.c[2]",
        ):
            params[k] = 0.0
    params.update(
        {
            "m": 95.1,
            "friction.sigma2": 203.5,
            "friction.F_c": 20.4,
            "friction.F_s": 20.4,
            "offset.F": -3.16,
            "stroke.x_min": -0.01,
            "stroke.x_max": 0.3,
        }
    )
    return ModelFile(
        name="emps_baseline",
        effects=effects,
        parameters=params,
        description="EMPS rigid baseline (Janot et al. 2019, IDIM-LS): "
        "M 95.1 kg, Fv 203.5 N s/m, Fc 20.4 N, offset -3.16 N; "
        "force = 35.15 N/V * u (no current measured)",
    )

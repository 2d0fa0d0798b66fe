"""The result of an identification: every step's fit, the model file they make, the runs
used and, with a truth, the table of true versus identified parameters."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..data import Run
from ..model_file import ModelFile
from .attraction import AttractionFit
from .current_loop import CurrentLoopFit
from .mass import MassFit
from .position_friction import PositionFrictionFit
from .position_maps import PositionMapsFit
from .prerolling import PrerollingFit
from .stribeck import StribeckFit
from .truth_table import TruthRow, format_rows


@dataclass
class IdentificationResult:
    """Every step's fit, the model file they make, and (with a truth) the comparison."""

    model: ModelFile
    groups: dict[str, list[Run]]
    current_loop: CurrentLoopFit | None = None
    maps: PositionMapsFit | None = None
    stribeck: StribeckFit | None = None
    mass: MassFit | None = None
    attraction: AttractionFit | None = None
    prerolling: PrerollingFit | None = None
    position_friction: PositionFrictionFit | None = None
    #: step -> why it was skipped
    skipped: dict[str, str] = field(default_factory=dict)
    #: FMU parameters that kept the paper's value (not identified)
    defaulted: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)
    truth: ModelFile | None = None
    table: list[TruthRow] = field(default_factory=list)
    out_path: Path | None = None
    #: one line per run: the kind it was given and why
    placement: list[str] = field(default_factory=list)

    def text(self) -> str:
        """A plain-text account: runs used, each step's result, the truth table if any."""
        L = [
            f"identification from {sum(len(v) for v in self.groups.values())} runs: "
            + ", ".join(f"{k} {len(v)}" for k, v in self.groups.items())
        ]
        L += self.placement
        p = self.model.parameters
        if self.current_loop is not None:
            c = self.current_loop
            poles = zip(c.pole_hz, c.pole_zeta, strict=True)
            L.append(
                f"current loop: order {c.order}, delay {c.delay}, G(1) = {c.dc_gain:.4f} A/V, "
                f"poles {', '.join(f'{h:.0f} Hz/zeta {z:.2f}' for h, z in poles)}, "
                f"fit {c.fit_percent:.1f} %"
            )
        if self.maps is not None:
            m = self.maps
            L.append(
                f"maps: {len(m.samples.loads)} loads "
                f"{', '.join(f'{P:.4g}' for P in m.samples.loads)} N over "
                f"x = {m.samples.x[0]:.4f} .. {m.samples.x[-1]:.4f} m; fit rms K_f "
                f"{m.ripple.rms_full:.3g} N/A, F_cg {m.cogging.rms_full:.3g} N; periodic-only "
                f"fits +{m.ripple.increase_percent:.0f} % / +{m.cogging.increase_percent:.0f} %"
            )
        if self.stribeck is not None:
            s = self.stribeck
            L.append(
                f"Stribeck: {len(s.points.speed)} speeds {s.points.speed.min() * 1e3:.3g} .. "
                f"{s.points.speed.max() * 1e3:.3g} mm/s, F_s = {p['friction.F_s']:.3f} N, "
                f"F_c = {p['friction.F_c']:.3f} N, V_s = {p['friction.V_s'] * 1e3:.3f} mm/s, "
                f"delta = {p['friction.delta']:.3f}, sigma2 = {p['friction.sigma2']:.2f} N s/m "
                f"(rms residual {s.rms_residual:.3g} N)"
            )
            if s.asymmetry is not None:
                L.append(
                    f"  direction asymmetry (diagnostic, not in the model): dF = "
                    f"{s.asymmetry['asymmetry.dF']:.3f} +- {s.asymmetry['stderr.asymmetry.dF']:.3f} N, "
                    f"dsigma2 = {s.asymmetry['asymmetry.dsigma2']:.2f} +- "
                    f"{s.asymmetry['stderr.asymmetry.dsigma2']:.2f} N s/m"
                )
        if self.mass is not None:
            L.append(
                f"mass: m = {p['m']:.4f} +- {self.mass.stderr['m']:.4f} kg "
                f"({self.mass.n_used} samples, force residual {self.mass.rms_residual:.3g} N)"
            )
        if self.attraction is not None:
            L.append(f"attraction: {self.attraction.message}; model C = {p['friction.C']:.4g} N/s")
        if self.prerolling is not None:
            r = self.prerolling
            L.append(
                f"pre-rolling: N = {len(r.W)}, Delta = "
                + ", ".join(f"{d * 1e6:.1f}" for d in r.Delta)
                + " um, W = "
                + ", ".join(f"{w:.2f}" for w in r.W)
                + f" N; fit rms {100 * r.rms_relative:.2f} % "
                "of F_s"
            )
        if self.position_friction is not None:
            f = self.position_friction
            L.append(
                f"position friction: {f.profile.n} knots over {f.profile.x_start * 1e3:.1f} .. "
                f"{f.profile.x_end * 1e3:.1f} mm, p(x) = {min(f.profile.c) + 1:.3f} .. "
                f"{max(f.profile.c) + 1:.3f} at the knots (median 1; levels x {f.scale:.4f}), "
                f"fit rms {f.rms_residual:.3g} N on {f.n_used} samples"
            )
        for step, why in self.skipped.items():
            L.append(f"SKIPPED {step}: {why}")
        L.extend(self.notes)
        if self.defaulted:
            L.append(
                "kept at the paper's value (not identified): " + compress_names(self.defaulted)
            )
        if self.out_path is not None:
            L.append(f"model file: {self.out_path}")
        if self.table:
            L.append("")
            L.append(f"true ({self.truth.name if self.truth else 'truth'}) vs identified:")
            L.append(format_rows(self.table))
        return "\n".join(L)


def compress_names(names: Sequence[str]) -> str:
    """The parameter names listed compactly, 'friction.nu[6..10]' style listing of parameter names."""
    out: list[str] = []
    groups: dict[str, list[int]] = {}
    order: list[str] = []
    for n in names:
        m = re.fullmatch(r"(.+)\[(\d+)\]", n)
        if m:
            if m.group(1) not in groups:
                order.append(m.group(1))
                groups[m.group(1)] = []
            groups[m.group(1)].append(int(m.group(2)))
        else:
            order.append(n)
    for n in order:
        if n in groups:
            idx = groups[n]
            out.append(f"{n}[{idx[0]}]" if len(idx) == 1 else f"{n}[{idx[0]}..{idx[-1]}]")
        else:
            out.append(n)
    return ", ".join(out)

"""``feeddrive plan``: write a plan's folder (references, sidecars, page).

Layout of ``DIR``::

    plan.md  [plan.html]       the page (:mod:`.page`)
    reference/NN_name.csv      what the drive plays: time,x_ref[,u_add] or time,u
    sidecar/NN_name.json       the sidecar to keep beside the recording NN_name.csv

Numbers carry the digits the signals have: time to the sample time's decimals, positions
to 1e-10 m, voltages to 1e-7 V (trailing zeros dropped).
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ...model_file import ModelFile, load_model, paper_model
from ...outputs import output_dir
from .limits import PlanError, default_limits
from .make import make_plan
from .page import REFERENCE_DIR, SIDECAR_DIR, plan_markdown
from .runs import Plan

#: decimals of each reference column (time: from the sample time)
DECIMALS = {"x_ref": 10, "u": 7, "u_add": 7}


def time_decimals(Ts: float) -> int:
    """The fewest decimals (<= 12) that write every multiple of ``Ts`` exactly enough."""
    for d in range(13):
        if abs(round(Ts, d) - Ts) <= 1e-9 * Ts:
            return d
    return 12


def _strings(values: np.ndarray, decimals: int) -> list[str]:
    out = []
    for v in values.tolist():
        s = f"{v:.{decimals}f}"
        if "." in s:
            s = s.rstrip("0").rstrip(".")
        out.append("0" if s == "-0" else s)
    return out


def reference_csv(columns: Mapping[str, np.ndarray], Ts: float) -> str:
    """The text of one reference CSV (header row, then one row per sample)."""
    names = list(columns)
    dec = {"time": time_decimals(Ts), **DECIMALS}
    cols = [_strings(np.asarray(columns[c], float), dec[c]) for c in names]
    return ",".join(names) + "\n" + "".join(",".join(row) + "\n" for row in zip(*cols, strict=True))


def write_plan(
    plan: Plan,
    out: str | Path,
    source: str,
    inputs: Sequence[str | Path] = (),
    force: bool = False,
    html: bool = False,
) -> int:
    """Write ``plan`` into the folder ``out`` (replaced as a whole, see
    :func:`feeddrive.outputs.output_dir`); returns the bytes written."""
    with output_dir(Path(out), inputs, force, what="plan") as stage:
        (stage / REFERENCE_DIR).mkdir()
        (stage / SIDECAR_DIR).mkdir()
        size = 0
        for r in plan.runs:
            text = reference_csv(r.columns, plan.Ts)
            (stage / REFERENCE_DIR / f"{r.name}.csv").write_text(text, encoding="ascii")
            side = json.dumps(r.sidecar, indent=2, allow_nan=False) + "\n"
            (stage / SIDECAR_DIR / f"{r.name}.json").write_text(side, encoding="utf-8")
            size += len(text) + len(side.encode())
        page = plan_markdown(plan, source, None)
        size += len(page.encode())
        page = plan_markdown(plan, source, size)
        (stage / "plan.md").write_text(page, encoding="utf-8")
        if html:
            import markdown

            body = markdown.markdown(page, extensions=["tables", "fenced_code"])
            doc = (
                '<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>'
                f"Identification plan: {plan.model_name}</title></head><body>\n{body}\n"
                "</body></html>\n"
            )
            (stage / "plan.html").write_text(doc, encoding="utf-8")
            size += len(doc.encode())
    return size


def _controller(path: str | Path) -> dict[str, Any] | None:
    try:
        spec = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as e:
        raise PlanError(f"--controller: {path}: {e}") from None
    except json.JSONDecodeError as e:
        raise PlanError(f"--controller: {path}: line {e.lineno}: not JSON ({e.msg})") from None
    if spec is not None and not isinstance(spec, dict):
        raise PlanError(
            f"--controller: {path}: must hold a JSON object (a controller spec "
            "with a 'type') or null"
        )
    return spec


def plan_command(
    out: str | Path,
    model: str | Path | None = None,
    controller: str | Path | None = None,
    stroke: Sequence[float] | None = None,
    v_max: float | None = None,
    a_max: float | None = None,
    u_limit: float | None = None,
    loads: Sequence[float] | None = None,
    force: bool = False,
    html: bool = False,
) -> tuple[Plan, int]:
    """What ``feeddrive plan`` does: the plan for the model file (default the paper's) and
    the limits given, written to ``out``; returns the plan and the bytes written."""
    mf: ModelFile = paper_model() if model is None else load_model(model)
    spec = "default" if controller is None else _controller(controller)
    limits = default_limits(mf, stroke, v_max, a_max, u_limit, loads)
    plan = make_plan(mf, limits, spec)
    source = "the paper's model" if model is None else f"the model file {Path(model).name}"
    size = write_plan(
        plan, out, source, [p for p in (model, controller) if p is not None], force=force, html=html
    )
    return plan, size


def summary(plan: Plan, out: str | Path, size: int) -> str:
    """What the command prints: runs, duration, size, what is not identifiable."""
    L = [
        f"wrote {len(plan.runs)} runs ({plan.duration / 60:.1f} min of reference, "
        f"{size / 1e6:.1f} MB) and plan.md to {out}"
    ]
    L += [f"not identifiable with these limits: {k}: {v}" for k, v in plan.not_identified.items()]
    L += [f"note: {n}" for n in plan.notes]
    return "\n".join(L)

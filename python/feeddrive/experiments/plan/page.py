"""The plan page (Markdown): order, durations, loads, what to record and why each run is there."""

from __future__ import annotations

from ..recording import HOLD
from .runs import IDENTIFIES, IDENTIFIES_SHORT, KIND_OF_GROUP, Plan

REFERENCE_DIR, SIDECAR_DIR = "reference", "sidecar"

#: the recording format's columns, as a recording of a planned run must hold them
RECORD_COLUMNS: tuple[tuple[str, str, str], ...] = (
    ("time", "s", "sample time, every controller sample Ts, strictly increasing"),
    (
        "u",
        "V",
        "current-amplifier reference: the controller's output (plus u_add in the "
        "PRBS run; the reference's u in the open-loop run)",
    ),
    (
        "i",
        "A",
        "measured motor current (amplifier feedback); leave the column out if the "
        "drive has no current measurement",
    ),
    ("x", "m", "measured position (linear scale)"),
    ("x_ref", "m", "the position reference played (closed-loop runs)"),
    ("F_load", "N", "the load hung (the run's load below; 0 when none)"),
)


def _table(head: tuple[str, ...], rows: list[tuple[str, ...]]) -> list[str]:
    out = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    out += ["| " + " | ".join(c.replace("|", "\\|") for c in r) + " |" for r in rows]
    return out


def _minutes(seconds: float) -> str:
    return f"{seconds:.1f} s" if seconds < 120 else f"{seconds / 60:.1f} min"


def plan_markdown(plan: Plan, source: str, size_bytes: int | None = None) -> str:
    """The page: limits, what to record, the runs in order, what is not identifiable."""
    lim = plan.limits
    L = [
        f"# Identification plan: {plan.model_name}",
        "",
        f"{len(plan.runs)} runs to play on the drive in this order, "
        f"{_minutes(plan.duration)} of reference in all (holds and load changes not "
        f"counted), sample time Ts = {plan.Ts * 1e3:g} ms. Sized from {source} to these "
        "limits:",
        "",
    ]
    L += _table(
        ("limit", "value", "option"),
        [
            ("stroke", f"{lim.stroke[0]:g} .. {lim.stroke[1]:g} m", "--stroke X0 X1"),
            ("speed", f"{lim.v_max:g} m/s", "--v-max"),
            ("acceleration", f"{lim.a_max:g} m/s^2", "--a-max"),
            ("amplifier reference", f"+-{lim.u_limit:g} V", "--u-limit"),
            ("loads to hang", ", ".join(f"{P:g}" for P in lim.loads) + " N (and none)", "--loads"),
        ],
    )
    L += [
        "",
        "## How to run it",
        "",
        f"- Each run's reference is `{REFERENCE_DIR}/NN_name.csv`, one row per controller "
        "sample from t = 0.",
        "- Closed-loop runs (`time,x_ref`): hang the run's load, let the drive hold "
        "x_ref at t = 0 until it has settled (at least "
        f"{HOLD:g} s), then start the "
        "reference and the recording together.",
        "- The PRBS run also has `u_add` [V]: add it to the controller's output at each "
        "sample and record the total voltage as `u`.",
        "- The open-loop run (`time,u`): switch the position controller off, start at rest "
        "where the run says, apply `u` to the amplifier reference and stop (and end the "
        "recording) where the stage leaves the sidecar's `stop_outside` interval.",
        f"- Record each run as `NN_name.csv` in one folder and copy `{SIDECAR_DIR}/NN_name.json` "
        "beside it: the sidecar says which experiment it is, the sample time, the "
        "controller and the load. If your controller is not the one in the sidecar, "
        "describe yours there (`controller`), or set it to null: identification does not "
        "need it, only a closed-loop replay does.",
        "",
        "## What to record",
        "",
        "One CSV per run, one row per controller sample, these columns (SI units, header "
        "row; see the recording format in the documentation, `docs/data-format.md`):",
        "",
    ]
    L += _table(("column", "unit", "what"), [(c, u, w) for c, u, w in RECORD_COLUMNS])
    L += ["", "## The runs", ""]
    L += _table(
        (
            "#",
            "run",
            "load to hang",
            "duration",
            "what the stage does",
            "identifies",
            "why it is shaped so",
        ),
        [
            (
                str(j + 1),
                f"`{r.name}`",
                f"{r.load:g} N",
                f"{r.duration:.1f} s",
                r.moves,
                IDENTIFIES_SHORT[r.group],
                r.why,
            )
            for j, r in enumerate(plan.runs)
        ],
    )
    L += ["", "## What each kind of run identifies", ""]
    L += _table(
        ("runs", "sidecar kind", "identifies"),
        [(g.replace("_", " "), KIND_OF_GROUP[g], IDENTIFIES[g]) for g in IDENTIFIES],
    )
    if plan.not_identified:
        L += [
            "",
            "## Not identifiable with these limits",
            "",
            "`identify` keeps the model's values for these (and says so):",
            "",
        ]
        L += [f"- {what}: {why}" for what, why in plan.not_identified.items()]
    if plan.notes:
        L += ["", "## Notes", ""] + [f"- {n}" for n in plan.notes]
    L += [
        "",
        "## Then",
        "",
        "```",
        "feeddrive identify RECORDINGS --out my_drive.json",
        "feeddrive validate RECORDINGS/NN_name.csv --model my_drive.json",
        "```",
        "",
    ]
    if size_bytes is not None:
        L += [f"This plan's files: {size_bytes / 1e6:.1f} MB.", ""]
    return "\n".join(L)

"""`make bench`'s agreement rows (feeddrive.bench_agreement) give figures, each within the
tolerance of the test that asserts the same agreement: the Python twin of the physics against
the plant FMU along the 6 s loop, the FMI 3.0 plant against the FMI 2.0 one, the clocked FMI 3.0
controller FMU against the Python-controller run."""

from __future__ import annotations

from pathlib import Path

from feeddrive.bench_agreement import (
    TARGETS,
    agreement_figures,
    agreement_rows,
    version_figures,
    within_targets,
)
from feeddrive.paper import paper_parameters

ME = {"fmi3_me_dx_m", "fmi3_me_dF_N"}
#: the figures without a target: the size of what is compared
SIZES = (
    "peak_cogging_N",
    "peak_K_f_N_per_A",
    "peak_friction_N",
    "peak_ma_N",
    "peak_current_A",
    "design_dx_m",
    "tracking_error_m",
    "samples",
)


def stub_figures() -> dict[str, float]:
    """Figures of every row at their targets (the sizes 1), to render rows without running."""
    return {**dict.fromkeys(TARGETS, 0.0), **dict.fromkeys(SIZES, 1.0)}


def test_agreement_rows_of_the_6s_loop_are_within_their_targets(fmu3_path: Path) -> None:
    f = agreement_figures(me=False)  # model exchange: the next test (6 s of CVode is slow)
    assert within_targets(f) == [], within_targets(f)
    assert set(TARGETS) - ME <= set(f)
    # the twin is compared on forces of their full size, not on zeros: friction up to its
    # sliding level, cogging up to its amplitude, the current of the 30 mm sinusoid
    assert 0.9 * paper_parameters()["friction.F_c"] < f["peak_friction_N"] < 30.0
    assert f["peak_cogging_N"] > 10.0 and f["peak_current_A"] > 0.1
    # the GMS integrated along the samples is another integration: close, not equal
    assert 0.0 < f["gms_along_N"]
    # the design model's loop (no ripple, forces held over a sample) follows the FMU's loop
    # to a few percent of the loop's tracking error (tens of um on this sinusoid)
    assert f["design_dx_m"] < 0.1 * f["tracking_error_m"] and f["tracking_error_m"] > 20e-6
    rows = agreement_rows(f)
    assert len(rows) == 8 and all(r[1] and "nan" not in r[1] for r in rows)
    assert not any("ME" in r[0] for r in rows)


def test_model_exchange_row_fmi3_against_fmi2(fmu3_path: Path) -> None:
    """CVode on 7 states (FMI 3.0, N = 5) and on 12 (FMI 2.0): not to the bit, within the CS/ME
    tolerance (1.5 s of the loop: the start from rest and the speed-up)."""
    f = version_figures(duration=1.5)
    assert within_targets(f) == [], within_targets(f)
    assert f["fmi3_cs_dx_m"] == 0.0 and 0.0 < f["fmi3_me_dx_m"]
    assert any("ME" in r[0] for r in agreement_rows({**stub_figures(), **f}))


def test_a_figure_beyond_its_target_is_named() -> None:
    f = {**stub_figures(), "twin_ma_N": 2e-6, "clocked_dx_m": 1e-15}
    assert within_targets(f) == ["twin_ma_N = 2e-06 > 1e-09", "clocked_dx_m = 1e-15 > 0"]

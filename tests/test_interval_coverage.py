"""Coverage of ``identify --bootstrap`` intervals over independent campaigns made by the FMU
(feeddrive.study.coverage).

K campaigns on a non-paper truth (mass, current-loop gain and Stribeck curve changed), each
with its own sensor noise, each identified and given 95 % parametric intervals from B
simulated campaigns.  For every parameter the truth must lie inside as many intervals as a
binomial(K, 0.95) gives with probability >= 1 % (K = 8: at least 6).  The intervals must
also be informative: their mean width at most twice the width 2 x 1.96 x sd that the
estimates' scatter over the K campaigns (plus their mean error from the truth) calls for.
The full study (K = 20, the percentile method of whole-run resampling beside it) is
``make interval-coverage``; its figures are in docs/intervals.md.
"""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.study.coverage import CHECKED, coverage_study, coverage_truth, lowest_count

K, B = 8, 10
#: the steps every campaign identifies: each must get an interval in every campaign
ALWAYS = ("m", "friction.F_s", "friction.F_c", "friction.V_s", "friction.delta", "friction.sigma2")


@pytest.mark.slow
def test_parametric_intervals_cover_the_truth(fmu_path):
    cov = coverage_study(K, "parametric", replicates=B, repeats=1)
    print("\n" + cov.table())
    summary = cov.summary()
    truth = coverage_truth().parameters
    assert not cov.failures(), "\n".join(cov.failures()) + "\n" + cov.table()
    for n in ALWAYS:
        s = summary[n]
        assert s["given"] == K, f"{n}: {s['refused']} refusals\n{cov.table()}"
        est = np.array([r[n]["estimate"] for r in cov.rows])
        need = 2 * 1.96 * np.hypot(np.std(est, ddof=1), np.mean(est) - truth[n])
        width = s["mean_rel_width"] * abs(truth[n])
        assert width <= 2 * need, f"{n}: mean width {width:.3g} > 2 x {need:.3g}\n{cov.table()}"
    for n in CHECKED:
        s = summary[n]
        if s["given"]:
            assert s["inside"] >= lowest_count(s["given"]), cov.table()

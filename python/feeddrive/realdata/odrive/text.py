"""The findings as a short human-readable report."""

from __future__ import annotations

from .along_revolution import PERIODIC_TOL
from .findings import OdriveFindings, slow_summary
from .recordings import SLOW_FOLDERS


def findings_text(f: OdriveFindings) -> str:
    """Short human-readable report of :func:`analyse`'s findings."""
    q, fr = f.crosstalk_order, f.friction
    amp = {ln.order: ln.amplitude for ln in f.lines}
    iso = {ln.order: ln.amplitude for ln in f.isolated_lines}
    stay = 100 * max(abs(iso[k] / a - 1) for k, a in amp.items() if k != q)
    clean = [s for s in f.stationarity if all(t.periodic for t in s.tracks)]
    odd = [s for s in f.stationarity if s not in clean]
    out = [
        f"ODrive BLDC (rotary), 8192 counts/rev, holding current Iq [A]; forward map {f.reference}",
        f"Summary: periodic (constant along the revolution in {', '.join(s.map_name for s in clean)}): "
        + ", ".join(f"{t.order}/rev" for t in f.stationarity[0].tracks)
        + f"; their zero-frequency term does not drift (<= {max(s.local_mean_drift for s in clean):.3f}"
        f" A p-p). Not periodic: the {q}/rev line is crosstalk (changes with the neighbour); "
        + "; ".join(
            f"{s.map_name}: lines "
            + ",".join(str(t.order) for t in s.tracks if not t.periodic)
            + f" wander, local mean drifts {s.local_mean_drift:.2f} A p-p"
            for s in odd
        )
        + ".",
        "Periodic lines, full revolution [order/rev: A]: "
        + ", ".join(f"{ln.order}: {ln.amplitude:.3f}" for ln in f.lines)
        + f" (grids 4..32 counts agree within {100 * f.grid_check:.1f} %)",
        f"Crosstalk: without the neighbouring motor (iso_16) the {q}/rev line drops "
        f"{amp[q]:.2f} -> {iso[q]:.2f} A, the others change by {stay:.0f} % at most; across "
        "sessions the same line reads "
        + ", ".join(f"{t.name} {t.crosstalk.amplitude:.2f} A" for t in f.trials)
        + f": an external force that a slot-harmonic cogging model would wrongly absorb "
        f"(iso_16 is also registered {f.isolated_shift[0]} counts away, r = {f.isolated_shift[1]:.2f})",
    ]
    out.append(
        "Along the revolution (DSTFT, rectangular window 1/2 rev, compared with the constant "
        f"lines through the same window; periodic if deviation <= {PERIODIC_TOL}):"
    )
    for s in f.stationarity:
        non = [t for t in s.tracks if not t.periodic]
        out.append(
            f"  {s.map_name:7s} deviation "
            + " ".join(f"{t.order}:{t.deviation:.2f}" for t in s.tracks)
            + (" -> NOT periodic " + ",".join(str(t.order) for t in non) if non else " -> periodic")
            + f"; local mean {s.local_mean_range[0]:+.2f}..{s.local_mean_range[1]:+.2f} A of which "
            f"{s.local_mean_drift:.3f} A p-p is not line leakage; residual rms {s.residual_rms:.3f} A"
        )
    for t in f.trials:
        out.append(
            f"Repeat {t.name}: r = {t.correlation:+.3f} as measured, {t.correlation_half_turn:+.3f} "
            f"shifted 4096 counts; rms diff {t.rms_difference:.3f} A; odd non-{q}k orders "
            f"coherence {t.odd_coherence:+.2f} (-1 would mean a true half-turn shift)"
        )
    out.append(
        f"Friction: forward - reverse = {fr.mean_difference:.3f} A ({fr.forward} - {fr.reverse}, "
        f"matched {q}/rev line; all 8 pairs {fr.pair_means[0]:.2f}..{fr.pair_means[2]:.2f}, "
        f"mean {fr.pair_means[1]:.2f}) = 2 F/Kt. Position-dependent part std "
        f"{fr.difference_std:.3f} A, lines "
        + ", ".join(f"{ln.order}: {ln.amplitude:.3f}" for ln in fr.difference_lines)
        + f"; {100 * fr.offset_r2:.0f} % of its variance is a {fr.offset_counts:.1f}-count "
        f"rest-position offset between directions; the rest {fr.residual_std:.3f} A vs white "
        f"point noise {fr.noise_std:.3f} A (from orders > 128/rev): "
        + (
            "no position-dependent friction above the noise"
            if fr.residual_std < 1.2 * fr.noise_std
            else "a position-dependent remainder above the noise"
        )
    )
    summ = slow_summary(f)
    for sub in SLOW_FOLDERS:
        n, c = summ[f"{sub}/nocomp"], summ[f"{sub}/comp"]
        out.append(
            f"Slow runs {sub} ({n['speed']:.3f} rev/s): velocity ripple std (np.gradient on "
            f"the non-uniform time stamps) {n['velocity_std']:.0f} -> {c['velocity_std']:.0f} "
            f"counts/s with the map as feed-forward (gap shrinks "
            f"x{n['velocity_std'] / c['velocity_std']:.1f})"
        )
        for k in ("nocomp", "comp", "crosstalk_nocomp", "crosstalk_comp"):
            if (row := summ.get(f"{sub}/{k}")) is not None:
                out.append(
                    f"  {k:16s} ({row['n']} run(s)): r(Iq, map at position) {row['r_static']:.3f}; "
                    f"behind a {1000 * row['lag_s']:.0f} ms first-order lag {row['r_lagged']:.3f}; "
                    f"map without odd {q}k/rev {row['r_lagged_no_crosstalk']:.3f}"
                    + (f"; velocity std {row['velocity_std']:.0f}" if "crosstalk" in k else "")
                )
    lags = [summ[f"{sub}/{k}"]["lag_s"] for sub in SLOW_FOLDERS for k in ("nocomp", "comp")]
    if max(lags) < 1.25 * min(lags):
        out.append(
            f"The Iq lag is the same at both speeds ({1000 * min(lags):.0f}..{1000 * max(lags):.0f}"
            " ms): a filter on the reported Iq, so the lower r(Iq, map) at the higher speed is "
            "that filter, not motor dynamics."
        )
    return "\n".join(out)

"""Ground-motion suites: records scaled to a design spectrum, checked
against the Eurocode 8 rule, and the statistics over the suite, each
recomputed here independently."""
import numpy as np
import pytest

import quakejoint as qj


def ec8_type1_c(t, ag_g=0.3):
    """Eurocode 8 type 1, ground C, 5 % (EN 1998-1 Table 3.2): S = 1.15,
    T_B = 0.2, T_C = 0.6, T_D = 2.0 s; [m/s^2]."""
    s, tb, tc, td = 1.15, 0.2, 0.6, 2.0
    t = np.asarray(t, dtype=float)
    plateau = ag_g * s * 2.5
    se = np.where(
        t <= tb,
        ag_g * s * (1 + t / tb * 1.5),
        np.where(t <= tc, plateau, np.where(t <= td, plateau * tc / t, plateau * tc * td / t**2)),
    )
    return se * qj.G


def test_the_target_and_the_records_factors(suite_sweep):
    s = qj.read_sweep(suite_sweep)
    suite = s.suite
    assert suite["target"].startswith("Eurocode 8 type 1, ground C, a_g = 0.3 g")
    np.testing.assert_allclose(suite["target_sa"], ec8_type1_c(s.periods), rtol=1e-12)
    np.testing.assert_allclose(suite["fit_target"], ec8_type1_c(suite["fit_period"]), rtol=1e-12)
    # the records in the file are the scaled ones: each file's g times its factor
    import h5py

    with h5py.File(suite_sweep) as f:
        scales = [f["records"][r]["scale"][()] for r in s.records]
    np.testing.assert_allclose(np.array(scales) / qj.G, suite["factor"], rtol=1e-14)


def test_the_suites_mean_meets_the_eurocode_8_rule(suite_sweep):
    import h5py

    s = qj.read_sweep(suite_sweep)
    suite = s.suite
    periods = suite["fit_period"]
    spectra = []
    with h5py.File(suite_sweep) as f:
        for r in s.records:
            # fitted over the runs' window (simulation.duration = 3 s), as the jobs see the records
            dt = f["records"][r]["dt"][()]
            window = f["records"][r]["acceleration"][: int(round(3.0 / dt)) + 1]
            spectra.append(qj.spectrum(window, periods, 0.05, dt=dt, units="m/s2").sa)
    mean = np.mean(spectra, axis=0)
    np.testing.assert_allclose(mean, suite["fit_mean"], rtol=1e-12)
    ratio = mean / suite["fit_target"]
    assert ratio.min() >= 0.9 * (1 - 1e-12) and suite["ec8_satisfied"]
    assert suite["min_ratio"] == pytest.approx(ratio.min(), rel=1e-12)
    if suite["rule_factor"] > 1:  # scaled up by the rule: exactly to 90 %, no further
        assert ratio.min() == pytest.approx(0.9, rel=1e-12)
    # each record alone is fitted by least squares in logarithms: with the
    # rule's common factor taken out, its log-ratio to the target averages 0
    for sa in spectra:
        assert np.mean(np.log(suite["fit_target"] / (sa / suite["rule_factor"]))) == pytest.approx(0, abs=1e-12)


def test_statistics_over_the_suite(suite_sweep):
    s = qj.read_sweep(suite_sweep)
    st = s.statistics
    assert (st["count"] == 3).all()
    sa, without = s["sa"][:, :, 0, :], s.without_joint["sa"][:, 0, :]  # (case, record, period), (record, period)
    np.testing.assert_allclose(st["with_joint"]["mean"][:, 0], sa.mean(axis=1), rtol=1e-12)
    np.testing.assert_allclose(st["with_joint"]["median"][:, 0], np.median(sa, axis=1), rtol=1e-12)
    np.testing.assert_allclose(st["with_joint"]["dispersion"][:, 0], np.log(sa).std(axis=1, ddof=1), rtol=1e-10)
    np.testing.assert_allclose(st["without_joint"]["mean"][0], without.mean(axis=0), rtol=1e-12)
    red = 1 - sa / without[None]
    np.testing.assert_allclose(st["reduction"]["mean"][:, 0], red.mean(axis=1), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(st["reduction"]["std"][:, 0], red.std(axis=1, ddof=1), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(
        st["reduction"]["of_mean"][:, 0], 1 - sa.mean(axis=1) / without.mean(axis=0), rtol=1e-9, atol=1e-15
    )
    ds = s.to_xarray()
    assert ds["suite_factor"].dims == ("record",) and ds["with_joint_mean"].dims == ("case", "damping", "period")


def test_the_suite_plot(suite_sweep):
    import sys

    from conftest import ROOT

    sys.path.insert(0, str(ROOT / "scripts"))
    import plot_spectrum

    fig = plot_spectrum.figure(suite_sweep)  # a suite: the statistics view
    ax, axr = fig.axes
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert "mean with joint" in labels and "mean without joint" in labels
    assert any(lb.startswith("target: Eurocode 8 type 1") for lb in labels)
    s = qj.read_sweep(suite_sweep)
    mean = [ln for ln in ax.get_lines() if ln.get_label() == "mean with joint"][0]
    np.testing.assert_array_equal(mean.get_ydata(), s.statistics["with_joint"]["mean"][0, 0])
    assert len([ln for ln in ax.get_lines() if ln.get_color() == "0.75"]) == 3
    assert "reduction of the mean, 1 - mean with / mean without" in [ln.get_label() for ln in axr.get_lines()]
    assert len(plot_spectrum.figure(suite_sweep, per_record=True).axes) == 6  # 3 records x 2 panels

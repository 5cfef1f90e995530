"""Exact linear spectra from Python: bit for bit the command line's, and
against the closed-form response of an oscillator to a harmonic ground
motion started from rest."""
import numpy as np
import pytest

import quakejoint as qj

from conftest import RECORD, cli_json


def test_the_spectrum_equals_the_command_lines_bit_for_bit(cli):
    periods = np.geomspace(0.05, 5.0, 60)
    rows = cli_json(
        cli, "spectrum", RECORD, "--periods", ",".join(repr(float(p)) for p in periods), "--damping", "0.02,0.05"
    )
    spec = qj.spectrum(qj.Record.read(RECORD), periods, [0.02, 0.05])
    assert spec.sa.shape == (2, 60)
    for row in rows:
        z = [0.02, 0.05].index(row["damping"])
        t = int(np.flatnonzero(periods == row["period"])[0])
        for key in ("sa", "psa", "sd", "sv", "psv", "t_sa"):
            assert getattr(spec, key)[z, t] == row[key], (key, row["period"], row["damping"])


def harmonic_response(period, zeta, amplitude, freq, t):
    """Closed form: u'' + 2 zeta w u' + w^2 u = -A sin(W t) from rest;
    returns the absolute acceleration -(w^2 u + 2 zeta w u')."""
    w, W = 2 * np.pi / period, 2 * np.pi * freq
    wd = w * np.sqrt(1 - zeta**2)
    # particular solution C sin Wt + D cos Wt
    m = np.array([[w**2 - W**2, -2 * zeta * w * W], [2 * zeta * w * W, w**2 - W**2]])
    C, D = np.linalg.solve(m, [-amplitude, 0.0])
    E = -D
    F = (zeta * w * E - W * C) / wd
    decay = np.exp(-zeta * w * t)
    u = C * np.sin(W * t) + D * np.cos(W * t) + decay * (E * np.cos(wd * t) + F * np.sin(wd * t))
    du = (
        C * W * np.cos(W * t)
        - D * W * np.sin(W * t)
        + decay * ((-zeta * w * E + wd * F) * np.cos(wd * t) + (-zeta * w * F - wd * E) * np.sin(wd * t))
    )
    return -(w**2 * u + 2 * zeta * w * du)


@pytest.mark.parametrize("period, zeta", [(0.3, 0.05), (1.0, 0.02), (2.5, 0.1)])
def test_a_harmonic_ground_motion_against_the_closed_form(period, zeta):
    dt, amplitude, freq = 0.0005, 2.0, 1.3
    t = np.arange(0, 20 + dt / 2, dt)
    ag = amplitude * np.sin(2 * np.pi * freq * t)
    spec = qj.spectrum(ag, [period], zeta, dt=dt, units="m/s2")
    exact = np.abs(harmonic_response(period, zeta, amplitude, freq, t)).max()
    # the engine is exact for ground acceleration linear between samples:
    # the sine's interpolation error is (W dt)^2 / 8, about 2e-6
    assert spec.sa[0] == pytest.approx(exact, rel=2e-5)


def test_an_array_and_its_record_give_one_spectrum():
    rec = qj.Record.read(RECORD)
    a = qj.spectrum(rec, [0.5, 1.0])
    b = qj.spectrum(rec.acceleration, [0.5, 1.0], dt=rec.dt, units="m/s2")
    np.testing.assert_array_equal(a.sa, b.sa)
    np.testing.assert_array_equal(rec.spectrum([0.5, 1.0], 0.05).sa, a.sa)
    assert a.damping.tolist() == [0.05]


def test_bad_spectrum_inputs_are_refused():
    rec = qj.Record.read(RECORD)
    with pytest.raises(qj.InputError, match="dt"):
        qj.spectrum(np.zeros(10), [1.0], units="g")
    with pytest.raises(qj.InputError, match="period"):
        qj.spectrum(rec, [-1.0])
    with pytest.raises(qj.InputError, match="damping"):
        qj.spectrum(rec, [1.0], 1.5)
    with pytest.raises(qj.InputError, match="Record carries its own"):
        qj.spectrum(rec, [1.0], dt=0.01)


def test_the_shape_follows_the_arguments(cli):
    """A number has no axis, a sequence (of one, or of none) has one: the
    arrays have shape np.shape(damping) + np.shape(periods)."""
    rec = qj.Record.read(RECORD)
    periods = [0.5, 1.0, 2.0]
    rows = cli_json(cli, "spectrum", RECORD, "--periods", "0.5,1.0,2.0", "--damping", "0.05")
    one = qj.spectrum(rec, periods, 0.05)
    for key in ("sa", "psa", "sd", "sv", "psv", "t_sa", "t_sd", "t_sv"):
        assert getattr(one, key).shape == (3,), key
    assert one.sa.tolist() == [row["sa"] for row in rows]  # the command's numbers, one per period
    assert qj.spectrum(rec, periods).sa.shape == (3,)  # the default damping is the number 0.05
    assert rec.spectrum(periods, 0.05).sa.shape == (3,)
    assert qj.spectrum(rec, np.array(periods), np.float64(0.05)).sa.shape == (3,)
    assert qj.spectrum(rec, periods, [0.05]).sa.tolist() == [one.sa.tolist()]
    assert qj.spectrum(rec, periods, [0.02, 0.05]).sa.shape == (2, 3)
    assert qj.spectrum(rec, periods, np.array([0.02, 0.05])).sa[1].tolist() == one.sa.tolist()
    # empty sequences keep their axis and the other's
    assert qj.spectrum(rec, [], [0.02, 0.05]).sa.shape == (2, 0)
    assert qj.spectrum(rec, np.array([]), 0.05).sa.shape == (0,)
    assert qj.spectrum(rec, periods, []).sa.shape == (0, 3)
    # a number of periods has no period axis either
    assert qj.spectrum(rec, 1.0, [0.02, 0.05]).sa.tolist() == [qj.spectrum(rec, [1.0], z).sa[0] for z in (0.02, 0.05)]
    assert qj.spectrum(rec, 1.0, 0.05).sa.shape == ()
    assert float(qj.spectrum(rec, 1.0, 0.05).sa) == one.sa[1]
    # the labels are always 1-D
    assert one.damping.tolist() == [0.05] and one.periods.tolist() == periods
    assert qj.spectrum(rec, 1.0).periods.tolist() == [1.0]

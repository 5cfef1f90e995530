"""One run, defined once: the same overridden run through the command line,
Python and a sweep job gives the same numbers, and the same bad override
the same reason, each naming the override as its front end names it.

A run is the config with every override applied and checked by one piece
of code (`quakejoint_model::runspec::RunSpec`): the command line's
`--period`, Python's `period=`, a sweep job's period and damping from its
grid. Before, the command line put `--period` into the config and into a
separate frequency without checking it again (`--period 1e5 --no-joint`
ran), and a sweep job overrode the damping through the config but the
period through the run's options.
"""
import h5py
import numpy as np
import pytest

import quakejoint as qj

from conftest import ROOT, SHORT_SMALL, cli_json, run_cli

#: results a sweep stores per job that a run reports too
COMPARED = ("sa", "psa", "sd", "sv", "t_sa", "peak_joint_force", "friction_energy", "earthquake_work", "steps")


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    d = tmp_path_factory.mktemp("runspec")
    run = d / "run.toml"
    run.write_text(SHORT_SMALL)
    sweep = d / "sweep.toml"
    sweep.write_text(SHORT_SMALL + "[sweep]\nperiods = [1.2]\ndamping = [0.03]\n")
    bad = d / "bad.toml"
    bad.write_text(SHORT_SMALL + "[sweep]\nperiods = [100000.0]\ndamping = [0.03]\n")
    return d, run, sweep, bad


def test_the_same_overridden_run_gives_the_same_numbers_everywhere(cli, configs):
    d, run, sweep, _ = configs
    damped = run.read_text().replace("[record]", "[bridge]\ndamping = 0.03\n[record]")
    run.write_text(damped)
    by_cli = cli_json(cli, "simulate", run, "--period", "1.2")
    by_python = qj.simulate(qj.Config.from_file(run), period=1.2, history=False)
    out = d / "sweep.h5"
    run_cli(cli, "sweep", sweep, "--output", out, "--progress", "none")
    with h5py.File(out) as f:
        by_sweep = {k: f[f"spectrum/with_joint/{k}"][()].ravel()[0] for k in COMPARED}
    for k in COMPARED:
        values = [np.float64(by_cli[k]), np.float64(getattr(by_python, k)), np.float64(by_sweep[k])]
        assert len({v.tobytes() for v in values}) == 1, (k, values)


def test_the_same_bad_override_gives_the_same_reason_everywhere(cli, configs):
    _, run, _, bad = configs
    reason = ": must be within 0.01 <= x <= 10 s"
    code, _, err = run_cli(cli, "simulate", run, "--period", "1e5", "--no-joint", check=False)
    assert code == 2 and f"--period 100000{reason}" in err, err
    with pytest.raises(qj.InputError) as python_error:
        qj.simulate(qj.Config.from_file(run), period=1e5, joint=False)
    assert str(python_error.value).startswith(f"period = 100000{reason}"), python_error.value
    code, _, err = run_cli(cli, "sweep", bad, "--check", check=False)
    assert code == 2 and f"sweep.periods[0] = 100000{reason}" in err, err


def test_a_record_passed_from_python_runs_as_the_command_lines_record(cli, configs):
    # (the run's spec carries the record Python read, as it carries the file
    # of --record: the same numbers and the same record in the result)
    _, run, _, _ = configs
    other = ROOT / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    by_cli = cli_json(cli, "simulate", run, "--record", other)
    by_python = qj.simulate(qj.Config.from_file(run), record=qj.Record.read(other), history=False)
    assert by_python.record.startswith("RSN6"), by_python.record
    for k in COMPARED:
        assert np.float64(by_cli[k]).tobytes() == np.float64(getattr(by_python, k)).tobytes(), k


def assert_same_reason(cli, cli_args, flag, value, python_call, keyword, reason):
    """The command line refuses `flag value` (after `cli_args`) and Python
    `python_call(keyword=value)` with the same reason, each naming the value
    as its front end does (`--flag value: ...`, `keyword = value: ...`)."""
    code, _, err = run_cli(cli, *cli_args, flag, value, check=False)
    assert code == 2 and f"{flag} {value:g}{reason}" in err, err
    with pytest.raises(qj.InputError) as python_error:
        python_call(**{keyword: [value] if keyword == "amplitudes" else value})
    assert str(python_error.value).startswith(f"{keyword} = {value:g}{reason}"), python_error.value


def test_the_same_bad_service_override_gives_the_same_reason_everywhere(cli, configs):
    # (the service case's speed, amplitude and cycles are overrides of the
    # one run spec, checked by the same code from the command line and
    # Python, each named as its front end names it)
    _, run, _, _ = configs
    cfg = qj.Config.from_file(run)
    for flag, keyword, value, reason in [
        ("--amplitude", "amplitude", 5.0, ": must be within 0 < x <= 2 m"),
        ("--speed", "speed", 2.0, ": must be within 0 < x <= 1 m/s"),
        ("--cycles", "cycles", 5000, ": must be within 1 <= x <= 1000"),
    ]:
        service = lambda **kw: qj.service(cfg, **kw)  # noqa: E731
        assert_same_reason(cli, ["service", run], flag, value, service, keyword, reason)


def test_the_same_bad_calibration_option_gives_the_same_reason_everywhere(cli, configs, tmp_path):
    # (checked before any loop runs, each named as its front end names it)
    _, run, _, _ = configs
    cfg = qj.Config.from_file(run)
    cli_args = ["calibrate", run, "--no-earthquake", "--output-dir", tmp_path]
    for flag, keyword, value, reason in [
        ("--speed", "speed", 3.0, ": must be within 0 < x <= 1 m/s"),
        ("--contact-force", "contact_force", 0.0, ": must be a force above 0 and at most 1e11 N"),
        ("--amplitudes", "amplitudes", 5.0, ": must be within 0 < x <= 2 m"),
    ]:
        calibrate = lambda **kw: qj.calibrate(cfg, earthquake=False, **kw)  # noqa: E731
        assert_same_reason(cli, cli_args, flag, value, calibrate, keyword, reason)

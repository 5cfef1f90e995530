"""Coupled runs from Python: the command line's numbers bit for bit, the
bridge alone against the exact spectrum, the GIL released, Ctrl-C."""
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import quakejoint as qj

from conftest import ROOT, cli_json


@pytest.fixture(scope="module")
def run(short_config):
    return qj.simulate(qj.Config.from_file(short_config), period=1.2)


def test_a_run_equals_the_command_lines_bit_for_bit(cli, short_config, run):
    expect = cli_json(cli, "simulate", short_config, "--period", "1.2")
    for key in ("sa", "psa", "sd", "sv", "t_sa", "peak_joint_force", "friction_energy", "earthquake_work",
                "min_subgap", "max_subgap", "energy_error", "steps", "newton_iterations"):
        assert getattr(run, key) == expect[key], key
    assert run.flags == expect["flags"] and run.validity == expect["validity"]


def test_histories_hold_the_peaks_and_close_the_energy(run):
    h = run.history
    n = len(h["t"])
    assert h["t"][-1] == pytest.approx(4.0)
    assert np.abs(h["a_abs"]).max() == run.sa  # peaks at the sample times
    assert h["subgaps"].shape == (4, n) and h["center_beam_dx"].shape == (3, n)
    assert h["joint_force"].shape == (n,)
    # the running integral of the sampled friction power approaches the
    # run's exact dissipation (which is integrated inside every step)
    assert h["friction_energy"][-1] == pytest.approx(run.friction_energy, rel=2e-2)
    assert run.energy_error < 1e-6


def test_the_bridge_alone_is_the_exact_linear_spectrum(short_config, run):
    alone = qj.simulate(qj.Config.from_file(short_config), period=1.2, joint=False)
    assert alone.joint is False and alone.flags == ["not_checked"] and np.isnan(alone.peak_joint_force)
    rec = qj.Record.read(ROOT / "ground_motions" / "RSN753_LOMAP_CLS090-hor2.AT2", scale=0.3)
    window = rec.acceleration[: int(round(4.0 / rec.dt)) + 1]
    exact = qj.spectrum(window, [1.2], 0.05, dt=rec.dt, units="m/s2")
    assert alone.sa == exact.sa[0]
    # the with-joint run carries the same exact response for comparison
    assert np.abs(run.history["a_abs_without_joint"]).max() == alone.sa


def test_a_record_object_replaces_the_configs(short_config):
    rec = qj.Record.read(ROOT / "ground_motions" / "RSN753_LOMAP_CLS090-hor2.AT2", scale=0.1)
    r = qj.simulate(qj.Config.from_file(short_config), period=1.2, record=rec, history=False)
    assert r.history is None and r.record_scale == 0.1


#: the reference joint followed by an hour of free vibration: hours of
#: computing on any machine, so a run of it lasts as long as a test lets it
#: (its wall-time limit, or Ctrl-C), whatever the machine's speed
ENDLESS = {"simulation.extra_time": 3600.0}


def test_the_gil_is_released_while_a_run_goes_on():
    # stopped by its wall-time limit after 0.5 s, on a fast machine as on a slow one
    config = qj.Config.from_file(ROOT / "configs" / "paper.toml").replace(
        dict(ENDLESS, **{"simulation.max_wall_time": 0.5})
    )
    done = threading.Event()
    result = {}

    def work():
        try:
            qj.simulate(config, period=0.8, history=False)
        except qj.SimulationError as e:
            result["error"] = str(e)
        done.set()

    thread = threading.Thread(target=work)
    start = time.monotonic()
    thread.start()
    ticks = 0
    while not done.is_set():
        ticks += 1  # pure Python: runs only if the run let go of the GIL
        time.sleep(0.001)
    thread.join()
    wall = time.monotonic() - start
    assert "time limit of 0.5 s wall clock reached" in result.get("error", ""), result
    # holding the GIL, the run would leave this loop a tick or two; free,
    # it ticks about once a millisecond of the run's 0.5 s
    assert wall >= 0.5 and ticks > 0.3 * 0.5 / 1e-3, (ticks, wall)


def test_ctrl_c_stops_a_run():
    code = (
        "import quakejoint as qj, sys; print('start', flush=True); "
        f"qj.simulate(qj.Config.from_file({str(ROOT / 'configs' / 'paper.toml')!r}).replace({ENDLESS!r}))"
    )
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "start"
    time.sleep(0.5)  # inside the run, which lasts hours
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=30)
    assert time.monotonic() - sent < 5.0
    assert p.returncode != 0 and "KeyboardInterrupt" in err


def test_a_failed_run_is_a_simulation_error(short_config):
    config = qj.Config.from_file(short_config).replace({"simulation.max_steps": 5})
    with pytest.raises(qj.SimulationError, match="step"):
        qj.simulate(config, history=False)


def test_the_service_loop(short_config):
    loop = qj.service(qj.Config.from_file(ROOT / "configs" / "small.toml").replace({"service.cycles": 2}))
    assert loop["u"].shape == loop["joint_force"].shape == loop["t"].shape
    assert loop["center_beam_dx"].shape[0] == 3
    # the loop's area is what friction, dampers and impacts dissipate
    dissipated = loop["friction_work_per_cycle"] + loop["damping_work_per_cycle"] + loop["contact_work_per_cycle"]
    assert loop["loop_work_per_cycle"] == pytest.approx(dissipated, rel=1e-2)


def test_the_deck_across_the_bridge(short_config):
    text = short_config.read_text() + (
        f'\n[record_y]\nfile = "{ROOT / "ground_motions" / "RSN753_LOMAP_CLS000-hor1.AT2"}"\nscale = 0.3\n'
    )
    config = qj.Config.from_toml(text).replace({"bridge.transverse_period": 0.8})
    run = qj.simulate(config, period=1.2)
    h = run.history
    assert run.period_y == pytest.approx(0.8) and run.sa_y > 0
    assert np.abs(h["a_abs_y"]).max() == run.sa_y and np.abs(h["uy"]).max() == run.sd_y
    assert run.sa_y_without_joint > 0 and run.energy_error < 1e-6
    along = qj.simulate(qj.Config.from_file(short_config), period=1.2)
    assert np.isnan(along.sa_y) and "uy" not in along.history


def test_the_joint_between_two_segments(short_config):
    config = qj.Config.from_file(short_config).replace({"bridge.far": {"period_ratio": 0.5}})
    run = qj.simulate(config, period=1.2, history=False)
    assert run.period_far == pytest.approx(0.6) and run.sa_far > 0 and run.sa_far_without_joint > 0
    assert run.max_relative_displacement > 0 and run.energy_error < 1e-6
    alone = qj.simulate(qj.Config.from_file(short_config), period=1.2, history=False)
    assert np.isnan(alone.sa_far)


def test_two_joints_on_a_modal_bridge_in_the_cli_python_and_the_run_file(cli, two_joints):
    """The same run through the command (JSON and its HDF5 file) and
    Python: each joint's values and each point's, the same numbers."""
    import h5py

    config, path = two_joints
    out = cli_json(cli, "simulate", config)
    assert out["bridge_model"] == "modal" and out["joint_name"] == "left abutment"
    assert [j["name"] for j in out["joints"]] == ["left abutment", "right abutment"]
    assert [p["name"] for p in out["points"]] == ["left end", "right end", "pier 1 top", "pier 2 top"]
    r = qj.simulate(qj.Config.from_file(config))
    assert r.sa == out["sa"] and r.base_shear == out["base_shear"]
    assert r.joints[1]["name"] == "right abutment"
    assert r.joints[1]["peak_joint_force"] == out["joints"][1]["peak_joint_force"]
    assert r.joints[1]["impacts"] == out["joints"][1]["impacts"]
    # every joint alike: the first's own values are the run's where they are its own
    assert r.joints[0]["max_subgap"] == out["max_subgap"] and r.joints[0]["history"] is None
    assert out["joints"][0]["friction_energy"] + out["joints"][1]["friction_energy"] == pytest.approx(
        out["friction_energy"], rel=1e-12
    )
    assert [p["sd"] for p in r.points] == [p["sd"] for p in out["points"]]
    # every point's history, with the joints and without
    assert r.history["points_u"].shape == (4, len(r.history["t"]))
    assert r.history["points_a_abs_without_joint"].shape == (4, len(r.history["t"]))
    with h5py.File(path) as f:
        assert f["joints/1"].attrs["name"].decode() == "right abutment"
        assert f["joints/1/peak_joint_force"][()] == out["joints"][1]["peak_joint_force"]
        assert f["joints/0"].attrs["name"].decode() == "left abutment"
        assert f["points/sa_without_joint"][()].tolist() == [p["sa_without_joint"] for p in out["points"]]
        assert f["result/sa"][()] == out["sa"]
    # the joints pound at this strength, and every output says so
    flags = out["validity_label"]
    assert r.flagged == (flags != "ok")

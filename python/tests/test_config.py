"""Configs from files, text and dicts: the command line's validation and
messages."""
import pytest

import quakejoint as qj

from conftest import ROOT, run_cli

BAD = ROOT / "tests" / "bad_inputs"


@pytest.mark.parametrize(
    "name",
    [
        "02-unknown-key.toml",
        "03-negative-bridge-mass.toml",
        "04-zero-period.toml",
        "05-damping-one.toml",
        "12-period-and-w0.toml",
        "13-negative-mu.toml",
        "16-broken-toml.toml",
        "28-beam-wider-than-pitch.toml",
    ],
)
def test_a_bad_config_gives_the_command_lines_message(cli, name):
    code, _, err = run_cli(cli, "model", BAD / name, check=False)
    assert code == 2
    expected = err.strip().removeprefix("error: ")
    with pytest.raises(qj.InputError) as e:
        qj.Config.from_file(BAD / name)
    assert str(e.value) == expected


def test_a_missing_record_is_named_with_the_config(cli):
    path = BAD / "01-missing-record-file.toml"
    code, _, err = run_cli(cli, "simulate", path, check=False)
    assert code == 2
    config = qj.Config.from_file(path)
    with pytest.raises(qj.InputError) as e:
        qj.simulate(config)
    assert str(e.value) == err.strip().removeprefix("error: ")


def test_dicts_defaults_and_replace():
    default = qj.Config()
    assert default.to_dict()["joint"]["center_beams"] == 27
    c = qj.Config({"bridge": {"mass": 2e8}, "joint": {"friction": {"mu": 0.1}}})
    d = c.to_dict()
    assert d["bridge"]["mass"] == 2e8 and d["joint"]["friction"]["mu"] == 0.1
    assert d["joint"]["friction"]["normal_force"] == default.to_dict()["joint"]["friction"]["normal_force"]
    r = c.replace({"bridge.mass": 3e8, "joint": {"friction": {"v_eps": 2e-3}}})
    assert r.to_dict()["bridge"]["mass"] == 3e8
    assert r.to_dict()["joint"]["friction"] == {**d["joint"]["friction"], "v_eps": 2e-3}
    assert c.to_dict()["bridge"]["mass"] == 2e8  # unchanged


def test_bad_dict_values_are_named():
    with pytest.raises(qj.InputError, match="bridge.mass = -1"):
        qj.Config({"bridge": {"mass": -1.0}})
    with pytest.raises(qj.InputError, match="masss"):
        qj.Config().replace({"bridge.masss": 1e8})
    with pytest.raises(qj.InputError, match="joint.pitch"):
        qj.Config({"joint": {"pitch": object()}})


def test_toml_round_trip():
    c = qj.Config.from_file(ROOT / "configs" / "paper.toml")
    again = qj.Config.from_toml(c.to_toml(), base_dir=c.base_dir)
    assert again.to_dict() == c.to_dict()
    assert c.period == pytest.approx(2 * 3.141592653589793 / 6.3)


def test_a_config_keeps_its_records_after_a_change_of_directory(tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    config = qj.Config.from_file("configs/small.toml").replace({"simulation.duration": 1.0})
    assert str(config.base_dir) == str(ROOT / "configs") and config.source == "configs/small.toml (replaced)"
    assert config.replace({"bridge.mass": 2e8}).source == "configs/small.toml (replaced)"
    monkeypatch.chdir(tmp_path)
    assert qj.simulate(config, history=False).sa > 0

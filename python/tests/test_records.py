"""Records from files and arrays: the same reading, units and checks as
`quakejoint record`."""
import numpy as np
import pytest

import quakejoint as qj

from conftest import RECORD, ROOT, cli_json


def test_an_at2_file_reads_as_the_command_line_reads_it(cli):
    rec = qj.Record.read(RECORD)
    expect = cli_json(cli, "record", RECORD)
    assert rec.units == "g" and rec.format == "at2"
    assert rec.dt == expect["dt"] and len(rec) == expect["samples"]
    for key in ("pga", "pgv", "pgd", "arias", "d5_95", "t5", "t95"):
        assert rec.stats[key] == expect[key], key
    assert rec.sha256 and rec.sha256 == qj.Record.read(RECORD).sha256
    # the file holds g: 0.482787 g at its peak
    assert rec.pga == pytest.approx(0.482787 * qj.G, rel=1e-12)
    assert rec.time[-1] == pytest.approx(rec.duration)


def test_scaling_to_a_target_pga():
    rec = qj.Record.read(RECORD, target_pga_g=0.3)
    assert rec.pga == pytest.approx(0.3 * qj.G, rel=1e-12)
    assert rec.scale == pytest.approx(0.3 / 0.482787, rel=1e-12)


def test_an_array_in_g_is_converted_to_si():
    t = np.arange(0, 2, 0.01)
    a = 0.2 * np.sin(2 * np.pi * t)
    rec = qj.Record.from_array(a, 0.01, units="g", name="sine")
    np.testing.assert_array_equal(rec.acceleration, a * qj.G)
    assert rec.name == "sine" and rec.units == "g"
    gal = qj.Record.from_array(a * 980.665, 0.01, units="gal")
    np.testing.assert_allclose(gal.acceleration, rec.acceleration, rtol=1e-14, atol=1e-15)


def test_a_list_is_an_array_and_a_2d_array_is_refused():
    rec = qj.Record.from_array([0.0, 0.01, -0.02, 0.0], 0.01, units="g")
    assert rec.name == "array" and len(rec) == 4
    with pytest.raises(qj.InputError, match=r"1-D array of samples, not an array of shape \[2, 3\]"):
        qj.Record.from_array(np.zeros((2, 3)), 0.01, units="g")


def test_an_array_without_units_is_refused():
    with pytest.raises(qj.InputError, match="cannot say its units"):
        qj.Record.from_array(np.zeros(100), 0.01)


@pytest.mark.parametrize(
    "values, dt, units, words",
    [
        (np.array([0.0, np.nan, 0.1]), 0.01, "g", "not a finite number"),
        (np.full(10, 6.0), 0.01, "g", "beyond 5 g"),
        (np.zeros(10), 5.0, "g", "dt = 5 s"),
        (np.zeros(10), 0.01, "furlong/s2", "unknown variant `furlong/s2`"),
    ],
)
def test_absurd_arrays_are_refused_by_name(values, dt, units, words):
    with pytest.raises(qj.InputError, match=words):
        qj.Record.from_array(values, dt, units=units)


def test_a_missing_file_is_named(tmp_path):
    missing = tmp_path / "nope.AT2"
    with pytest.raises(qj.InputError, match="nope.AT2"):
        qj.Record.read(missing)


def test_a_text_file_needs_its_units_and_dt(tmp_path):
    path = tmp_path / "a.txt"
    path.write_text("\n".join(["0.01", "0.02", "-0.01"] * 10))
    with pytest.raises(qj.InputError, match="units"):
        qj.Record.read(path, dt=0.01)
    rec = qj.Record.read(path, dt=0.01, units="m/s2")
    assert len(rec) == 30 and rec.dt == 0.01
    with pytest.raises(qj.InputError, match="dt"):
        qj.Record.read(RECORD, dt=0.01)


def test_every_error_is_a_quakejoint_error():
    assert issubclass(qj.InputError, qj.Error) and issubclass(qj.SimulationError, qj.Error)
    assert (ROOT / "ground_motions" / "PROVENANCE.md").exists()


@pytest.mark.parametrize(
    "name, fmt",
    [
        ("CE.CLS..HGE.D.19891018.000415.C.ACC.ASC", "esm"),
        ("CLS0001910181704.EW", "knet"),
        ("CLS090.V2", "cosmos"),
    ],
)
def test_other_databases_formats_read_as_the_command_line_reads_them(cli, name, fmt):
    path = ROOT / "crates" / "motion" / "tests" / "data" / name
    rec = qj.Record.read(path)
    expect = cli_json(cli, "record", path)
    assert rec.format == fmt == expect["format"] and rec.units == expect["file_units"]
    for key in ("pga", "pgv", "arias", "d5_95"):
        assert rec.stats[key] == expect[key], key


CESMD = ROOT / "ground_motions" / "cesmd" / "CICLC.v1"


@pytest.mark.parametrize("choice", [{"channel": 2}, {"azimuth": 360}, {"azimuth": 0.0}])
def test_a_cesmd_channel_is_chosen_as_the_command_line_chooses_it(cli, choice):
    rec = qj.Record.read(CESMD, **choice)
    assert rec.format == "csmip" and rec.units == "g"
    assert rec.channel["number"] == 2 and rec.channel["of"] == 3
    assert rec.channel["orientation"] == {"kind": "azimuth", "degrees": 360.0}
    flag, value = next(iter(choice.items()))
    cmd = cli_json(cli, "record", CESMD, f"--{flag}", str(value))
    assert rec.stats["pga"] == cmd["pga"] and rec.stats["samples"] == cmd["samples"] == 32080
    assert cmd["channel"]["number"] == 2


def test_a_vertical_channel_needs_allow_vertical():
    with pytest.raises(qj.InputError, match="allow_vertical"):
        qj.Record.read(CESMD, channel=3)
    rec = qj.Record.read(CESMD, channel=3, allow_vertical=True)
    assert rec.channel["orientation"]["kind"] == "vertical"
    assert any("vertical component, read as asked" in w for w in rec.warnings)
    with pytest.raises(qj.InputError, match="no channel 4"):
        qj.Record.read(CESMD, channel=4)
    with pytest.raises(qj.InputError, match="channel"):
        qj.Record.read(RECORD, channel=1)

"""Sweep files as labelled arrays."""
import sys

import h5py
import numpy as np
import pytest

import quakejoint as qj


def test_a_sweep_reads_into_labelled_arrays(quick_sweep):
    s = qj.read_sweep(quick_sweep)
    assert s.complete
    assert s.cases == ["base"] and len(s.records) == 1
    assert s.damping.tolist() == [0.02, 0.05] and len(s.periods) == 8
    assert s["sa"].shape == (1, 1, 2, 8) and s.without_joint["sa"].shape == (1, 2, 8)
    assert s.units["sa"] == "m/s^2"
    with h5py.File(quick_sweep) as f:
        np.testing.assert_array_equal(s["sa"], f["spectrum/with_joint/sa"][()])
    reduction = 1 - s["sa"] / s.without_joint["sa"][None]
    np.testing.assert_allclose(s["reduction"], reduction, rtol=1e-12)
    c, r, z = s.index(damping=0.05)
    assert (c, r, z) == (0, 0, 1)
    # the quick sweep finishes every job inside the model's validity
    assert s.ok.all() and not s.flagged.any() and not s.failed.any()


def test_to_xarray(quick_sweep):
    xr = pytest.importorskip("xarray")
    ds = qj.read_sweep(quick_sweep).to_xarray()
    assert isinstance(ds, xr.Dataset)
    sa = ds["sa_with_joint"].sel(case="base", damping=0.05)
    assert sa.dims == ("record", "period") and sa.attrs["units"] == "m/s^2"
    assert ds["sa_without_joint"].dims == ("record", "damping", "period")


def test_not_a_sweep_file_is_refused(tmp_path):
    with pytest.raises(qj.InputError, match="no such file"):
        qj.read_sweep(tmp_path / "missing.h5")
    path = tmp_path / "other.h5"
    with h5py.File(path, "w") as f:
        f.attrs["kind"] = "simulate"
    with pytest.raises(qj.InputError, match="not a sweep file"):
        qj.read_sweep(path)


def test_a_one_record_sweep_has_the_records_own_statistics(one_record_sweep):
    """One record: count 1 where its job finished, mean = median = its value,
    dispersion (and the reductions' std) NaN: undefined for one value."""
    s = qj.read_sweep(one_record_sweep)
    with h5py.File(one_record_sweep) as f:
        assert "statistics" in f["spectrum"]  # stored for one record too
        sa = f["spectrum/with_joint/sa"][()][:, 0]  # (case, damping, period)
        alone = f["spectrum/without_joint/sa"][()][0]  # (damping, period)
        status = f["spectrum/with_joint/status"][()][:, 0]
        validity = f["spectrum/with_joint/validity"][()][:, 0]
    done = status == 0
    assert done[0].all() and not done[1].any()  # the second case stops after 5 steps
    st = s.statistics
    np.testing.assert_array_equal(st["count"], done.astype(int))
    np.testing.assert_array_equal(st["flagged"], (done & ((validity.astype(np.int64) & ~(1 << 15)) != 0)).astype(int))
    for name in ("mean", "median"):
        np.testing.assert_array_equal(st["with_joint"][name][done], sa[done])
        assert np.isnan(st["with_joint"][name][~done]).all()
        np.testing.assert_array_equal(st["without_joint"][name], alone)
        np.testing.assert_allclose(st["reduction"][name][done], (1 - sa / alone[None])[done], rtol=1e-14)
        assert np.isnan(st["reduction"][name][~done]).all()
    np.testing.assert_allclose(st["reduction"]["of_mean"][done], (1 - sa / alone[None])[done], rtol=1e-14)
    assert np.isnan(st["with_joint"]["dispersion"]).all() and np.isnan(st["without_joint"]["dispersion"]).all()
    assert np.isnan(st["reduction"]["std"]).all()
    assert st["with_joint"]["mean"].shape == (2, 2, 3) and st["without_joint"]["mean"].shape == (2, 3)


def test_the_suites_statistics_are_still_the_files(suite_sweep):
    s = qj.read_sweep(suite_sweep)
    with h5py.File(suite_sweep) as f:
        g = f["spectrum/statistics"]
        np.testing.assert_array_equal(s.statistics["with_joint"]["dispersion"], g["with_joint/dispersion"][()])
        np.testing.assert_array_equal(s.statistics["count"], g["count"][()])


def columns_of(f):
    """The dataframe's result columns from the file itself: name -> (dataset, with joint)."""
    wj, woj = f["spectrum/with_joint"], f["spectrum/without_joint"]
    special = {"status", "message", "validity", "findings"}
    out = {}
    for k in wj:
        if k not in special:
            out[f"{k}_with_joint" if k in woj else k] = (wj[k], True)
    for k in woj:
        out[f"{k}_without_joint"] = (woj[k], False)
    return out


def test_to_dataframe_has_one_row_per_job(one_record_sweep):
    pd = pytest.importorskip("pandas")
    s = qj.read_sweep(one_record_sweep)
    df = s.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    shape = (len(s.cases), len(s.records), len(s.damping), len(s.periods))
    assert len(df) == np.prod(shape) == 12
    assert list(df.columns[:4]) == ["case", "record", "damping", "period"]
    # against the file read by h5py directly: rows in the order of the
    # file's arrays (case, record, damping, period), the last fastest
    with h5py.File(one_record_sweep) as f:
        sp = f["spectrum"]
        labels = np.meshgrid(
            [v.decode() for v in sp["case"][()]],
            [v.decode() for v in sp["record"][()]],
            sp["damping"][()],
            sp["period"][()],
            indexing="ij",
        )
        for name, values in zip(("case", "record", "damping", "period"), labels):
            assert df[name].tolist() == values.ravel().tolist(), name
        columns = columns_of(f)
        for name, (ds, with_joint) in columns.items():
            values = ds[()] if with_joint else np.broadcast_to(ds[()][None], shape)
            np.testing.assert_array_equal(df[name].to_numpy(), values.ravel(), err_msg=name)
            assert df.attrs["units"][name] == ds.attrs["units"].decode(), name
        wj = f["spectrum/with_joint"]
        np.testing.assert_array_equal(df["reduction"].to_numpy(), sp["reduction"][()].ravel())
        np.testing.assert_array_equal(df["status"].to_numpy(), wj["status"][()].ravel())
        np.testing.assert_array_equal(df["validity"].to_numpy(), wj["validity"][()].ravel())
        assert df["message"].tolist() == [m.decode() for m in wj["message"][()].ravel()]
        assert df["findings"].tolist() == [m.decode() for m in wj["findings"][()].ravel()]
    assert set(df.columns) == {"case", "record", "damping", "period", "reduction", "status", "validity", "message",
                               "findings", *columns}
    assert df.attrs["units"]["period"] == "s" and df.attrs["units"]["reduction"] == "1"
    # against the Sweep's own arrays, job by job
    for c, case in enumerate(s.cases):
        for z, damping in enumerate(s.damping):
            for t, period in enumerate(s.periods):
                row = df[(df.case == case) & (df.damping == damping) & (df.period == period)]
                assert len(row) == 1
                row = row.iloc[0]
                np.testing.assert_array_equal(row["sa_with_joint"], s["sa"][c, 0, z, t])
                assert row["sa_without_joint"] == s.without_joint["sa"][0, z, t]
                assert row["status"] == s.status[c, 0, z, t] and row["message"] == s.message[c, 0, z, t]
    failed = df[df.status != 0]
    assert len(failed) == 6 and (failed.case == "few steps").all() and failed["sa_with_joint"].isna().all()
    assert failed["message"].str.contains("step limit of 5 steps").all()


def test_a_missing_extra_is_named(quick_sweep, monkeypatch):
    s = qj.read_sweep(quick_sweep)
    monkeypatch.setitem(sys.modules, "xarray", None)
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError) as e:
        s.to_xarray()
    assert 'pip install "quakejoint[xarray]"' in str(e.value) and 'pip install ".[xarray]"' in str(e.value)
    with pytest.raises(ImportError) as e:
        s.to_dataframe()
    assert 'pip install "quakejoint[pandas]"' in str(e.value) and 'pip install ".[pandas]"' in str(e.value)


def test_a_modal_sweep_reads_with_its_period_scales_and_joints(modal_sweep):
    """A bridge given by its modes is swept by a factor on its periods: the
    last axis is the factor (not a period), each case has its own bridge
    alone, and every joint is read by name, the first one's own values
    beside the run's (its sub-gaps are the per-job ones; the friction
    energies of the two joints add up to the system's)."""
    s = qj.read_sweep(modal_sweep)
    assert s.dims == ("case", "record", "damping", "period_scale")
    np.testing.assert_array_equal(s.period_scales, [0.8, 1.25])
    np.testing.assert_allclose(s.periods, 0.7368132859282219 * s.period_scales, rtol=1e-14)
    assert s["sa"].shape == s.without_joint["sa"].shape == (2, 1, 1, 2)
    assert not np.array_equal(s.without_joint["sa"][0], s.without_joint["sa"][1]), "3 modes against all"
    np.testing.assert_array_equal(s.reduction, 1 - s["sa"] / s.without_joint["sa"])
    assert list(s.joints) == ["left", "right"]
    np.testing.assert_array_equal(s.joints["left"]["max_subgap"], s["max_subgap"])
    np.testing.assert_allclose(
        s.joints["left"]["friction_energy"] + s.joints["right"]["friction_energy"], s["friction_energy"], rtol=1e-12
    )
    assert s.joints["right"]["max_subgap"].shape == (2, 1, 1, 2) and (s.joints["right"]["validity"] == 0).all()
    with h5py.File(modal_sweep) as f:
        assert "period" not in f["spectrum"]
        np.testing.assert_array_equal(s.joints["right"]["peak_joint_force"], f["joints/1/peak_joint_force"][()])
    pd = pytest.importorskip("pandas")
    df = s.to_dataframe()
    assert isinstance(df, pd.DataFrame) and len(df) == 4
    assert list(df.columns[:5]) == ["case", "record", "damping", "period_scale", "longest_period"]
    np.testing.assert_array_equal(df["right:sa"].to_numpy(), s.joints["right"]["sa"].ravel())
    np.testing.assert_array_equal(df["sa_without_joint"].to_numpy(), s.without_joint["sa"].ravel())
    xr = pytest.importorskip("xarray")
    ds = s.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert ds["sa_with_joint"].dims == s.dims and ds["sa_without_joint"].dims == s.dims
    np.testing.assert_array_equal(ds["longest_period"].values, s.periods)

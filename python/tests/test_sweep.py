"""Sweep files as labelled arrays."""
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

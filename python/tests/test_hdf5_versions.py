"""Files written by the command (the system's libhdf5, 1.10 on Debian 12)
read by h5py (its own bundled HDF5, 2.0 with h5py 3.16), bit for bit.

The command writes the HDF5 1.10 file format; h5py's library reads it.
Every dataset of a run file and of a sweep file is read, and the numbers
are compared with what the command itself reports (`simulate --json`),
so a difference between the two libraries in how they read a value
would show. docs/hdf5-layout.md, "Checksums".
"""
import json

import h5py
import numpy as np

from conftest import ROOT, run_cli


def every_dataset(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
        superblock = f.id.get_create_plist().get_version()[0]
    return out, superblock


def test_a_run_file_reads_the_same_in_h5py(cli, short_config, tmp_path):
    out = tmp_path / "run.h5"
    code, stdout, _ = run_cli(cli, "simulate", short_config, "--period", "1.2", "--output", out, "--json")
    reported = json.loads(stdout)
    data, superblock = every_dataset(out)
    assert superblock >= 2, "the HDF5 1.10 file format (checksummed metadata)"
    print(f"h5py {h5py.version.version} with HDF5 {h5py.version.hdf5_version}: {len(data)} datasets read")
    scalars = {name.split("/", 1)[1]: v for name, v in data.items() if name.startswith("result/")}
    assert len(scalars) > 20
    compared = 0
    for name, value in scalars.items():
        if name in reported and isinstance(reported[name], float):
            assert np.float64(value).tobytes() == np.float64(reported[name]).tobytes() or (
                np.isnan(value) and np.isnan(reported[name])
            ), name
            compared += 1
    assert compared > 20, compared
    assert data["history/t"].shape == data["history/a_abs"].shape


def test_a_sweep_file_reads_the_same_in_h5py(quick_sweep):
    data, _ = every_dataset(quick_sweep)
    with h5py.File(quick_sweep, "r") as f:
        text = f["spectrum/case"].asstr()[()]
        assert list(text) == ["base"]
        assert f["spectrum/with_joint/message"].dtype.kind == "S", "fixed-length text, under the checksum"
    sa, without = data["spectrum/with_joint/sa"], data["spectrum/without_joint/sa"]
    # the reduction the command stored is the one h5py's numbers give
    np.testing.assert_array_equal(data["spectrum/reduction"], 1.0 - sa / without[np.newaxis])
    assert all(np.isfinite(v).all() for k, v in data.items() if k.endswith("acceleration"))

"""A bit flipped in any dataset of a finished sweep is reported or repaired.

A sweep of two records scaled as a small suite (so that the file holds
statistics, a suite and histories besides the spectra) is run once. Then,
for every dataset of its output in turn, one bit of the dataset's stored
bytes is flipped in a copy (the chunk of a chunked dataset, the value
inside the object header of a compact scalar), and

- `quakejoint compare` refuses the copy, naming the dataset;
- `quakejoint sweep --check` says the output is damaged and that a run
  rebuilds it from its journal, naming the dataset;
- running the sweep again rebuilds it from the journal (the notice names
  the dataset), after which `compare` finds it identical to the original;
- h5py (the HDF5 library Python uses) refuses to read the dataset, and
  `quakejoint.read_sweep` refuses the file, naming the dataset.

A dataset rewritten consistently (valid checksum, wrong value) is caught
by checking what is derived against what it is derived from.
"""
import re
import shutil

import h5py
import numpy as np
import pytest

import quakejoint as qj

from conftest import ROOT, SMALL_JOINT, run_cli

GM = ROOT / "ground_motions"
CONFIG = SMALL_JOINT + f"""
[simulation]
duration = 2.0
[sweep]
periods = [0.3, 1.0]
damping = [0.05]
histories = [1.0]
records = [
  {{ file = "{GM / 'RSN753_LOMAP_CLS090-hor2.AT2'}" }},
  {{ file = "{GM / 'RSN6_IMPVALL.I_I-ELC180-hor1.AT2'}" }},
]
[sweep.suite]
target = {{ code = "ec8", type = 1, ground = "C", ag_g = 0.05 }}
range = [0.2, 2.0]
rule = "check"
"""


@pytest.fixture(scope="module")
def finished(cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("damage")
    config = d / "suite.toml"
    config.write_text(CONFIG)
    out = d / "good.h5"
    run_cli(cli, "sweep", config, "--output", out, "--progress", "none")
    return config, out


def datasets(path):
    names = []
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return names


def stored_byte(path, name):
    """The file offset of one byte of `name`'s stored data."""
    with h5py.File(path, "r") as f:
        ds = f[name]
        layout = ds.id.get_create_plist().get_layout()
        if layout == h5py.h5d.CHUNKED:
            info = ds.id.get_chunk_info(0)
            return info.byte_offset + info.size // 2
        if layout == h5py.h5d.CONTIGUOUS:
            return ds.id.get_offset() + ds.id.get_storage_size() // 2
        # compact: the value is inside the dataset's object header
        raw = np.asarray(ds[()]).tobytes()
        start = h5py.h5o.get_info(ds.id).addr
    blob = path.read_bytes()
    return blob.index(raw, start) + len(raw) // 2


def damaged_copy(good, name, where):
    """A copy of the sweep (output and journal) in `where` with one bit of
    `name` flipped."""
    where.mkdir()
    out = where / "out.h5"
    shutil.copy(good, out)
    shutil.copy(str(good) + ".journal", str(out) + ".journal")
    at = stored_byte(good, name)
    with open(out, "r+b") as f:
        f.seek(at)
        byte = f.read(1)[0]
        f.seek(at)
        f.write(bytes([byte ^ 0x10]))
    return out


def test_every_dataset_is_covered(finished):
    names = datasets(finished[1])
    for group in ("spectrum/statistics/", "suite/", "histories/", "records/", "inputs/records/"):
        assert any(n.startswith(group) for n in names), group
    with h5py.File(finished[1], "r") as f:
        for name in names:
            ds = f[name]
            if ds.shape == ():
                assert ds.id.get_create_plist().get_layout() == h5py.h5d.COMPACT, name
            else:
                assert ds.fletcher32, f"{name} has no checksum"
                assert ds.dtype.kind != "O", f"{name}: variable-length text is outside the checksum"


def test_a_bit_flipped_in_any_dataset_is_reported_and_repaired(cli, finished, tmp_path):
    config, good = finished
    names = datasets(good)
    assert len(names) > 60, names
    for i, name in enumerate(names):
        out = damaged_copy(good, name, tmp_path / f"d{i}")
        label = "/" + name
        code, stdout, stderr = run_cli(cli, "compare", good, out, check=False)
        assert code != 0 and label in stdout + stderr, f"compare missed {name}: {stdout}{stderr}"
        code, stdout, stderr = run_cli(cli, "sweep", config, "--check", "--output", out, check=False)
        assert code == 0 and label in stderr and "a run rebuilds it from the journal" in stderr, (name, stderr)
        with pytest.raises((OSError, KeyError)):
            with h5py.File(out, "r") as f:
                f[name][()]
        with pytest.raises(qj.InputError, match=label):
            qj.read_sweep(out)
        code, stdout, stderr = run_cli(cli, "sweep", config, "--output", out, "--progress", "none", check=False)
        assert code == 0 and label in stderr and "rebuilt from the journal" in stderr, (name, stderr)
        code, stdout, stderr = run_cli(cli, "compare", good, out, check=False)
        assert code == 0, f"not repaired after {name}: {stdout}{stderr}"


@pytest.mark.parametrize(
    "name, change",
    [
        ("spectrum/reduction", lambda a: a + 1.0),
        ("spectrum/statistics/with_joint/mean", lambda a: a * 2.0),
        ("histories/job_1/period", lambda a: a + 0.5),
        ("records/RSN753_LOMAP_CLS090-hor2/pga", lambda a: a * 1.1),
        ("inputs/records/RSN753_LOMAP_CLS090-hor2/scale", lambda a: a * 1.1),
    ],
)
def test_a_value_rewritten_with_a_valid_checksum_is_caught(cli, finished, tmp_path, name, change):
    config, good = finished
    out = tmp_path / "edited.h5"
    shutil.copy(good, out)
    shutil.copy(str(good) + ".journal", str(out) + ".journal")
    with h5py.File(out, "r+") as f:
        f[name][()] = change(f[name][()])
    code, stdout, stderr = run_cli(cli, "compare", good, out, check=False)
    assert code != 0 and "does not match" in stderr, stderr
    code, stdout, stderr = run_cli(cli, "sweep", config, "--check", "--output", out, check=False)
    assert "does not match" in stderr and "a run rebuilds it" in stderr, stderr
    code, stdout, stderr = run_cli(cli, "sweep", config, "--output", out, "--progress", "none", check=False)
    assert code == 0 and "rebuilt from the journal" in stderr, stderr
    assert run_cli(cli, "compare", good, out, check=False)[0] == 0


def attribute_texts(path):
    """(object, attribute, text) of every text attribute of the file that is
    long enough to be found once in its bytes."""
    out = []
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            for key, value in obj.attrs.items():
                if isinstance(value, bytes) and len(value) >= 12:
                    out.append((name, key, value))
        visit("/", f)
        f.visititems(visit)
    return out


def test_a_bit_flipped_in_the_text_of_any_attribute_is_reported_and_repaired(cli, finished, tmp_path):
    """The text of every attribute (the config, the command, the provenance,
    units, meanings) is under HDF5's metadata checksums: a flipped bit in
    it is refused by every reader, named, and rebuilt by a rerun. (Files of
    schema 11 kept it in the global heap, which has no checksum: one byte
    there made 10 of 17 root attributes unreadable while every reader said
    "fine".)"""
    config, good = finished
    blob = good.read_bytes()
    texts = attribute_texts(good)
    assert len(texts) > 20, texts
    for i, (name, key, value) in enumerate(texts):
        # every copy of the text (HDF5 may leave a stale copy in space it
        # freed while writing, where a flip changes nothing)
        copies = [m.start() for m in re.finditer(re.escape(value), blob)]
        assert copies, f"{name} attribute {key}: its text is not stored in the file as written"
        d = tmp_path / f"a{i}"
        d.mkdir()
        out = d / "out.h5"
        shutil.copy(good, out)
        shutil.copy(str(good) + ".journal", str(out) + ".journal")
        with open(out, "r+b") as f:
            for at in copies:
                f.seek(at + len(value) // 2)
                byte = f.read(1)[0]
                f.seek(at + len(value) // 2)
                f.write(bytes([byte ^ 0x04]))
        code, stdout, stderr = run_cli(cli, "compare", good, out, check=False)
        assert code != 0 and "damaged" in stdout + stderr, f"compare missed {name}@{key}: {stdout}{stderr}"
        with pytest.raises(qj.InputError, match="not a readable sweep file"):
            qj.read_sweep(out)
        code, stdout, stderr = run_cli(cli, "sweep", config, "--output", out, "--progress", "none", check=False)
        assert code == 0 and "rebuilt from the journal" in stderr, (name, key, stderr)
        assert run_cli(cli, "compare", good, out, check=False)[0] == 0, f"not repaired after {name}@{key}"


@pytest.mark.parametrize(
    "name, change",
    [
        ("median_lo", lambda a: a * 0.9),
        ("annual_frequency_hi", lambda a: a * 1.1),
        ("fragility/hazard_frequency", lambda a: a * 2.0),
        ("fragility/hazard_intensity", lambda a: a * 1.5),
    ],
)
def test_a_fragility_value_rewritten_with_a_valid_checksum_is_caught(cli, stripes_sweep, tmp_path, name, change):
    """The bootstrap's intervals are not resampled on reading (its inputs'
    key says they are the file's): a rewritten interval breaks the check
    that sums up the key with what is stored for it. The hazard curve's
    arrays are checked against the config's."""
    out = tmp_path / "edited.h5"
    shutil.copy(stripes_sweep, out)
    with h5py.File(out, "r+") as f:
        if not name.startswith("fragility/"):
            # an interval of a limit state that has one
            fr = f["fragility"]
            key = next(k for k in fr if isinstance(fr[k], h5py.Group) and name in fr[k] and np.isfinite(fr[k][name][()]).any())
            name = f"fragility/{key}/{name}"
        a = f[name][()]
        f[name][()] = np.where(np.isfinite(a), change(a), a)
    code, stdout, stderr = run_cli(cli, "compare", stripes_sweep, out, check=False)
    assert code != 0 and "does not match" in stderr, (name, stderr)
    with pytest.raises(qj.InputError, match="does not match"):
        qj.read_sweep(out)

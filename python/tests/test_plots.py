"""Every plotting script rendered from real outputs, and what it draws
checked: axes, series, labels, units, marked failures."""
import importlib
import json
import shutil
import subprocess
import sys

import h5py
import matplotlib
import numpy as np
import pytest

import quakejoint as qj
from conftest import ROOT, run_cli

matplotlib.use("Agg")
sys.path.insert(0, str(ROOT / "scripts"))
G = 9.80665


def script(name):
    return importlib.import_module(name)


def labels(ax):
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend else []


def line(ax, label):
    found = [ln for ln in ax.get_lines() if ln.get_label() == label]
    assert found, f"no series `{label}` in {[ln.get_label() for ln in ax.get_lines()]}"
    return found[0]


def tick_labels(ax):
    return [t.get_text() for t in ax.get_xticklabels() if t.get_text()]


@pytest.fixture()
def damaged_sweep(quick_sweep, tmp_path):
    """The quick sweep with one job marked failed and one flagged (a
    collision), as a crashed run and a colliding one leave them."""
    path = tmp_path / "damaged.h5"
    shutil.copy(quick_sweep, path)
    with h5py.File(path, "r+") as f:
        w = f["spectrum/with_joint"]
        status, sa, validity = w["status"][()], w["sa"][()], w["validity"][()]
        status[0, 0, 0, 2], sa[0, 0, 0, 2], validity[0, 0, 0, 2] = 1, np.nan, 1 << 15
        validity[0, 0, 1, 3] = 1
        w["status"][...], w["sa"][...], w["validity"][...] = status, sa, validity
    return path


def test_spectrum_draws_every_damping_with_and_without_the_joint(quick_sweep):
    fig = script("plot_spectrum").figure(quick_sweep)
    axes = fig.axes
    assert len(axes) == 4  # 2 damping ratios x (Sa, reduction)
    with h5py.File(quick_sweep) as f:
        periods = f["spectrum/period"][()]
        sa = f["spectrum/with_joint/sa"][()]
        without = f["spectrum/without_joint/sa"][()]
    ax, axr = axes[0], axes[1]
    assert ax.get_xlabel() == "bridge period T [s]" and ax.get_ylabel() == "Sa [m/s$^2$]"
    assert "damping 0.02" in ax.get_title()
    np.testing.assert_array_equal(line(ax, "without joint (exact)").get_ydata(), without[0, 0])
    np.testing.assert_array_equal(line(ax, "with joint").get_xdata(), periods)
    np.testing.assert_array_equal(line(ax, "with joint").get_ydata(), sa[0, 0, 0])
    assert axr.get_ylabel().startswith("reduction of Sa")
    assert tick_labels(ax) == ["0.2", "0.5", "1", "2"]


def test_spectrum_in_g(quick_sweep):
    ax = script("plot_spectrum").figure(quick_sweep, in_g=True).axes[0]
    assert ax.get_ylabel() == "Sa [g]"
    with h5py.File(quick_sweep) as f:
        np.testing.assert_allclose(line(ax, "with joint").get_ydata(), f["spectrum/with_joint/sa"][0, 0, 0] / G)


def test_failed_and_flagged_jobs_are_marked_not_dropped(damaged_sweep):
    fig = script("plot_spectrum").figure(damaged_sweep)
    ax0, ax1 = fig.axes[0], fig.axes[2]
    failed = line(ax0, "failed (1 jobs)")
    with h5py.File(damaged_sweep) as f:
        periods = f["spectrum/period"][()]
    assert failed.get_xdata().tolist() == [periods[2]] and failed.get_ydata().tolist() == [0.0]
    assert len(line(ax0, "with joint").get_xdata()) == len(periods) - 1
    flagged = line(ax1, "flagged: collision")
    assert flagged.get_xdata().tolist() == [periods[3]]
    assert flagged.get_markerfacecolor() == "none"


def test_a_study_is_drawn_against_its_parameter(study_sweep):
    fig = script("plot_spectrum").figure(study_sweep)  # few periods, several cases: the study view
    ax, axr = fig.axes
    assert ax.get_xlabel() == "joint.friction.mu" and ax.get_ylabel() == "Sa [m/s$^2$]"
    with h5py.File(study_sweep) as f:
        sa = f["spectrum/with_joint/sa"][()]
        without = f["spectrum/without_joint/sa"][()]
    for t, period in enumerate([0.6, 1.2]):
        series = line(ax, f"with joint, T = {period:.3g} s")
        np.testing.assert_array_equal(series.get_xdata(), [0.02, 0.05, 0.2, 0.5])
        np.testing.assert_array_equal(series.get_ydata(), sa[:, 0, 0, t])
        ref = line(ax, f"without joint, T = {period:.3g} s")
        assert ref.get_ydata()[0] == without[0, 0, t]
    assert ax.get_xscale() == "log" and tick_labels(ax) == ["0.02", "0.05", "0.1", "0.2", "0.5"]
    assert labels(axr) == ["T = 0.6 s", "T = 1.2 s"]


def test_history_panels_of_a_run(run_h5):
    run, _ = run_h5
    fig = script("plot_history").figure(run)
    ax, axd, axf, axg, axc = fig.axes
    with h5py.File(run) as f:
        h = {k: f["history"][k][()] for k in ("t", "a_abs", "a_abs_without_joint", "joint_force", "subgaps")}
    np.testing.assert_array_equal(line(ax, "with joint").get_ydata(), h["a_abs"])
    np.testing.assert_array_equal(line(axd, "with - without").get_ydata(), h["a_abs"] - h["a_abs_without_joint"])
    np.testing.assert_allclose(axf.get_lines()[0].get_ydata(), 1e-3 * h["joint_force"])
    assert axf.get_ylabel() == "joint force [kN]" and axg.get_ylabel() == "sub-gap [mm]"
    assert len([ln for ln in axg.get_lines() if ln.get_label().startswith("sub-gap")]) == 4
    assert "T = 1.2 s" in ax.get_title()
    assert axc.get_ylabel() == "contact force [kN]"
    assert fig.axes[-1].get_xlabel() == "t [s]"


@pytest.fixture(scope="module")
def opening_beyond_capacity(cli, tmp_path_factory):
    """configs/small.toml: under the full record a cell opens beyond the
    80 mm capacity (the run is flagged capacity_exceeded)."""
    out = tmp_path_factory.mktemp("capacity") / "small.h5"
    run_cli(cli, "simulate", ROOT / "configs" / "small.toml", "--output", out)
    return out


def test_the_sub_gap_panel_shows_the_governing_opening_and_the_capacity(opening_beyond_capacity):
    fig = script("plot_history").figure(opening_beyond_capacity)
    axg = fig.axes[3]
    with h5py.File(opening_beyond_capacity) as f:
        narrow, wide = f["history/subgaps"][()], f["history/subgaps_wide"][()]
        largest, smallest = f["result/max_subgap"][()], f["result/min_subgap"][()]
        assert "capacity_exceeded" in f.attrs["validity_label"].decode()
    # the run's reported extremes are in the stored histories: the wider end
    # holds the opening the run is flagged for, the narrower the closing
    assert wide.max() == largest and narrow.min() == smallest and (wide >= narrow).all()
    solid = [ln for ln in axg.get_lines() if ln.get_label().startswith("sub-gap")]
    dotted = [ln for ln in axg.get_lines() if ln.get_linestyle() == ":"]
    for k, (s, d) in enumerate(zip(solid, dotted)):
        np.testing.assert_allclose(s.get_ydata(), 1e3 * wide[k])
        np.testing.assert_allclose(d.get_ydata(), 1e3 * narrow[k])
    assert max(ln.get_ydata().max() for ln in solid) == pytest.approx(1e3 * largest)
    cap = line(axg, "capacity 80 mm")
    assert list(cap.get_ydata()) == [80.0, 80.0]
    notes = [t.get_text() for t in axg.texts]
    assert any(f"opens to {1e3 * largest:.1f} mm" in t for t in notes), notes
    assert axg.get_ylim()[1] > 1e3 * largest, "the largest opening is inside the panel"
    assert all(t.get_fontsize() >= 8 for t in axg.get_legend().get_texts()), "a readable legend"


def test_a_run_without_the_joint_says_so(run_h5):
    _, alone = run_h5
    fig = script("plot_history").figure(alone)
    assert len(fig.axes) == 1
    ax = fig.axes[0]
    assert labels(ax) == ["without joint (exact)"] and "bridge alone" in ax.get_title()


def test_sweep_histories_in_job_order_and_a_window(quick_sweep):
    fig = script("plot_history").figure(quick_sweep, window=(2.0, 6.0), in_g=True)
    titles = [a.get_title() for a in fig.axes if "damping" in a.get_title()]
    assert [("0.02" in t, "0.05" in t) for t in titles] == [(True, False), (False, True)]  # job_4, job_12
    assert fig.axes[0].get_xlim() == (2.0, 6.0) and fig.axes[0].get_ylabel() == "deck abs. acc. [g]"


def test_the_service_loop(service_h5):
    fig = script("plot_service").figure(service_h5)
    ax, axb = fig.axes
    assert ax.get_xlabel() == "deck opening u [mm]" and ax.get_ylabel() == "force of the joint on the deck [kN]"
    with h5py.File(service_h5) as f:
        work = f["service/loop_work_per_cycle"][()]
        u, force, t, period = (f["service"][k][()] for k in ("u", "joint_force", "t", "period"))
    last = [ln for ln in ax.get_lines() if ln.get_label().startswith("last cycle")][0]
    assert f"loop area {1e-3 * work:.1f} kJ" in last.get_label()
    # the drawn loop is the last cycle, and its area is the reported work
    x, y = np.asarray(last.get_xdata()) * 1e-3, np.asarray(last.get_ydata()) * 1e3
    trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy < 2 has only trapz
    assert abs(abs(trapezoid(y, x)) - work) <= 0.02 * work
    assert len(last.get_xdata()) == int(np.sum(t >= t[-1] - period * (1 + 1e-9)))
    assert "cycle 1" in labels(ax)
    assert "deck opening" in labels(axb)


def test_geometry_sparsity_and_scaling(cli, tmp_path):
    _, out, _ = run_cli(cli, "model", ROOT / "configs" / "small.toml", "--json")
    (tmp_path / "model.json").write_text(out)
    model = json.loads(out)
    ax = script("plot_geometry").figure(tmp_path / "model.json").axes[0]
    assert f"{model['center_beams']} center beams" in ax.get_title()
    assert set(labels(ax)) >= {"center beams", "bearings", "guide"}
    run_cli(cli, "model", ROOT / "configs" / "small.toml", "--sparsity", tmp_path / "s.h5")
    ax = script("plot_sparsity").figure(tmp_path / "s.h5").axes[0]
    assert f"{model['coordinates']} coordinates" in ax.get_title()
    rows = [
        {"nc": nc, "coordinates": 34 * nc, "steps": 100, "newton_iterations": 150, "wall_time_s": 1e-4 * nc}
        for nc in (3, 9, 27, 81)
    ]
    (tmp_path / "scaling.json").write_text(json.dumps(rows))
    ax = script("plot_scaling").figure(tmp_path / "scaling.json").axes[0]
    np.testing.assert_allclose(line(ax, "per step").get_ydata(), [1e-6 * nc / 100 * 1e6 * 100 for nc in (3, 9, 27, 81)])


@pytest.mark.parametrize(
    "values, expect",
    [([0.3, 0.5], ["0.3", "0.5"]), ([0.1, 5.0], ["0.1", "0.2", "0.5", "1", "2", "5"]), ([2e4, 5e6], None)],
)
def test_log_ticks_stay_readable_on_short_ranges(values, expect):
    import matplotlib.pyplot as plt

    from plotlib import log_ticks

    fig, ax = plt.subplots()
    ax.set_xscale("log")
    ax.plot(values, values)
    log_ticks(ax, values)
    got = tick_labels(ax)
    assert len(got) >= 2 and len(set(got)) == len(got)
    if expect:
        assert set(expect) <= set(got)
    else:
        assert all(len(t) <= 4 for t in got), got  # 20k, 50k, 100k, 1M: no 500000 running into 1e+06
    plt.close(fig)


def test_the_scripts_run_from_the_command_line(quick_sweep, tmp_path):
    out = tmp_path / "spectrum.png"
    p = subprocess.run([sys.executable, str(ROOT / "scripts" / "plot_spectrum.py"), str(quick_sweep), str(out), "--g"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 10_000


def test_an_incomplete_file_says_so(quick_sweep, study_sweep, tmp_path):
    for src, name in [(quick_sweep, "quick.h5"), (study_sweep, "study.h5")]:
        path = tmp_path / name
        shutil.copy(src, path)
        with h5py.File(path, "r+") as f:
            f.attrs["complete"] = np.uint8(0)
        fig = script("plot_spectrum").figure(path)
        assert "INCOMPLETE" in fig.axes[0].get_title(), name


def test_bridge_draws_each_joint_and_the_points(two_joints):
    _, path = two_joints
    fig = script("plot_bridge").figure(path)
    ax_u, ax_f, ax_g, ax_t = fig.axes
    with h5py.File(path) as f:
        u_left = f["history/u"][()]
        u_right = f["joints/1/history/u"][()]
        force_right = f["joints/1/history/joint_force"][()]
        names = [n.decode() for n in f["points/name"][()]]
        sd = f["points/sd"][()]
    assert labels(ax_u) == ["left abutment", "right abutment"]
    np.testing.assert_allclose(line(ax_u, "left abutment").get_ydata(), u_left * 1e3)
    np.testing.assert_allclose(line(ax_u, "right abutment").get_ydata(), u_right * 1e3)
    np.testing.assert_allclose(line(ax_f, "right abutment").get_ydata(), force_right / 1e3)
    assert "capacity 80 mm" in labels(ax_g)
    assert ax_u.get_ylabel().startswith("deck point u [mm]")
    cells = {(r, c): t.get_text().get_text() for (r, c), t in ax_t.tables[0].get_celld().items()}
    assert [cells[(r + 1, 0)] for r in range(len(names))] == names
    assert cells[(1, 1)] == f"{sd[0] * 1e3:.1f}"


def test_bridge_refuses_a_single_dof_run(run_h5):
    run, _ = run_h5
    with pytest.raises(SystemExit, match="not a run of a bridge given by its modes"):
        script("plot_bridge").figure(run)


def test_fragility_draws_a_panel_per_limit_state_with_its_fit(stripes_sweep):
    s = qj.read_sweep(stripes_sweep)
    fig = script("plot_fragility").figure(stripes_sweep, hazard=True)
    titles = [ax.get_title() for ax in fig.axes]
    for ls in s.fragility.limit_states.values():
        assert any(ls.name in t for t in titles), (ls.name, titles)
        ax = next(ax for ax in fig.axes if ls.name in ax.get_title())
        # the stripes' fractions are points at the levels
        xs = np.concatenate([np.asarray(line.get_xdata(), float) for line in ax.get_lines()] or [np.array([])])
        assert set(np.round(s.fragility.levels, 6)) <= set(np.round(xs, 6)), ls.name
        if np.isfinite(ls.median[0, 0, 0]):
            # the fitted curve passes 0.5 at the median
            curve = max(ax.get_lines(), key=lambda line: len(line.get_xdata()))
            x, y = np.asarray(curve.get_xdata(), float), np.asarray(curve.get_ydata(), float)
            assert abs(np.interp(ls.median[0, 0, 0], x, y) - 0.5) < 0.02, ls.name
    assert any("hazard" in ax.get_title().lower() or ax.get_xscale() == "log" for ax in fig.axes)


def test_the_design_is_read_and_drawn_from_the_curves(design_sweep):
    s = qj.read_sweep(design_sweep)
    [d] = s.design
    assert d.candidates == ["3 beams", "3 beams, fuse"] and d.cells == [4, 4]
    assert d.fuse[0] == "none" and d.fuse[1].startswith("box 200 kN")
    assert d.checked.shape == d.passed.shape == (2, 2)
    for c in range(2):
        for k, (key, _, target) in enumerate(d.targets):
            hi = s.fragility[key].annual_frequency_hi[c, 0, 0]
            if np.isfinite(hi):
                assert d.checked[c, k] == hi, (c, key)
            assert d.passed[c, k] == (d.checked[c, k] <= target), (c, key)
    # the joint without a fuse cannot break one
    assert d.checked[0, 1] == 0 and d.passed[0, 1]
    passing = [c for c in range(2) if d.passed[c].all()]
    assert d.recommended == (d.candidates[passing[0]] if passing else None)
    fig = script("plot_design").figure(design_sweep)
    titles = [ax.get_title() for ax in fig.axes]
    assert all(any(name in t for t in titles) for _, name, _ in d.targets), titles
    verdict = fig._suptitle.get_text()
    assert (f"recommended: {d.recommended}" in verdict) if d.recommended else ("no candidate" in verdict)


def test_the_main_jobs_headline_is_the_files_numbers(quick_sweep):
    """scripts/headline.py (the main job's last words) quotes Sa with and
    without the joint at the period nearest 1 s, as the file holds them."""
    import headline

    text = headline.headline(str(quick_sweep))
    with h5py.File(quick_sweep, "r") as f:
        s = f["spectrum"]
        t = int(np.argmin(np.abs(s["period"][:] - 1.0)))
        without, with_ = s["without_joint/sa"][0, 0, t], s["with_joint/sa"][0, 0, 0, t]
    assert f"Sa {without:.3f} m/s^2 without the joint, {with_:.3f} with it" in text, text

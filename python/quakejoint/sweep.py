"""Sweep files (`quakejoint sweep`, `quakejoint merge`) as labelled arrays.

A job is one (case, record, damping, period); results with the joint have
the dimensions ("case", "record", "damping", "period"), the exact spectra
without it ("record", "damping", "period"). A sweep over a bridge given by
its modes sweeps a factor on every period of its modes instead: its last
dimension is "period_scale" (`Sweep.period_scales`; `Sweep.periods` holds
the bridge's longest kept period at each scale), its bridge alone has the
case dimension too, and `Sweep.joints` holds the values of its joints after
the first. Layout: docs/hdf5-layout.md.
`Sweep.to_xarray()` needs the extra `xarray`, `Sweep.to_dataframe()` the
extra `pandas` (`pip install "quakejoint[xarray,pandas]"`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import math

import numpy as np

from ._quakejoint import InputError, read_sweep_file

#: dimensions of the results with the joint
DIMS = ("case", "record", "damping", "period")
#: the `not_checked` bit of the validity flags
NOT_CHECKED = 1 << 15


@dataclass(repr=False)
class Sweep:
    """The results of a sweep file.

    `with_joint[name]` has shape (case, record, damping, period) and
    `without_joint[name]` (record, damping, period); `units[name]` gives the
    units. `status` (0 ok, 1 failed, 2 invalid parameters, 3 time or step
    limit, -1 not run), `message` (why a job failed), `validity` (bit set,
    `flag_names`), `findings` and `reduction` = 1 - Sa with / Sa without.
    Jobs that failed or did not run hold NaN. `complete` is False for a
    checkpoint of a running sweep, an interrupted one or a partial merge.

    A sweep over a bridge given by its modes (`period_scales` not None):
    the last dimension is the period scale, `periods` the bridge's longest
    kept period at each scale [s], `without_joint[name]` has the shape of
    the results with the joint (each case's bridge alone: a case may keep
    other modes), and `joints[name]` holds every joint's values by field
    (`sa`, `peak_joint_force`, `friction_energy`, `max_subgap`, ...,
    `validity`), each of the results' shape (a file written before schema
    13 holds the joints after the first only).
    """

    path: str
    cases: list[str]
    records: list[str]
    damping: np.ndarray
    periods: np.ndarray
    with_joint: dict[str, np.ndarray]
    without_joint: dict[str, np.ndarray]
    units: dict[str, str]
    status: np.ndarray
    message: np.ndarray
    validity: np.ndarray
    findings: np.ndarray
    reduction: np.ndarray
    flag_names: list[tuple[int, str]]
    attrs: dict = field(default_factory=dict)
    #: over the records, per (case, damping, period) ((damping, period)
    #: without the joint): {"with_joint": {"mean", "median", "dispersion"},
    #: "without_joint": {...}, "reduction": {"mean", "median", "std",
    #: "of_mean"}, "count", "flagged"}. For a sweep of one record the
    #: record's own values: count 1 where its job finished (0 and NaN
    #: elsewhere), mean = median = the value, dispersion and std NaN
    #: (undefined for one value).
    statistics: Optional[dict] = None
    #: the suite's target and scaling: target (in words), rule, range [s],
    #: factor (per record), rule_factor, min_ratio, min_ratio_period [s],
    #: ec8_satisfied, target_sa (at the swept periods) [m/s^2], fit_period,
    #: fit_target, fit_mean; None when the records are not a suite
    suite: Optional[dict] = None
    #: a bridge given by its modes: the swept factors on its periods [-]
    #: (the last dimension); None for a single-DOF bridge
    period_scales: Optional[np.ndarray] = None
    #: a bridge given by its modes: the joints after the first of
    #: [[joints]], by name: {field: array of the results' shape}
    joints: dict = field(default_factory=dict)
    #: a multiple-stripe sweep ([sweep.stripes]): its stripes and the
    #: fitted fragility of each limit state (`Fragility`); None otherwise
    fragility: Optional["Fragility"] = None
    #: with target frequencies on the limit states: the choice among the
    #: cases as candidate joints, one `Design` per damping ratio and
    #: period (empty otherwise; docs/design.md)
    design: list = field(default_factory=list)

    @property
    def dims(self) -> tuple:
        """The dimensions of the results with the joint: (case, record,
        damping, period), or (..., period_scale) for a bridge given by its
        modes."""
        return DIMS if self.period_scales is None else DIMS[:3] + ("period_scale",)

    def __repr__(self) -> str:
        shape = (len(self.cases), len(self.records), len(self.damping), len(self.periods))
        return (
            f"Sweep({self.path!r}, ({', '.join(self.dims)}) = {shape}, "
            f"{int(self.ok.sum())} ok, {int(self.flagged.sum())} flagged, {int(self.failed.sum())} failed, "
            f"complete={self.complete}{', suite' if self.suite else ''})"
        )

    @property
    def complete(self) -> bool:
        """Whether every job in the file's scope has a result."""
        return bool(self.attrs.get("complete", 0))

    @property
    def ok(self) -> np.ndarray:
        """Jobs that finished inside the model's validity."""
        return (self.status == 0) & ((self.validity.astype(np.int64) & ~NOT_CHECKED) == 0)

    @property
    def flagged(self) -> np.ndarray:
        """Jobs that finished outside what the model can stand behind."""
        return (self.status == 0) & ((self.validity.astype(np.int64) & ~NOT_CHECKED) != 0)

    @property
    def failed(self) -> np.ndarray:
        """Jobs that ran and failed (see `message`)."""
        return (self.status != 0) & (self.status != -1)

    def __getitem__(self, name: str) -> np.ndarray:
        """A result with the joint (`sweep["sa"]`), or `reduction`."""
        if name == "reduction":
            return self.reduction
        try:
            return self.with_joint[name]
        except KeyError:
            raise KeyError(f"{self.path}: no result `{name}` (there are {', '.join(sorted(self.with_joint))})") from None

    def index(self, case=None, record=None, damping=None) -> tuple:
        """The (case, record, damping) index of labels: a case or record name
        or position, a damping ratio; None for the only one there is."""

        def pick(dim, labels, value):
            if value is None:
                if len(labels) != 1:
                    raise InputError(f"{self.path}: there are {len(labels)} {dim}s ({list(labels)}); name one")
                return 0
            if isinstance(value, (int, np.integer)) and dim != "damping":
                return int(value)
            matches = [i for i, v in enumerate(labels) if (np.isclose(v, value) if dim == "damping" else v == value)]
            if not matches:
                raise InputError(f"{self.path}: no {dim} {value!r} (there are {list(labels)})")
            return matches[0]

        return (
            pick("case", self.cases, case),
            pick("record", self.records, record),
            pick("damping", list(self.damping), damping),
        )

    def to_xarray(self):
        """The results as an xarray.Dataset with coordinates case, record,
        damping and period (needs the extra `xarray`:
        `pip install "quakejoint[xarray]"`)."""
        xr = _extra("xarray", "xarray", "Sweep.to_xarray")
        dims, last = self.dims, self.dims[3]
        coords = {"case": self.cases, "record": self.records, "damping": self.damping}
        if self.period_scales is None:
            coords["period"] = self.periods
        else:
            coords["period_scale"] = self.period_scales
            coords["longest_period"] = ("period_scale", self.periods, {"units": "s"})
        data = {}
        for name, a in self.with_joint.items():
            data[f"{name}_with_joint" if name in self.without_joint else name] = (
                dims,
                a,
                {"units": self.units.get(name, "")},
            )
        for name, a in self.without_joint.items():
            data[f"{name}_without_joint"] = (dims[4 - a.ndim :], a, {"units": self.units.get(name, "")})
        data["reduction"] = (dims, self.reduction, {"units": "1"})
        data["status"] = (dims, self.status)
        data["validity"] = (dims, self.validity)
        data["message"] = (dims, self.message)
        data["findings"] = (dims, self.findings)
        for joint, arrays in self.joints.items():
            for name, a in arrays.items():
                data[f"{joint}:{name}"] = (dims, a, {"units": self.units.get(f"{joint}:{name}", "")})
        if self.statistics:
            czt = ("case", "damping", last)
            for group, arrays in self.statistics.items():
                if isinstance(arrays, dict):
                    for name, a in arrays.items():
                        data[f"{group}_{name}"] = (czt[3 - a.ndim :], a)
                else:
                    data[f"records_{group}"] = (czt, arrays)
        if self.suite:
            data["suite_factor"] = (("record",), self.suite["factor"], {"units": "1"})
            data["target_sa"] = ((last,), self.suite["target_sa"], {"units": "m/s^2"})
        return xr.Dataset(data, coords=coords, attrs={k: v for k, v in self.attrs.items() if k != "config_file"})

    def _columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """The results per job, by the names of `to_xarray` and
        `to_dataframe`: name -> (array of shape (case, record, damping,
        period), units). A result the file holds with and without the joint
        is `<name>_with_joint` and `<name>_without_joint` (the spectrum
        without the joint repeated over the cases), one it holds with the
        joint only keeps its name."""
        shape = self.status.shape
        out = {}
        for name, a in self.with_joint.items():
            out[f"{name}_with_joint" if name in self.without_joint else name] = (a, self.units.get(name, ""))
        for name, a in self.without_joint.items():
            out[f"{name}_without_joint"] = (np.broadcast_to(a if a.ndim == 4 else a[None], shape), self.units.get(name, ""))
        out["reduction"] = (self.reduction, "1")
        for joint, arrays in self.joints.items():
            for name, a in arrays.items():
                out[f"{joint}:{name}"] = (a, self.units.get(f"{joint}:{name}", ""))
        return out

    def to_dataframe(self):
        """The results as a pandas.DataFrame in long format: one row per job
        (case, record, damping, period; the period fastest, as in the
        file's arrays) with the columns case, record, damping [-], period
        [s] (a bridge given by its modes: period_scale [-] and
        longest_period [s]), every result with and without the joint (named
        as in `to_xarray`; the joints after the first as `<joint>:<field>`),
        reduction, status, validity, message and findings.
        Failed jobs and jobs that did not run hold NaN (see `status` and
        `message`). The units are in `df.attrs["units"]` (column ->
        units). Needs the extra `pandas`: `pip install "quakejoint[pandas]"`."""
        pd = _extra("pandas", "pandas", "Sweep.to_dataframe")
        shape = self.status.shape
        axis = self.periods if self.period_scales is None else self.period_scales
        labels = np.meshgrid(
            np.array(self.cases, dtype=object),
            np.array(self.records, dtype=object),
            self.damping,
            axis,
            indexing="ij",
        )
        data = {name: values.ravel() for name, values in zip(self.dims, labels)}
        units = {"damping": "1", "period": "s", "period_scale": "1"}
        if self.period_scales is not None:
            data["longest_period"] = np.broadcast_to(self.periods, shape).ravel()
            units["longest_period"] = "s"
        for name, (a, unit) in self._columns().items():
            data[name] = np.asarray(a).reshape(shape).ravel()
            units[name] = unit
        data["status"] = self.status.ravel()
        data["validity"] = self.validity.ravel()
        data["message"] = self.message.ravel()
        data["findings"] = self.findings.ravel()
        df = pd.DataFrame(data)
        df.attrs["units"] = units
        return df


def _extra(module: str, extra: str, what: str):
    """Imports `module`, which the package's extra `extra` brings; an
    ImportError that says how to install it otherwise."""
    try:
        return __import__(module)
    except ImportError as e:
        raise ImportError(
            f"{what} needs {module}, which `pip install quakejoint` does not bring: "
            f'pip install "quakejoint[{extra}]" (from the checkout: pip install ".[{extra}]")'
        ) from e


def _text(flat_and_shape) -> np.ndarray:
    """Text given as (flat list, shape) as an object array of str."""
    flat, shape = flat_and_shape
    out = np.empty(len(flat), dtype=object)
    out[:] = flat
    return out.reshape(shape)


def read_sweep(path) -> Sweep:
    """Reads a sweep or merge file (`quakejoint sweep --output path`): by the
    command line's own reader, which reads every dataset and attribute and
    checks what is derived against what it is derived from, so that a
    damaged file is refused (an InputError naming the dataset or
    attribute), never read as a good one."""
    path = str(path)
    d = read_sweep_file(path)
    sweep = Sweep(
        path=path,
        cases=list(d["cases"]),
        records=list(d["records"]),
        damping=d["damping"],
        periods=d["periods"],
        period_scales=d["period_scales"],
        joints=d["joints"],
        with_joint=d["with_joint"],
        without_joint=d["without_joint"],
        units=d["units"],
        status=d["status"],
        message=_text(d["message"]),
        validity=d["validity"],
        findings=_text(d["findings"]),
        reduction=d["reduction"],
        flag_names=[tuple(p) for p in d["flag_names"]],
        attrs=d["attrs"],
        suite=d["suite"],
        fragility=_fragility(d["fragility"]),
        statistics=d["statistics"],
        design=[_design(x) for x in d["design"]],
    )
    return sweep


@dataclass(repr=False)
class LimitStateFragility:
    """One limit state of a multiple-stripe sweep (`/fragility/<key>`).

    `outcome` has the results' shape (case, record, damping, period): 1
    exceeded, 0 not, -1 failed, -2 not run, -3 not reported by the run.
    The counts (`runs`, `exceeded`, `failed`, `not_run`, `undetermined`,
    `flagged`) have shape (case, damping, period, stripe); the fit
    (`median` [g], `beta`, `se_ln_median`, `se_beta`, `median_lo`,
    `median_hi`, `beta_lo`, `beta_hi`, `annual_frequency` [1/year],
    `return_period` [year]) and `note` shape (case, damping, period),
    NaN where the counts determine no fit (the note says why)."""

    key: str
    name: str
    kind: str
    definition: str
    arrays: dict

    def __getattr__(self, name):
        try:
            return self.__dict__["arrays"][name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.arrays))

    def __repr__(self) -> str:
        return f"LimitStateFragility({self.name!r}, median={self.arrays['median'].ravel()}, beta={self.arrays['beta'].ravel()})"

    def probability(self, im, case: int = 0, damping: int = 0, period: int = 0) -> np.ndarray:
        """The fitted P(exceeded | intensity `im` [g]) of one curve (NaN
        where there is no fit)."""
        m, b = self.arrays["median"][case, damping, period], self.arrays["beta"][case, damping, period]
        im = np.asarray(im, dtype=float)
        if np.any(~(im >= 0)):
            raise InputError(f"probability: intensities must be >= 0 [g], got {im[~(im >= 0)][:3].tolist()}")
        out = np.full(im.shape, np.nan)
        if np.isfinite(m) and np.isfinite(b):
            with np.errstate(divide="ignore"):
                z = np.log(im / m) / (b * math.sqrt(2.0))
            out = 0.5 * (1.0 + np.array([math.erf(x) for x in z.ravel()]).reshape(im.shape))
        return out


@dataclass(repr=False)
class Fragility:
    """The stripes of a multiple-stripe sweep and its limit states.

    `measure` is `sa` (Sa(T1), pseudo-spectral acceleration at
    `measure_period` [s] and `measure_damping`) or `pga`; `levels` [g] the
    stripes; `ground_records` the records as given with their intensity
    as read (`ground_intensity` [g]); per record of the sweep (the scaled
    copies, `Sweep.records`): `record_ground`, `record_stripe`,
    `record_factor`. `hazard` is (intensity [g], annual frequency) or
    None; `limit_states` maps each key to a `LimitStateFragility`."""

    measure: str
    measure_label: str
    measure_period: Optional[float]
    measure_damping: Optional[float]
    levels: np.ndarray
    ground_records: list
    ground_intensity: np.ndarray
    record_ground: np.ndarray
    record_stripe: np.ndarray
    record_factor: np.ndarray
    failed: str
    hazard: Optional[tuple]
    limit_states: dict

    def __repr__(self) -> str:
        return (
            f"Fragility({self.measure_label}, levels={[float(x) for x in self.levels]} g, "
            f"limit_states={list(self.limit_states)})"
        )

    def __getitem__(self, key: str) -> LimitStateFragility:
        return self.limit_states[key]


@dataclass(repr=False)
class Design:
    """Which candidate joint meets the targets (docs/design.md), at one
    damping ratio (`damping`, an index) and period (`period`, an index)
    of the sweep: the candidates are its cases (`candidates`, with their
    `cells` (gaps) and `fuse` in words), `targets` the limit states that
    carry one as (key, name, annual frequency [1/year]);
    `annual_frequency`, `checked` (the upper end of the bootstrap interval,
    what is compared), `passed` and `notes` have shape (candidate,
    target); `recommended` is the case with the fewest gaps that meets
    every target (None if none does), `margin` its smallest ratio of a
    target to its checked value, on the limit state `margin_on`."""

    damping: int
    period: int
    targets: list
    candidates: list
    cells: list
    fuse: list
    annual_frequency: np.ndarray
    checked: np.ndarray
    passed: np.ndarray
    notes: list
    recommended: Optional[str]
    margin: Optional[float]
    margin_on: Optional[str]

    def __repr__(self) -> str:
        return f"Design(candidates={self.candidates}, recommended={self.recommended!r}, margin={self.margin})"


def _design(d) -> Design:
    return Design(
        damping=d["damping"],
        period=d["period"],
        targets=[tuple(t) for t in d["targets"]],
        candidates=list(d["candidates"]),
        cells=list(d["cells"]),
        fuse=list(d["fuse"]),
        annual_frequency=np.array(d["annual_frequency"], dtype=float),
        checked=np.array(d["checked"], dtype=float),
        passed=np.array(d["passed"], dtype=bool),
        notes=[list(r) for r in d["notes"]],
        recommended=d["recommended"],
        margin=d["margin"],
        margin_on=d["margin_on"],
    )


def _fragility(d) -> Optional[Fragility]:
    if d is None:
        return None
    states = {}
    # in the config's order
    for ls in d["limit_states"]:
        arrays = dict(ls["arrays"])
        arrays["note"] = _text(arrays["note"])
        states[ls["key"]] = LimitStateFragility(
            key=ls["key"], name=ls["name"], kind=ls["kind"], definition=ls["definition"], arrays=arrays
        )
    return Fragility(
        measure=d["measure"],
        measure_label=d["measure_label"],
        measure_period=d["measure_period"],
        measure_damping=d["measure_damping"],
        levels=d["levels"],
        ground_records=list(d["ground_records"]),
        ground_intensity=d["ground_intensity"],
        record_ground=d["record_ground"],
        record_stripe=d["record_stripe"],
        record_factor=d["record_factor"],
        failed=d["failed"],
        hazard=d["hazard"],
        limit_states=states,
    )

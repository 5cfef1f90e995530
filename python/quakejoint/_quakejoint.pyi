"""Type stubs of the extension module (crates/python). SI units throughout."""
from os import PathLike
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
#: standard gravity [m/s^2], the unit `g`
G: float

class Error(Exception):
    """Base class of the errors of quakejoint."""

class InputError(Error):
    """Bad input (the command line's exit code 2); the message names the file, field or value."""

class SimulationError(Error):
    """A run that failed (the command line's exit code 1)."""

#: a real number, or a 1-D sequence or array of them (not complex)
_Numbers = Union[float, Sequence[float], npt.NDArray[np.floating[Any]], npt.NDArray[np.integer[Any]]]
#: an array of spectrum values: shape np.shape(damping) + np.shape(periods)
_SpectrumArray = npt.NDArray[np.float64]

class Record:
    """A ground-motion record: acceleration [m/s^2] at a uniform time step."""

    @staticmethod
    def read(
        path: Union[str, PathLike[str]],
        *,
        format: Optional[str] = None,
        units: Optional[str] = None,
        dt: Optional[float] = None,
        column: Optional[int] = None,
        scale: Optional[float] = None,
        target_pga_g: Optional[float] = None,
        name: Optional[str] = None,
        channel: Optional[int] = None,
        azimuth: Optional[float] = None,
        allow_vertical: bool = False,
    ) -> Record:
        """Reads a record file (AT2, ESM, K-NET, COSMOS, CSMIP/DMG from CESMD, CSV,
        text); units from the header or `units` ("g", "m/s2", "cm/s2", "gal"),
        never guessed. `channel` (number) or `azimuth` [degrees from north]
        choose a channel of a file of several; a vertical one needs
        `allow_vertical=True`."""
    @staticmethod
    def from_array(
        acceleration: npt.ArrayLike,
        dt: float,
        *,
        units: Optional[str] = None,
        scale: Optional[float] = None,
        target_pga_g: Optional[float] = None,
        name: Optional[str] = None,
    ) -> Record:
        """A record from 1-D real samples in `units` (required) at time step `dt` [s]; named "array" by default.
        A complex array is refused (InputError), not cut to its real part."""
    @property
    def acceleration(self) -> npt.NDArray[np.float64]:
        """Ground acceleration [m/s^2] (a copy)."""
    @property
    def time(self) -> npt.NDArray[np.float64]:
        """Sample times [s] from 0."""
    @property
    def dt(self) -> float:
        """Time step [s]."""
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str:
        """The file as given."""
    @property
    def units(self) -> str:
        """Units of the numbers in the file."""
    @property
    def format(self) -> str:
        """The format the file was read as."""
    @property
    def channel(self) -> Optional[dict]:
        """The channel read: {"number", "of", "orientation": {"kind", "degrees" or
        "label"}, "description"}; None for text."""
    @property
    def scale(self) -> float:
        """The user's scale factor [-]."""
    @property
    def total_scale(self) -> float:
        """Factor from the file's numbers to `acceleration` [m/s^2 per file unit]."""
    @property
    def sha256(self) -> str: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def header(self) -> list[str]: ...
    @property
    def duration(self) -> float:
        """(n - 1) dt [s]."""
    @property
    def pga(self) -> float:
        """Peak ground acceleration [m/s^2]."""
    @property
    def stats(self) -> dict[str, Union[float, int]]:
        """dt, samples, duration [s], pga [m/s^2], pgv [m/s], pgd [m], their times, arias [m/s], d5_95, t5, t95 [s]."""
    def spectrum(self, periods: _Numbers, damping: Optional[_Numbers] = None, *, subdivisions: int = 0) -> Spectrum:
        """The exact linear response spectrum (see `spectrum`; the same shapes)."""
    def __len__(self) -> int: ...

class Spectrum:
    """Exact linear spectrum. Each array has the shape np.shape(damping) + np.shape(periods)
    of the arguments: a number has no axis, a sequence (of one, or of none) has one. A number
    of damping (or the default 0.05) gives (len(periods),), a list of dampings
    (len(damping), len(periods)); empty periods with two dampings (2, 0)."""

    @property
    def periods(self) -> npt.NDArray[np.float64]:
        """[s], always 1-D"""
    @property
    def damping(self) -> npt.NDArray[np.float64]:
        """[-], always 1-D"""
    @property
    def sa(self) -> _SpectrumArray:
        """Peak absolute acceleration [m/s^2]."""
    @property
    def psa(self) -> _SpectrumArray:
        """w^2 Sd [m/s^2]."""
    @property
    def sd(self) -> _SpectrumArray:
        """Peak relative displacement [m]."""
    @property
    def sv(self) -> _SpectrumArray:
        """Peak relative velocity [m/s]."""
    @property
    def psv(self) -> _SpectrumArray:
        """w Sd [m/s]."""
    @property
    def t_sa(self) -> _SpectrumArray:
        """[s]"""
    @property
    def t_sd(self) -> _SpectrumArray:
        """[s]"""
    @property
    def t_sv(self) -> _SpectrumArray:
        """[s]"""

def spectrum(
    record: Union[Record, npt.ArrayLike],
    periods: _Numbers,
    damping: Optional[_Numbers] = None,
    *,
    dt: Optional[float] = None,
    units: Optional[str] = None,
    subdivisions: int = 0,
) -> Spectrum:
    """Exact linear response spectrum of a record, or of an array at `dt` [s] in `units`; damping default 0.05.
    Arrays of shape np.shape(damping) + np.shape(periods): (len(periods),) for a number of damping,
    (len(damping), len(periods)) for a sequence of them."""

class Config:
    """A validated model config; relative record paths are read from `base_dir`."""

    def __init__(self, tables: Optional[dict[str, Any]] = None, *, base_dir: Union[str, PathLike[str]] = ".") -> None:
        """From a dict of the TOML file's tables; every default without one. Values are numbers
        (Python's or numpy's, real), strings, booleans, lists and dicts; a dict that contains
        itself or is nested deeper than 32 levels, a whole number beyond its field's range and a
        complex number raise InputError naming the key."""
    @staticmethod
    def from_file(path: Union[str, PathLike[str]]) -> Config: ...
    @staticmethod
    def from_toml(text: str, *, base_dir: Union[str, PathLike[str]] = ".", source: str = "config (text)") -> Config: ...
    def replace(self, changes: dict[str, Any]) -> Config:
        """A copy with dotted keys ({"bridge.mass": 2e8}) or nested dicts changed, validated again
        (the values checked as `Config(tables)` checks them)."""
    def to_dict(self) -> dict[str, Any]: ...
    def to_toml(self) -> str: ...
    @property
    def base_dir(self) -> Path: ...
    @property
    def source(self) -> str: ...
    @property
    def period(self) -> float:
        """The bridge's natural period [s]."""
    @property
    def joint(self) -> bool: ...

class RunResult:
    """One earthquake run. Scalars as attributes, named as in `quakejoint simulate --json`:
    period [s], omega [rad/s], sa, psa [m/s^2], sd [m], sv [m/s], t_sa, t_sd, t_sv [s],
    peak_joint_force, peak_bushing_force, peak_friction_force [N], friction_energy,
    damping_energy, earthquake_work, contact_energy [J], min_subgap, max_subgap,
    max_subgap_deviation, max_penetration [m], impacts, peak_contact_force,
    peak_deck_contact_force [N], peak_contact_time [s], energy_error [-], steps,
    rejected_steps, newton_iterations, wall_time_s, cpu_time_s, duration [s], record,
    record_pga_g, joint, method, validity, validity_label; across the bridge period_y [s],
    sa_y, sa_y_without_joint [m/s^2], t_sa_y [s], sd_y [m], sv_y [m/s], peak_joint_force_y [N];
    an adjacent segment period_far [s], sa_far, sa_far_without_joint [m/s^2], t_sa_far [s],
    sd_far, max_relative_displacement [m], peak_joint_force_far [N] (NaN: not computed)."""

    history: Optional[dict[str, npt.NDArray[np.float64]]]
    impacts_log: list[dict[str, float]]
    flags: list[str]
    findings: list[str]
    flagged: bool
    def as_dict(self) -> dict[str, Any]: ...
    def __getattr__(self, name: str) -> Any: ...

def simulate(
    config: Optional[Config] = None,
    *,
    period: Optional[float] = None,
    record: Optional[Record] = None,
    joint: bool = True,
    history: bool = True,
) -> RunResult:
    """One coupled earthquake run (or the bridge alone, exactly, with joint=False); GIL released, Ctrl-C stops it."""

def calibrate(
    config: Optional[Config] = None,
    *,
    amplitudes: Any = None,
    speed: Optional[float] = None,
    contact_force: Optional[float] = None,
    record: Optional[Record] = None,
    earthquake: bool = True,
) -> dict[str, Any]:
    """The joint's link element: stiffness, friction, mass, damping, gap, fit, loops, exports (docs/link.md)."""
    ...

def fit_fragility(intensities: Any, runs: Any, exceeded: Any) -> dict[str, float]:
    """Lognormal fragility by maximum likelihood on stripe counts: median, beta, log_likelihood, standard errors."""
    ...

def bootstrap_fragility(
    outcomes: Any,
    intensities: Any,
    samples: Optional[int] = None,
    seed: Optional[int] = None,
    level: Optional[float] = None,
    hazard_intensity: Any = None,
    hazard_frequency: Any = None,
) -> dict[str, Any]:
    """Bootstrap intervals of the fragility over records (outcomes 1, 0 or -1 per record and stripe; samples 1 to
    100000, 1000 if None; seed 0 to 2**64 - 1, 0 if None; level 0.9 if None); with a hazard curve (intensity [g],
    annual frequency [1/year]) the annual frequency's interval too."""
    ...

def limit_state_frequency(median: float, beta: float, hazard_intensity: Any, hazard_frequency: Any) -> float:
    """Mean annual frequency of the limit state over a hazard curve (intensity [g], annual frequency [1/year]) [1/year],
    in closed form; a UserWarning when more than 1 % of it comes from beyond the curve's ends."""
    ...

def service(
    config: Optional[Config] = None,
    *,
    speed: Optional[float] = None,
    amplitude: Optional[float] = None,
    cycles: Optional[int] = None,
) -> dict[str, Any]:
    """The service loop: t, u, joint_force, center-beam motions, works per cycle [J], validity.

    speed [m/s], amplitude [m] and cycles replace the config's [service]
    values, checked as `quakejoint service --speed/--amplitude/--cycles`."""

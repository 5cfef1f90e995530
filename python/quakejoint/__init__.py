"""quakejoint: how much a modular bridge expansion joint damps its bridge in an earthquake.

The engine of the `quakejoint` command on numpy arrays (SI units throughout):

- `Record.read(path)` / `Record.from_array(a, dt, units=...)`: ground-motion
  records, units never guessed, with their statistics;
- `spectrum(record, periods, damping)`: exact linear response spectra (the
  code of `quakejoint spectrum`, bit for bit), arrays of shape
  np.shape(damping) + np.shape(periods);
- `Config.from_file(path)` / `Config({...})` / `config.replace({...})`:
  validated model configs;
- `simulate(config, period=...)`: one coupled earthquake run, scalars and
  time histories; `service(config)`: the hysteresis loop of the joint;
- `calibrate(config)`: the joint's link element for a global bridge model,
  with its OpenSees, SAP2000 and TOML exports (docs/link.md);
- `fit_fragility(intensities, runs, exceeded)`, `bootstrap_fragility(...)`,
  `limit_state_frequency(median, beta, hazard_im, hazard_rate)`: lognormal
  fragility by maximum likelihood on stripe counts and its risk at a site;
- `read_sweep(path)`: a `quakejoint sweep` file as labelled arrays,
  `.to_xarray()` (extra `xarray`) and `.to_dataframe()` (extra `pandas`).

Errors are `InputError` (bad input: the message names the file, field or
value) and `SimulationError` (a run that failed), both `quakejoint.Error`.
"""
from ._quakejoint import (  # noqa: F401
    G,
    Config,
    Error,
    InputError,
    Record,
    RunResult,
    SimulationError,
    Spectrum,
    __version__,
    bootstrap_fragility,
    calibrate,
    fit_fragility,
    limit_state_frequency,
    service,
    simulate,
    spectrum,
)
from .sweep import Fragility, LimitStateFragility, Sweep, read_sweep  # noqa: F401

__all__ = [
    "G",
    "Config",
    "Error",
    "InputError",
    "Record",
    "RunResult",
    "SimulationError",
    "Spectrum",
    "Fragility",
    "LimitStateFragility",
    "Sweep",
    "bootstrap_fragility",
    "calibrate",
    "fit_fragility",
    "limit_state_frequency",
    "read_sweep",
    "service",
    "simulate",
    "spectrum",
    "__version__",
]

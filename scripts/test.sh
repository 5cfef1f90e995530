#!/usr/bin/env bash
# The project's tests, as CI runs them (.ci/run calls this script): installs
# what they need on a fresh Debian machine, then runs them.
#
#   scripts/test.sh
#
# 1. System packages (apt, as root or with sudo): libhdf5-dev and pkg-config
#    for the HDF5 bindings; python3-venv if Python cannot make a virtual
#    environment; munge and SLURM for the cluster test.
# 2. A Python virtual environment `.venv` with scripts/requirements.txt
#    (h5py, numpy, matplotlib): the tests call `python3` for the plotting
#    scripts and to open outputs with h5py. It comes first on PATH.
# 3. `cargo fmt --check`, `cargo clippy` and `cargo doc` with warnings
#    denied, then `cargo test --workspace` (which, run by hand without the
#    Python packages, skips the parts that need h5py or matplotlib and says
#    what to install; here they must run).
# 4. The Python package (pip install ".[test]" into .venv, which builds the
#    engine with maturin) and its tests, python/tests: values against the
#    command line and closed forms, every plot script, the examples; with
#    openseespy (scripts/opensees/requirements.txt; Debian's libblas3 and
#    liblapack3), the three-span bridge rebuilt and checked in OpenSees.
# 5. The cluster tests on a real one-node SLURM on localhost
#    (tests/slurm/start.sh, test_start.sh, test_array.sh, stop.sh). It needs root; set
#    QJ_SKIP_SLURM=1 to leave it out where that is impossible (it is then
#    reported as not run, and CI never sets it).
#
# It builds three profiles: the checks (clippy, rustdoc), the tests (the
# `test` profile, optimised) and the Python package's engine (release).
# On 2 idle cores the whole script takes about 40 minutes from a fresh
# clone, of which the builds take about 25; every stage prints its time.
set -euo pipefail
cd "$(dirname "$0")/.."

. scripts/setup.sh
start=$SECONDS
stage_start=$SECONDS
# stage NAME: prints the time the previous stage took and starts NAME
stage() {
  echo "   ($(( SECONDS - stage_start )) s)"
  stage_start=$SECONDS
  echo "== $1"
}
system_packages
python_env

stage "cargo fmt --check, clippy and rustdoc with warnings denied; the code's shape"
cargo fmt --all --check
# (no function over 120 lines in crates/*/src, no import circle between the
# model crate's modules: issue 36)
python3 scripts/long_functions.py 120
python3 scripts/import_cycles.py model
cargo clippy --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

stage "cargo test --workspace"
# the tests that need h5py and matplotlib fail here if they are missing,
# rather than skip as they do in a plain `cargo test` without them
rm -f target/tmp/simd_paths.skipped
QJ_REQUIRE_PYTHON=1 cargo test --workspace
if [ -f target/tmp/simd_paths.skipped ]; then
  echo "NOT RUN: the AVX2 against portable kernels test (crates/cli/tests/simd_paths.rs): $(cat target/tmp/simd_paths.skipped)"
fi

stage "the Python package (builds the engine in release) and openseespy"
python_package
opensees_env
stage "pytest python/tests"
QUAKEJOINT_BIN="$PWD/target/debug/quakejoint" QJ_REQUIRE_OPENSEES=1 .venv/bin/python3 -m pytest -q python/tests

stage "cluster test on a real SLURM"
trap 'echo "== scripts/test.sh: $(( (SECONDS - start) / 60 )) min $(( (SECONDS - start) % 60 )) s in all"' EXIT
if [ "${QJ_SKIP_SLURM:-0}" = 1 ]; then
  echo "NOT RUN: the SLURM test (QJ_SKIP_SLURM=1)"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "the SLURM test needs root to install and start a one-node cluster; run as root, or set QJ_SKIP_SLURM=1" >&2
  exit 1
fi
# the trap first: a start that fails half-way (munged up, slurmctld not) is
# stopped too
trap 'tests/slurm/stop.sh > /dev/null; echo "== scripts/test.sh: $(( (SECONDS - start) / 60 )) min $(( (SECONDS - start) % 60 )) s in all"' EXIT
tests/slurm/start.sh
tests/slurm/test_start.sh
tests/slurm/test_array.sh target/debug/quakejoint

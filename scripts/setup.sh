# Shared set-up of scripts/main_job.sh and scripts/test.sh (sourced, not
# run): what a fresh Debian machine needs besides the Rust toolchain.

SUDO=""
if [ "$(id -u)" -ne 0 ] && command -v sudo > /dev/null 2>&1; then SUDO="sudo"; fi

# apt_install PACKAGE...: installs Debian packages quietly
apt_install() {
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" > /dev/null
}

# system_packages: the HDF5 library and headers the hdf5 crate builds against
system_packages() {
  if ! dpkg -s libhdf5-dev > /dev/null 2>&1 || ! command -v pkg-config > /dev/null 2>&1; then
    echo "== installing libhdf5-dev and pkg-config"
    apt_install libhdf5-dev pkg-config
  fi
}

# python_env: the virtual environment .venv with the plotting scripts'
# packages (scripts/requirements.txt), put first on PATH
python_env() {
  if [ ! -x .venv/bin/python3 ]; then
    echo "== creating the Python environment .venv"
    python3 -m venv .venv 2> /dev/null || { apt_install python3-venv && python3 -m venv .venv; }
  fi
  .venv/bin/python3 -m pip install --quiet --disable-pip-version-check -r scripts/requirements.txt
  export PATH="$PWD/.venv/bin:$PATH"
}

# python_package: the Python package quakejoint built from this checkout
# (pyproject.toml: maturin builds crates/python in release) with its test
# dependencies (pytest, matplotlib, xarray, pandas), into .venv
python_package() {
  echo "== installing the Python package quakejoint into .venv (builds the engine)"
  .venv/bin/python3 -m pip install --quiet --disable-pip-version-check ".[test]"
}

# opensees_env: openseespy (scripts/opensees/requirements.txt), the
# independent engine of the bridge checks, into .venv; on Debian it needs
# the BLAS and LAPACK libraries; and tclsh, which runs the Tcl export
# against a recorder of OpenSees' commands
opensees_env() {
  if ! dpkg -s libblas3 > /dev/null 2>&1 || ! dpkg -s liblapack3 > /dev/null 2>&1; then
    echo "== installing libblas3 and liblapack3 (for openseespy)"
    apt_install libblas3 liblapack3
  fi
  if ! command -v tclsh > /dev/null 2>&1; then
    echo "== installing tcl (tclsh, for the Tcl export's test)"
    apt_install tcl
  fi
  .venv/bin/python3 -m pip install --quiet --disable-pip-version-check -r scripts/opensees/requirements.txt
}

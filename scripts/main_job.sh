#!/usr/bin/env bash
# The main job: the response spectrum of the reference bridge with and
# without the reference joint (configs/paper.toml: 50 periods from 0.1 to
# 5 s, 5 % damping, Loma Prieta Corralitos 090), on a fresh Debian machine
# with a Rust toolchain. Installs what it needs, builds, runs, plots:
#
#   scripts/main_job.sh            # paper.h5 and paper.png in the checkout's root
#
# Run it again to continue an interrupted run (Ctrl-C is safe: finished
# jobs are kept in paper.h5.journal); once complete it says so.
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/setup.sh
system_packages
echo "== building quakejoint (release; the first build compiles about 200 crates: 5 to 15 minutes on 2 cores, later ones seconds)"
cargo build --release -p quakejoint
echo "== quakejoint sweep configs/paper.toml --output paper.h5"
status=0
target/release/quakejoint sweep configs/paper.toml --output paper.h5 || status=$?
case "$status" in
  0) ;;
  130|143) echo "interrupted: run scripts/main_job.sh again to continue where it stopped"; exit "$status" ;;
  *) echo "the sweep ended with exit code $status (see above; 3: some jobs failed, 4: some were flagged)"; exit "$status" ;;
esac
python_env
python3 scripts/plot_spectrum.py paper.h5 paper.png
python3 scripts/headline.py paper.h5
echo "== done: $PWD/paper.h5 (docs/hdf5-layout.md) and $PWD/paper.png"
echo "   to use quakejoint directly: cargo install --locked --path crates/cli  (puts it on PATH, in ~/.cargo/bin)"

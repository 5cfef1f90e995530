#!/usr/bin/env bash
# The reference earthquake run (configs/paper.toml: the 307-body joint on the
# paper's bridge under Corralitos 090, one thread) timed with this
# checkout's release binary and with the release binary of an earlier commit,
# alternately, N times each (default 5); prints the fastest integration time
# of each (the `wall_time_s` of `simulate --json`), their ratio and Sa.
# docs/performance.md quotes it for the commit 1ad4cc7.
#
#   scripts/bench_against.sh <commit> [N]
#
# The earlier commit is built in a git worktree under target/bench-against/
# (a few minutes the first time) with its own configs and records.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
rev=${1:?usage: scripts/bench_against.sh <commit> [N]}
n=${2:-5}
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "N must be a positive whole number, not '$n'" >&2; exit 2; }
commit=$(git -C "$repo" rev-parse --verify "$rev^{commit}")
short=${commit:0:12}
old=$repo/target/bench-against/$short
if [ ! -d "$old" ]; then
  # a worktree whose folder was removed (cargo clean) is still registered
  git -C "$repo" worktree prune
  git -C "$repo" worktree add --detach "$old" "$commit" >/dev/null
fi
(cd "$old" && CARGO_TARGET_DIR=$old/target cargo build --release -q -p quakejoint)
(cd "$repo" && CARGO_TARGET_DIR=$repo/target cargo build --release -q -p quakejoint)
time_of() {   # time_of BINARY DIR: prints "wall_time_s sa"
  local json
  json=$(cd "$2" && "$1" simulate configs/paper.toml --json) || {
    echo "$1 simulate configs/paper.toml failed in $2" >&2
    exit 1
  }
  python3 -c "import json, sys; d = json.loads(sys.argv[1]); print(d['wall_time_s'], d['sa'])" "$json"
}
best_new=1e300; best_old=1e300
for i in $(seq "$n"); do
  read -r t_old sa_old < <(time_of "$old/target/release/quakejoint" "$old")
  read -r t_new sa_new < <(time_of "$repo/target/release/quakejoint" "$repo")
  [ -n "${t_old:-}" ] && [ -n "${t_new:-}" ] || exit 1
  echo "run $i: $rev ${t_old} s, this checkout ${t_new} s"
  best_old=$(python3 -c "print(min($best_old, $t_old))")
  best_new=$(python3 -c "print(min($best_new, $t_new))")
done
python3 - "$rev" "$best_old" "$best_new" "$sa_old" "$sa_new" <<'EOF'
import sys
rev, old, new, sa_old, sa_new = sys.argv[1], *map(float, sys.argv[2:])
print(f"fastest of each: {rev} {old:.2f} s, this checkout {new:.2f} s, ratio {new / old:.3f}")
print(f"Sa: {rev} {sa_old:.7f} m/s^2, this checkout {sa_new:.7f} m/s^2 (relative difference {abs(sa_new - sa_old) / sa_old:.1e})")
EOF

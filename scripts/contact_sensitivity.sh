#!/usr/bin/env bash
# The contact's sensitivity table of docs/model.md ("Pounding"): the
# reference joint and bridge under Pacoima Dam 164 scaled by 2.5 at
# T = 3.5 s, one `quakejoint simulate` per contact setting, a Markdown row
# each (about 90 s on 2 cores).
#
#   scripts/contact_sensitivity.sh [path/to/quakejoint]
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
q=${1:-$repo/target/release/quakejoint}
work=$(mktemp -d /tmp/qj-contact-sensitivity.XXXXXX)
trap 'rm -rf "$work"' EXIT
# paper.toml without its [sweep] and [joint.contact] tables, under Pacoima x 2.5
base=$(sed -e '/^\[sweep\]/,$d' -e '/^\[joint.contact\]/,/^max_penetration/d' \
  -e "s#\.\./ground_motions/RSN753_LOMAP_CLS090-hor2.AT2#$repo/ground_motions/RSN77_SFERN_PUL164-hor1.AT2#" \
  -e 's#^\[record\]#[record]\nscale = 2.5#' "$repo/configs/paper.toml")
row() {
  local name=$1 contact=$2
  printf '%s\n[joint.contact]\n%b\n' "$base" "$contact" > "$work/c.toml"
  # a flagged run (exit code 4: the run without contact) still prints its numbers
  { "$q" simulate "$work/c.toml" --period 3.5 --json 2>/dev/null || [ $? -eq 4 ]; } | python3 -c "
import json, sys
d = json.load(sys.stdin)
print(f\"| $name | {d['sa']:.4f} | {d['impacts']} | {d['peak_contact_force']/1e6:.2f} | {d['peak_deck_contact_force']/1e6:.2f} | {d['contact_energy']/1e3:.1f} | {d['max_penetration']*1e3:.2f} | {d['validity_label']} | {d['steps']} | {d['wall_time_s']:.1f} |\")"
}
echo "| contact | Sa [m/s^2] | impacts | peak contact force [MN] | peak on the deck [MN] | contact energy [kJ] | deepest penetration [mm] | validity | steps | wall [s] |"
echo "|---|---|---|---|---|---|---|---|---|---|"
row "no contact" "enabled = false"
row "Hertz, defaults (2.75e10 N/m^1.5, e = 0.65, Ye-Li-Zhu)" ""
row "Hertz, 2.75e9 N/m^1.5" "hertz_stiffness = 2.75e9"
row "Hertz, 2.75e11 N/m^1.5" "hertz_stiffness = 2.75e11"
row "Hertz, e = 0.5" "restitution = 0.5"
row "Hertz, e = 0.8" "restitution = 0.8"
row "Hertz, Lankarani-Nikravesh" 'damping = "lankarani-nikravesh"'
row "linear, 1e9 N/m" 'law = "linear"'
row "linear, 1e10 N/m" 'law = "linear"\nlinear_stiffness = 1e10'

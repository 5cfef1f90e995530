#!/usr/bin/env python3
"""The headline numbers of a spectrum sweep, for a terminal.

    python3 scripts/headline.py paper.h5

For each case, record and damping ratio of a sweep file (`quakejoint
sweep`): Sa without and with the joint at the period nearest 1 s (the
reference bridge's w0 = 6.3 rad/s is T = 0.997 s), and the largest and
smallest reduction of Sa by the joint over the swept periods with their
periods; jobs that failed or that the model flags are counted, and left
out of the extremes. Reads the file with h5py (the layout of
docs/hdf5-layout.md).
"""
import sys

import h5py
import numpy as np

from plotlib import job_masks, refuse_modal, text


def headline(src):
    lines = []
    with h5py.File(src, "r") as f:
        refuse_modal(f, src)
        s = f["spectrum"]
        periods, damping = s["period"][:], s["damping"][:]
        cases, records = [text(c) for c in s["case"][:]], [text(r) for r in s["record"][:]]
        with_, without = s["with_joint/sa"][:], s["without_joint/sa"][:]
        reduction, status, validity = s["reduction"][:], s["with_joint/status"][:], s["with_joint/validity"][:]
    near = int(np.argmin(np.abs(periods - 1.0)))
    for c, case in enumerate(cases):
        for r, record in enumerate(records):
            for z, zeta in enumerate(damping):
                ok, flagged, failed, not_run = job_masks(status[c, r, z], validity[c, r, z])
                # (rounded to a tenth of a percent; +0.0 rather than -0.0)
                red = np.round(100 * reduction[c, r, z], 1) + 0.0
                head = f"{case} / {record} / {100 * zeta:g} % damping"
                at = (
                    f"  T = {periods[near]:.3f} s: Sa {without[r, z, near]:.3f} m/s^2 without the joint, "
                    f"{with_[c, r, z, near]:.3f} with it ({red[near]:.1f} % less)"
                )
                lines += [head, at if ok[near] else f"  T = {periods[near]:.3f} s: no valid result"]
                if ok.any():
                    hi, lo = np.nanargmax(np.where(ok, red, -np.inf)), np.nanargmin(np.where(ok, red, np.inf))
                    lines.append(
                        f"  over {periods[0]:g} to {periods[-1]:g} s: the joint lowers Sa by up to {red[hi]:.1f} % "
                        f"(T = {periods[hi]:.3f} s), by {red[lo]:.1f} % at least (T = {periods[lo]:.3f} s)"
                    )
                for n, what in ((flagged.sum(), "flagged by the model"), (failed.sum(), "failed"), (not_run.sum(), "not run")):
                    if n:
                        lines.append(f"  {n} of {len(periods)} jobs {what} (left out above)")
    return "\n".join(lines)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    print(headline(sys.argv[1]))

"""The calibrated link element against the detailed joint on single-DOF
decks (docs/link.md, "Where it holds"): configs/paper.toml's joint, its
deck's mass and period changed, detailed and as its link, and the deck
alone, under four records none of which calibrated the link (a strong
record, a pulse-like one, El Centro and a weak aftershock).

    quakejoint calibrate configs/paper.toml \
        --record ground_motions/RSN753_LOMAP_CLS000-hor1.AT2 \
        --record ground_motions/RSN77_SFERN_PUL164-hor1.AT2 \
        --record ground_motions/RSN6_IMPVALL.I_I-ELC270-hor2.AT2 --output-dir examples/link
    python3 scripts/link_study.py examples/link/link.toml --work /tmp/link_study [--opensees]

Prints one markdown row per deck, period and record: Sa, the peak force on
the deck, the friction energy, and the joint's effect on Sa, detailed
against link (about 2.5 s of runs per row). The link is quakejoint's
`joint.model = "link"`, or with --opensees the exported element run by
OpenSees itself (scripts/opensees/link_sdof.py on the link_opensees.py next
to the link.toml; openseespy needed).
"""
import argparse
import json
import math
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RECORDS = {
    "Corralitos 090": "RSN753_LOMAP_CLS090-hor2.AT2",
    "Pacoima Dam 254 (pulse, 1.2 g)": "RSN77_SFERN_PUL254-hor2.AT2",
    "El Centro 180": "RSN6_IMPVALL.I_I-ELC180-hor1.AT2",
    "Sylmar 090 (M5 aftershock, 0.086 g)": "RSN1690_NORTH151_SYL090-hor1.AT2",
}


def config(base, link, mass, period, model, record):
    text = base.replace("mass = 1.0e8 ", f"mass = {mass:e} ").replace("w0 = 6.3 ", f"w0 = {2 * math.pi / period!r} ")
    text = re.sub(r'file = "[^"]+AT2"', f'file = "{ROOT / "ground_motions" / record}"', text, count=1)
    if model == "link":
        text = text.replace("[joint]\n", '[joint]\nmodel = "link"\n', 1) + "\n" + link
    return text


def run(binary, path, *extra):
    p = subprocess.run([binary, "simulate", str(path), "--json", *extra], capture_output=True, text=True)
    if not p.stdout:
        raise SystemExit(f"{path}: {p.stderr}")
    return json.loads(p.stdout)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("link", help="link.toml written by quakejoint calibrate")
    ap.add_argument("--work", default="link_study", help="folder for the configs (default link_study)")
    ap.add_argument("--quakejoint", default="quakejoint", help="the command (default: quakejoint on PATH)")
    ap.add_argument("--opensees", action="store_true",
                    help="run the link in OpenSees (link_opensees.py beside the link.toml) instead of quakejoint")
    a = ap.parse_args(argv)
    if a.opensees:
        sys.path.insert(0, str(ROOT / "scripts" / "opensees"))
        import link_sdof
    base = (ROOT / "configs" / "paper.toml").read_text()
    base = base[: base.index("[sweep]")]
    link = Path(a.link).read_text()
    link = link[link.index("[joint.link]"):]
    work = Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    print("| deck | T [s] | record | Sa detailed / link [m/s^2] | Sa | peak force detailed / link [kN] | force | "
          "friction energy | joint's effect on Sa, detailed / link |")
    print("|---|---|---|---|---|---|---|---|---|")
    for mass in (1e6, 1e7):
        for period in (0.5, 1.0, 2.0, 4.0):
            for name, record in RECORDS.items():
                out = {}
                for model in ("detailed", "link"):
                    path = work / f"{model}_{mass:.0e}_{period}_{record}.toml"
                    path.write_text(config(base, link, mass, period, model, record))
                    if model == "link" and a.opensees:
                        out[model] = link_sdof.run(Path(a.link).parent / "link_opensees.py", mass, period, 0.05,
                                                   ROOT / "ground_motions" / record)
                    else:
                        out[model] = run(a.quakejoint, path)
                alone = run(a.quakejoint, path, "--no-joint")["sa"]
                d, k = out["detailed"], out["link"]
                rel = lambda key: 100 * (k[key] / d[key] - 1)  # noqa: E731
                print(f"| {mass:.0e} kg | {period} | {name} | {d['sa']:.4f} / {k['sa']:.4f} | {rel('sa'):+.1f} % | "
                      f"{d['peak_joint_force'] / 1e3:.0f} / {k['peak_joint_force'] / 1e3:.0f} | "
                      f"{rel('peak_joint_force'):+.1f} % | {rel('friction_energy'):+.1f} % | "
                      f"{100 * (d['sa'] / alone - 1):+.1f} / {100 * (k['sa'] / alone - 1):+.1f} % |", flush=True)


if __name__ == "__main__":
    main()

"""Exports the modes of an openseespy model as a quakejoint modes file
(format "quakejoint-modes-1", docs/bridge.md, "The modes file").

For the reference three-span bridge (three_span.py):

    python scripts/opensees/export_modes.py --output modes.toml
    python scripts/opensees/export_modes.py --modes all --damping 0.05 \
        --output tests/data/three_span/modes.toml

For your own model: build it in openseespy, then call

    from export_modes import export_modes
    export_modes(points=[("left end", 101, "x"), ("right end", 257, "x")],
                 n_modes=40, output="modes.toml", source="my bridge, ...")

`points` are (name, node tag, direction) with direction "x" (along the
bridge) or "y" (across); `dofs` maps a direction to the OpenSees DOF
number (default x -> 1, y -> 2, which is right for a 3-D model with X along
and Y across the bridge; change it if your axes differ). The model must
have its masses (nodal, or element masses: the mass matrix is assembled by
OpenSees itself) and its boundary conditions; multi-point constraints
(equalDOF, rigidLink) are not supported by the influence vector used here
(one at every free DOF along the direction).

What it does, all with OpenSees' own matrices:
  1. eigen analysis (`-fullGenLapack` by default: every mode of a small
     model; use `--solver genBandArpack` for a large one);
  2. assembles the mass matrix M (integrator GimmeMCK) and mass-normalises
     each eigenvector (phi^T M phi = 1; OpenSees' are normalised already:
     the factor is checked and applied anyway);
  3. Gamma_x = phi^T M r_x with r_x = 1 at each free DOF along x;
  4. the static flexibility between the points (a static analysis per
     point with a unit force there) and ground_x, the static displacement
     of each point relative to the ground under a ground acceleration of
     +1 m/s^2 along x, i.e. under the body force -M r_x: ground_x =
     -K^-1 M r_x [m/(m/s^2) = s^2], negative along x.
"""
import argparse
import contextlib
import math
import os
import sys
from pathlib import Path

import numpy as np
import openseespy.opensees as ops

FORMAT = "quakejoint-modes-1"


@contextlib.contextmanager
def _quiet():
    """Silences OpenSees' C++ messages (written to the process's stderr)."""
    sys.stderr.flush()
    saved = os.dup(2)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)


def opensees_version():
    """'OpenSees 3.7.1 (openseespy 3.7.1.2)'."""
    from importlib.metadata import version

    try:
        py = version("openseespy")
    except Exception:  # pragma: no cover - not installed as a distribution
        py = "?"
    return f"OpenSees {ops.version()} (openseespy {py})"


def assembled_matrix(m, c, k):
    """OpenSees' own m M + c C + k K over its equations (dense, N x N)."""
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.algorithm("Linear")
    ops.integrator("GimmeMCK", m, c, k)
    ops.analysis("Transient")
    with _quiet():
        # the solve fails where the matrix is singular (massless DOFs in M):
        # the matrix is assembled before and printA returns it unchanged
        ops.analyze(1, 0.0)
    n = ops.systemSize()
    a = np.array(ops.printA("-ret")).reshape(n, n)
    ops.wipeAnalysis()
    return a


def equation_map():
    """{(node tag, dof 1-based): equation number} of the free DOFs."""
    eqs = {}
    for tag in ops.getNodeTags():
        for d, q in enumerate(ops.nodeDOFs(tag)):
            if q >= 0:
                eqs[(tag, d + 1)] = q
    return eqs


def influence_vector(eqs, n, dof):
    """r: 1 at every free DOF number `dof` (a ground motion along it)."""
    r = np.zeros(n)
    for (tag, d), q in eqs.items():
        if d == dof:
            r[q] = 1.0
    return r


def eigen(n_modes, solver="-fullGenLapack"):
    """OpenSees eigen analysis; returns the eigenvalues w^2 [rad^2/s^2]."""
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    args = [solver] if solver else []
    with _quiet():  # fullGenLapack warns that it is slow
        lam = ops.eigen(*args, n_modes)
    return np.asarray(lam, dtype=float)


def mode_vectors(eqs, n, n_modes):
    """Eigenvectors over the equations, one column per mode (as OpenSees has
    them)."""
    phi = np.zeros((n, n_modes))
    for (tag, d), q in eqs.items():
        for i in range(n_modes):
            phi[q, i] = ops.nodeEigenvector(tag, i + 1, d)
    return phi


def _static_displacements(loads, points, dofs):
    """Linear static analysis under nodal forces {(tag, dof): F [N]};
    returns the displacements at the points [m]. Leaves the domain as
    found (pattern removed, state reset)."""
    ndf_of = {tag: len(ops.nodeDisp(tag)) for tag in ops.getNodeTags()}
    ops.wipeAnalysis()
    ops.timeSeries("Constant", 990001)
    ops.pattern("Plain", 990001, 990001)
    per_node = {}
    for (tag, d), f in loads.items():
        per_node.setdefault(tag, [0.0] * ndf_of[tag])[d - 1] += f
    for tag, f in per_node.items():
        ops.load(tag, *f)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.algorithm("Linear")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("the static analysis failed (is the model stable without its masses?)")
    u = np.array([ops.nodeDisp(tag, dofs[direction]) for _, tag, direction in points])
    ops.remove("loadPattern", 990001)
    ops.remove("timeSeries", 990001)
    ops.wipeAnalysis()
    ops.reset()
    ops.setTime(0.0)
    return u


def modal_data(points, n_modes, solver="-fullGenLapack", dofs=None, static=True, plan=False):
    """Everything the modes file holds, from the current openseespy model.

    points: [(name, node tag, direction)]; n_modes: number of modes, or
    None for every mode with a finite frequency (fullGenLapack only).
    Returns a dict: periods [s], omega [rad/s], shapes (n_modes x n_points)
    [kg^-0.5], gamma_x, gamma_y [kg^0.5], total_mass_x, total_mass_y [kg],
    flexibility [m/N] and ground_x [s^2] (if static), and the checks:
    normalisation (the factors OpenSees' vectors were scaled by) and
    orthogonality (max |Phi^T M Phi - I|).

    A 2-D model is taken as an elevation (X along the bridge, Y vertical):
    its DOF 2 is vertical, and a point across the bridge ("y") is refused
    unless `plan=True` says the model is a plan view (Y horizontal, across).
    """
    ndm = len(ops.nodeCoord(ops.getNodeTags()[0]))
    if dofs is None:
        dofs = {"x": 1, "y": 2} if ndm == 3 else {"x": 1}
    if ndm == 2 and "y" in dofs and not plan:
        raise ValueError(
            "a 2-D model's DOF 2 is vertical in an elevation of the bridge, not across it: quakejoint's y is "
            "horizontal, across the bridge. Give points along x only, or pass plan=True for a model in plan view"
        )
    for name, tag, direction in points:
        if direction not in dofs:
            raise ValueError(f"point {name!r}: direction {direction!r} is not one of {sorted(dofs)}")
    names = [p[0] for p in points]
    if len(set(zip(names, (p[2] for p in points)))) != len(points):
        raise ValueError("a point (name, direction) is given twice")

    mass = assembled_matrix(1.0, 0.0, 0.0)
    n = mass.shape[0]
    n_massive = int(np.count_nonzero(np.abs(mass).sum(axis=1)))
    if n_modes is None:
        if solver != "-fullGenLapack":
            raise ValueError("all modes: only with the -fullGenLapack solver")
        n_modes = n_massive
    lam = eigen(n_modes, solver)
    if len(lam) < n_modes or not np.all(np.isfinite(lam)) or np.any(lam <= 0):
        raise RuntimeError(
            f"OpenSees returned {len(lam)} eigenvalues, not all finite and positive; "
            f"the model has {n_massive} DOFs with mass"
        )
    eqs = equation_map()
    phi = mode_vectors(eqs, n, n_modes)
    modal_mass = np.einsum("qi,qp,pi->i", phi, mass, phi)
    scale = 1.0 / np.sqrt(modal_mass)
    phi = phi * scale
    ortho = float(np.max(np.abs(phi.T @ mass @ phi - np.eye(n_modes))))

    out = {
        "n_equations": n,
        "n_massive": n_massive,
        "omega": np.sqrt(lam),
        "periods": 2 * math.pi / np.sqrt(lam),
        "normalisation": scale,
        "orthogonality": ortho,
        "mass": mass,
        "phi": phi,
        "eqs": eqs,
    }
    for direction, dof in dofs.items():
        r = influence_vector(eqs, n, dof)
        out[f"gamma_{direction}"] = phi.T @ mass @ r
        out[f"total_mass_{direction}"] = float(r @ mass @ r)
        out[f"r_{direction}"] = r
    rows = [eqs[(tag, dofs[direction])] for _, tag, direction in points]
    out["shapes"] = phi[rows, :].T  # n_modes x n_points

    if static:
        flex = np.zeros((len(points), len(points)))
        for j, (_, tag, direction) in enumerate(points):
            flex[:, j] = _static_displacements({(tag, dofs[direction]): 1.0}, points, dofs)
        out["flexibility"] = flex
        # body force -M r_x of a ground acceleration of +1 m/s^2 along x
        f = -(mass @ out["r_x"])
        loads = {key: f[q] for key, q in eqs.items() if f[q] != 0.0}
        out["ground_x"] = _static_displacements(loads, points, dofs)
    return out


def _fmt(v):
    """A float as TOML (shortest repr that reads back exactly)."""
    v = float(v)
    if not math.isfinite(v):
        raise ValueError(f"not a finite number: {v}")
    return repr(v)


def _toml_str(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def modes_toml(data, points, source, header=(), damping=None, write_y=None):
    """The text of the modes file."""
    lines = ["# quakejoint modal bridge (docs/bridge.md, \"The modes file\")"]
    lines += [f"# {h}" for h in header]
    lines += [
        f'format = "{FORMAT}"',
        f"source = {_toml_str(source)}",
        f"total_mass_x = {_fmt(data['total_mass_x'])}  # [kg] sum of the masses a ground acceleration along x excites",
        "",
    ]
    for name, tag, direction in points:
        lines += ["[[point]]", f"name = {_toml_str(name)}  # node {tag}", f'direction = "{direction}"', ""]
    if write_y is None:
        write_y = "gamma_y" in data and np.any(data["gamma_y"] != 0.0)
    for i in range(len(data["periods"])):
        lines += [
            "[[mode]]",
            f"# mode {i + 1}: f = {data['omega'][i] / (2 * math.pi):.6g} Hz, "
            f"effective mass x {data['gamma_x'][i] ** 2 / data['total_mass_x']:.4%}",
            f"period = {_fmt(data['periods'][i])}",
        ]
        if damping is not None:
            lines.append(f"damping = {_fmt(damping)}")
        lines.append(f"participation_x = {_fmt(data['gamma_x'][i])}")
        if write_y:
            lines.append(f"participation_y = {_fmt(data['gamma_y'][i])}")
        lines += ["shape = [" + ", ".join(_fmt(v) for v in data["shapes"][i]) + "]", ""]
    if "flexibility" in data:
        lines += [
            "[static]",
            "# full model's static flexibility between the points [m/N] (column j: unit force at point j)",
            "flexibility = [",
            *("  [" + ", ".join(_fmt(v) for v in row) + "]," for row in data["flexibility"]),
            "]",
            "# static displacement relative to the ground under a ground acceleration of",
            "# +1 m/s^2 along x (body force -M r_x): -K^-1 M r_x [s^2], negative along x",
            "ground_x = [" + ", ".join(_fmt(v) for v in data["ground_x"]) + "]",
            "",
        ]
    return "\n".join(lines)


def default_mode_count(f_max=50.0, n_max=40, solver="-fullGenLapack"):
    """Modes below f_max [Hz], at most n_max (at least one)."""
    lam = eigen(n_max, solver)
    f = np.sqrt(lam) / (2 * math.pi)
    return max(1, int(np.count_nonzero(f < f_max)))


def export_modes(points, n_modes, output, source, header=(), solver="-fullGenLapack",
                 dofs=None, damping=None, static=True, verbose=True, plan=False):
    """Exports the current openseespy model's modes to `output` (TOML).
    Returns modal_data's dict."""
    data = modal_data(points, n_modes, solver=solver, dofs=dofs, static=static, plan=plan)
    text = modes_toml(data, points, source, header=header, damping=damping)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    Path(output).write_text(text + "\n")
    if verbose:
        eff = data["gamma_x"] ** 2 / data["total_mass_x"]
        print(f"{output}: {len(data['periods'])} modes, T = {data['periods'][0]:.4f} .. "
              f"{data['periods'][-1]:.4g} s; effective mass in x {eff.sum():.4%} of "
              f"{data['total_mass_x']:.6g} kg")
        print(f"  mass normalisation: OpenSees' vectors scaled by {data['normalisation'].min():.12g} .. "
              f"{data['normalisation'].max():.12g}; max |Phi^T M Phi - I| = {data['orthogonality']:.2e}")
        if eff.sum() < 0.9:
            print("  warning: the modes hold less than 90 % of the mass along x: export more", file=sys.stderr)
    return data


def main(argv=None):
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import three_span

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--modes", default=None,
                    help="number of modes, or 'all' (every mode of the model); default: the "
                         "modes below 50 Hz, at most 40")
    ap.add_argument("--output", required=True, help="modes file to write (TOML)")
    ap.add_argument("--damping", type=float, default=None,
                    help="damping ratio to write with every mode (default: none written, "
                         "the config's bridge.damping applies)")
    ap.add_argument("--solver", default="-fullGenLapack",
                    help="OpenSees eigen solver flag (default -fullGenLapack; '' for OpenSees' default)")
    ap.add_argument("--no-static", action="store_true", help="leave out the [static] table")
    a = ap.parse_args(argv)

    model = three_span.build()
    if a.modes is None:
        n = default_mode_count(solver=a.solver)
        how = "default: modes below 50 Hz, at most 40"
    elif a.modes == "all":
        n = None
        how = "all modes"
    else:
        n = int(a.modes)
        how = f"{n} modes"
    cmd = "python scripts/opensees/export_modes.py " + " ".join(argv if argv is not None else sys.argv[1:])
    source = (f"three-span reference bridge, scripts/opensees/three_span.py; {opensees_version()}, "
              f"eigen {a.solver or 'default solver'}")
    header = [
        f"produced by: {cmd}",
        f"({how}; {opensees_version()}, numpy {np.__version__})",
        f"model: {three_span.summary(model)}",
    ]
    export_modes(model.points, n, a.output, source, header=header, solver=a.solver,
                 damping=a.damping, static=not a.no_static)


if __name__ == "__main__":
    main()

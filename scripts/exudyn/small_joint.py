"""Independent Exudyn model of quakejoint's *small* expansion joint on its
single-DOF bridge deck: the reference data of tests/data/exudyn/.

What it models (the physical model of the project's spec, joint-model.md,
and docs/model.md; parameters of configs/small.toml with the defaults of
docs/config.md), written apart from quakejoint's code, in Exudyn's own
elements wherever Exudyn has one:

Bodies (planar, coordinates x, y, phi of the centre of mass, each an
Exudyn ``NodeRigidBody2D`` + ``ObjectRigidBody2D``), 15 joint bodies:

- 3 center beams (900 kg, 16875 kg m^2), at (i s0, 0), phi = 0, s0 = 0.13 m;
- the guide (600 kg, 2812.5 kg m^2) at (G0/2, -7.2 m), phi = 0, G0 = 4 s0;
- 2 swivel joists (600 kg, 2812.5 kg m^2): pivots (0, -1.0 m) at 13 deg and
  (0, 5.0 m) at 17 deg, the joist axis the line from the pivot
  P = (0, y_P) to the box point B = (G0 + u, y_P + G0 tan theta), the
  centre of mass at the midpoint of P and B at rest, phi = theta;
- 9 bearings (20 kg, 0.3 kg m^2), one where each center beam's axis
  (x = x_i) crosses each support beam's axis, phi = its support beam's;
- the deck, a rigid body with mass m (1e8 kg) whose y and phi are held to
  the ground (``ObjectConnectorCoordinate``), so its one free coordinate
  is x: the opening u. Its reference position is (G0, 0).

Constraints (Exudyn joints, solved with Lagrange multipliers):

- prismatic joint bearing b / support beam s: the bearing's centre on the
  support beam's axis, (A(phi_s) e_y) . (r_b - r_s) = 0
  (``ObjectJointPrismatic2D``, constrainRotation = False), and the
  relative angle kept, phi_b - phi_s - (phi_b0 - phi_s0) = 0
  (``ObjectConnectorCoordinate`` on the two angles) - the spec's two
  equations, g1 in its linear form;
- revolute joint joist pivot / abutment (``ObjectJointRevolute2D``);
- joist box: the deck point B_j(u) on the joist axis,
  (A(phi_s) e_y) . (B_j(u) - r_s) = 0 (``ObjectJointPrismatic2D`` between
  a marker on the deck at B_j and the joist, constrainRotation = False);
  the deck's only connection to the joint;
- weld guide / abutment: x, y, phi of the guide held (three
  ``ObjectConnectorCoordinate``).

Force elements:

- bridge spring and damper -k u - c u' on the deck, k = m w0^2,
  c = 2 zeta m w0 (``ObjectConnectorCoordinateSpringDamper``);
- bushing between bearing (i, k) and center beam i, attachment point on the
  beam r_SP = (0, y_ik) (the bearing's reference position in the beam's
  frame), on the bearing its centre. With
  d = r_b - (r_c + A(phi_c) r_SP), d_l = A(phi_c)^T d, K = diag(kx, ky):
  the elastic forces and moments are -grad V of V = 1/2 d_l^T K d_l
  (bearing: -A K d_l; beam: +A K d_l and the moment
  (r_SP + d_l) x (K d_l), in the beam's axes - so the element is
  conservative also when kx != ky); the damping force on the bearing is
  -A C A^T d', C = diag(cx, cy), d' the relative velocity of the two
  attachment points, its reaction on the beam at the attachment point.
  kx = ky = 1e7 N/m, cx = cy = 2e3 N s/m. Exudyn has no planar bushing with
  the stiffness in a turning body frame and the potential form, so this is
  a Python user function (``ObjectGenericODE2`` forceUserFunction);
  ``--bushing cartesian`` uses Exudyn's own
  ``ObjectConnectorCartesianSpringDamper`` instead (global axes, exact only
  for kx = ky and cx = cy, the defaults) as a check of that user function;
- sliding friction between bearing (i, k) and support beam k: v_rel = the
  bearing centre's velocity minus the velocity of the support beam's
  material point at the same place, v_b - v_s - omega_s x (r_b - r_s);
  force on the bearing F = -mu n_s F_N v_rel / max(|v_rel|, v_eps)
  (``--friction smooth``: / sqrt(|v_rel|^2 + v_eps^2)), the reaction -F on
  the support beam at the bearing's position (with its moment).
  mu = 0.05, F_N = 20 kN, n_s = 2, v_eps = 1e-3 m/s. A Python user function
  (``ObjectGenericODE2``; Exudyn has no regularised Coulomb law between two
  planar rigid bodies);
- earthquake: -m_body a_g(t) in x on every body including the deck, a_g the
  record's samples joined linearly (sample j at t = j dt), PEER AT2 in g,
  g = 9.80665 m/s^2, times --scale. In the same user function (it depends
  on t only).

Integration: Exudyn's generalized-alpha (index 3, Lagrange multipliers,
spectral radius 0.6), fixed step h dividing the record's step (0.005 s), so
that no step crosses a sample of the piecewise-linear ground motion;
modified Newton (tolerances 1e-10) with Exudyn's numerical Jacobian of the
user-function forces. Converged when halving h does not change the results
(run --h 1e-4 and --h 5e-5). With spectral radius 0.9 the deck's motion is
the same, but the multipliers (the joint force) carry a high-frequency
noise of about 0.1 N (0.3 N at the peaks) that a smaller h makes worse.

What it reports (docs/model.md, "What a run reports"), from the state at
every step:

- the joint force on the deck: the x component of the joist-box
  constraints' reaction, lambda_j (A(phi_j) e_y)_x summed over the joists
  (lambda_j Exudyn's multiplier of the box constraint g_j, Exudyn's
  equations being M q'' + g_q^T lambda = f); checked against the deck's
  force balance m (u'' + a_g) + k u + c u' with Exudyn's accelerations;
- a_abs = (-k u - c u' + F_joint) / m (the force balance, not differenced);
- Sa = max |a_abs|, Sd = max |u|, Sv = max |u'|, taken at the record's
  sample times (quakejoint's convention); the peak joint force, the peak
  bushing force (elastic + damping) and friction force of one element, at
  every step and (``_at_samples``) at the record's sample times;
- the friction energy, the time integral of sum mu n_s F_N |v_rel|^2 /
  max(|v_rel|, v_eps) (trapezoidal rule over the steps);
- the clear sub-gaps at both ends of the center beams (y = -L/2 and +L/2):
  the x distance between neighbouring centre lines there (x_c -+ (L/2)
  sin phi; the abutment line x = 0, the deck line x = G0 + u) minus the
  width w_c = 0.09 m, smallest and largest over all steps and at the
  record's sample times, and their largest deviation from equal spacing
  (G0 + u)/(Nc + 1) - w_c;
- the energy balance (kinetic + stored + dissipated - work of the
  earthquake load, over the largest |work|), a check of the model itself.

Run (from the checkout's root, in a virtual environment with
``pip install -r scripts/exudyn/requirements.txt``):

    python scripts/exudyn/small_joint.py --h 5e-5 \\
        --history tests/data/exudyn/exudyn_small_quick.csv \\
        --summary tests/data/exudyn/exudyn_small_quick.json

(about 6 minutes; --h 1e-4 takes two thirds of that).

``--help`` lists the options (step, record scale and duration, deck period,
damping and mass, Newton tolerance, spectral radius, friction law, bushing
element). tests/data/exudyn/README.md gives the exact commands of every
stored file.
"""
import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

import exudyn as exu
from exudyn.itemInterface import (
    MarkerBodyPosition,
    MarkerBodyRigid,
    MarkerNodeCoordinate,
    NodePointGround,
    NodeRigidBody2D,
    ObjectConnectorCartesianSpringDamper,
    ObjectConnectorCoordinate,
    ObjectConnectorCoordinateSpringDamper,
    ObjectGenericODE2,
    ObjectGround,
    ObjectJointPrismatic2D,
    ObjectJointRevolute2D,
    ObjectRigidBody2D,
)

G = 9.80665  # [m/s^2]
HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_RECORD = os.path.join(HERE, "..", "..", "ground_motions", "RSN753_LOMAP_CLS090-hor2.AT2")


# ---------------------------------------------------------------- inputs


def read_at2(path):
    """(dt [s], acceleration [m/s^2]) of a PEER NGA AT2 file (values in g)."""
    with open(path) as f:
        lines = f.read().splitlines()
    head = lines[3].replace(",", " ").replace("=", " = ").split()
    npts = int(head[head.index("NPTS") + 2])
    dt = float(head[head.index("DT") + 2])
    acc = np.array([float(v) for line in lines[4:] for v in line.split()])
    if len(acc) != npts:
        raise ValueError(f"{path}: NPTS = {npts} but {len(acc)} values")
    return dt, acc * G


class Ground:
    """a_g(t): the samples joined linearly, sample j at t = j dt, 0 after the
    last sample."""

    def __init__(self, dt, acc):
        self.dt, self.acc = dt, acc

    def __call__(self, t):
        s = t / self.dt
        j = int(math.floor(s + 1e-9))
        if j < 0:
            return 0.0
        if j >= len(self.acc) - 1:
            return float(self.acc[-1]) if abs(s - (len(self.acc) - 1)) < 1e-9 else 0.0
        r = min(max(s - j, 0.0), 1.0)
        return float(self.acc[j] + r * (self.acc[j + 1] - self.acc[j]))


def model_parameters(args):
    """The small joint (configs/small.toml) with the defaults of
    docs/config.md, and the case's bridge."""
    p = dict(
        nc=3,
        pitch=0.13,
        lc=15.0,
        width=0.09,
        m_c=900.0,
        m_s=600.0,
        ls=7.5,
        m_b=20.0,
        i_b=0.3,
        kx=1e7,
        ky=1e7,
        cx=2e3,
        cy=2e3,
        mu=0.05,
        normal_force=2e4,
        surfaces=2.0,
        v_eps=1e-3,
        law=args.friction,
        # (kind, y [m], angle [deg]) as configs/small.toml
        supports=[("guide", -7.2, 0.0), ("joist", -1.0, 13.0), ("joist", 5.0, 17.0)],
        deck_mass=args.deck_mass,
        period=args.period,
        damping=args.damping,
    )
    p["i_c"] = p["m_c"] * p["lc"] ** 2 / 12
    p["i_s"] = p["m_s"] * p["ls"] ** 2 / 12
    p["gap"] = (p["nc"] + 1) * p["pitch"]
    w0 = 2 * math.pi / p["period"]
    p["w0"] = w0
    p["k_deck"] = p["deck_mass"] * w0 ** 2
    p["c_deck"] = 2 * p["damping"] * p["deck_mass"] * w0
    return p


# ---------------------------------------------------------------- force laws


def rot(phi):
    c, s = math.cos(phi), math.sin(phi)
    return c, s  # A = [[c, -s], [s, c]]


def bushing(p, rc, phic, vc, omc, rb, vb, rsp_y):
    """Bushing between a center beam (rc, phic, vc, omc) and a bearing
    (rb, vb), attachment point (0, rsp_y) on the beam. Returns the force on
    the bearing (fbx, fby), the force (fcx, fcy) and the moment mc on the
    center beam, the stored energy, the damper's power and the force's
    magnitude (elastic + damping)."""
    c, s = rot(phic)
    # attachment point on the beam, in global axes: A r_SP
    ax, ay = -s * rsp_y, c * rsp_y
    dx, dy = rb[0] - rc[0] - ax, rb[1] - rc[1] - ay
    # deflection in the beam's axes d_l = A^T d
    dlx, dly = c * dx + s * dy, -s * dx + c * dy
    flx, fly = p["kx"] * dlx, p["ky"] * dly  # K d_l (local)
    # elastic force on the bearing -A K d_l
    fbx, fby = -(c * flx - s * fly), -(s * flx + c * fly)
    # moment on the beam: -dV/dphi_c = (r_SP + d_l) x (K d_l) (local axes)
    mc = dlx * fly - (rsp_y + dly) * flx
    energy = 0.5 * (dlx * flx + dly * fly)
    # damper: d' = v_b - (v_c + omega_c x A r_SP); -A C A^T d' on the bearing
    ddx, ddy = vb[0] - (vc[0] - omc * ay), vb[1] - (vc[1] + omc * ax)
    dlx_t, dly_t = c * ddx + s * ddy, -s * ddx + c * ddy
    clx, cly = p["cx"] * dlx_t, p["cy"] * dly_t
    gdx, gdy = -(c * clx - s * cly), -(s * clx + c * cly)
    fbx += gdx
    fby += gdy
    damper_power = dlx_t * clx + dly_t * cly
    # reaction on the beam at the attachment point: -f_b; the damping
    # reaction's moment (A r_SP) x (-g_d) joins the elastic moment
    mc += ax * (-gdy) - ay * (-gdx)
    return (fbx, fby), (-fbx, -fby), mc, energy, damper_power, math.hypot(fbx, fby)


def friction(p, rb, vb, rs, vs, oms):
    """Sliding friction of a bearing (rb, vb) on its support beam (rs, vs,
    oms). Returns the force on the bearing, the force and moment on the
    support beam, the dissipated power and |F|."""
    rx, ry = rb[0] - rs[0], rb[1] - rs[1]
    # v_rel = v_b - (v_s + omega_s x (r_b - r_s))
    wx, wy = vb[0] - (vs[0] - oms * ry), vb[1] - (vs[1] + oms * rx)
    speed = math.hypot(wx, wy)
    f0 = p["mu"] * p["surfaces"] * p["normal_force"]
    if p["law"] == "smooth":
        scale = f0 / math.sqrt(speed * speed + p["v_eps"] ** 2)
    else:
        scale = f0 / max(speed, p["v_eps"])
    fx, fy = -scale * wx, -scale * wy
    # reaction -F on the support beam at the bearing's position
    ms = rx * (-fy) - ry * (-fx)
    return (fx, fy), (-fx, -fy), ms, scale * speed * speed, scale * speed


# ---------------------------------------------------------------- model


class SmallJoint:
    def __init__(self, args):
        self.args = args
        self.p = p = model_parameters(args)
        dt, acc = read_at2(args.record)
        self.record_dt = dt
        self.ag = Ground(dt, acc * args.scale)
        self.pga = float(np.max(np.abs(acc * args.scale)))

        SC = exu.SystemContainer()
        mbs = SC.AddSystem()
        self.SC, self.mbs = SC, mbs
        ground = mbs.AddObject(ObjectGround(referencePosition=[0, 0, 0]))
        ground_node = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
        m_gc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0))

        nodes, bodies, ref, masses, inertias, labels = [], [], [], [], [], []

        def body(x, y, phi, m, inertia, label):
            n = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[x, y, phi], initialVelocities=[0, 0, 0]))
            b = mbs.AddObject(ObjectRigidBody2D(mass=m, inertia=inertia, nodeNumber=n))
            nodes.append(n)
            bodies.append(b)
            ref.append((x, y, phi))
            masses.append(m)
            inertias.append(inertia)
            labels.append(label)
            return len(nodes) - 1

        nc, gap = p["nc"], p["gap"]
        self.cx0 = [(i + 1) * p["pitch"] for i in range(nc)]
        # center beams
        self.cb = [body(x, 0.0, 0.0, p["m_c"], p["i_c"], f"center beam {i + 1}") for i, x in enumerate(self.cx0)]
        # support beams
        self.sb, self.joists, self.guides = [], [], []
        for k, (kind, y, ang) in enumerate(p["supports"]):
            th = math.radians(ang)
            if kind == "guide":
                idx = body(gap / 2, y, 0.0, p["m_s"], p["i_s"], f"guide {k}")
                self.guides.append(idx)
            else:
                bx, by = gap, y + gap * math.tan(th)
                idx = body(bx / 2, (y + by) / 2, th, p["m_s"], p["i_s"], f"joist {k}")
                self.joists.append((idx, y, th, math.hypot(bx, by - y)))
            self.sb.append((idx, kind, y, th))
        # bearings
        self.bearings = []  # (index, center beam index, support beam index, y on the beam)
        for i, x in enumerate(self.cx0):
            for k, (idx_s, kind, y, th) in enumerate(self.sb):
                yb = y if kind == "guide" else y + x * math.tan(th)
                if abs(yb) > p["lc"] / 2:
                    raise ValueError(f"bearing ({i + 1}, {k}) at y = {yb} lies outside the center beam")
                idx = body(x, yb, th, p["m_b"], p["i_b"], f"bearing ({i + 1},{k})")
                self.bearings.append((idx, self.cb[i], idx_s, yb))
        # the deck: x free (u), y and phi held
        self.deck = body(gap, 0.0, 0.0, p["deck_mass"], p["deck_mass"], "deck")
        self.nodes, self.bodies = nodes, bodies
        self.ref = np.array(ref)
        self.masses, self.inertias, self.labels = np.array(masses), np.array(inertias), labels
        self.n_joint_bodies = len(nodes) - 1

        def coord_marker(i, c):
            return mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[i], coordinate=c))

        def rigid_marker(i, local=(0.0, 0.0)):
            return mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[i], localPosition=[local[0], local[1], 0.0]))

        n_eq = 0
        # deck: y and phi to the ground; spring and damper on x
        for c in (1, 2):
            mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[m_gc, coord_marker(self.deck, c)]))
        mbs.AddObject(
            ObjectConnectorCoordinateSpringDamper(
                markerNumbers=[m_gc, coord_marker(self.deck, 0)], stiffness=p["k_deck"], damping=p["c_deck"]
            )
        )
        # weld: guide to the abutment
        for g in self.guides:
            for c in (0, 1, 2):
                mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[m_gc, coord_marker(g, c)]))
                n_eq += 1
        # joists: pivot (revolute to ground) and box (deck point on the joist axis)
        self.box_constraints = []
        for idx, y, th, length in self.joists:
            m_pivot_g = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[0.0, y, 0.0]))
            m_pivot_j = mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodies[idx], localPosition=[-length / 2, 0.0, 0.0]))
            mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[m_pivot_g, m_pivot_j]))
            n_eq += 2
            m_box = rigid_marker(self.deck, (0.0, y + gap * math.tan(th)))
            con = mbs.AddObject(
                ObjectJointPrismatic2D(
                    markerNumbers=[m_box, rigid_marker(idx)],
                    axisMarker0=[1.0, 0.0, 0.0],
                    normalMarker1=[0.0, 1.0, 0.0],
                    constrainRotation=False,
                )
            )
            n_eq += 1
            self.box_constraints.append((con, idx))
        # bearings: prismatic joint on the support beam
        for idx, ic, js, yb in self.bearings:
            mbs.AddObject(
                ObjectJointPrismatic2D(
                    markerNumbers=[rigid_marker(idx), rigid_marker(js)],
                    axisMarker0=[1.0, 0.0, 0.0],
                    normalMarker1=[0.0, 1.0, 0.0],
                    constrainRotation=False,
                )
            )
            mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[coord_marker(js, 2), coord_marker(idx, 2)]))
            n_eq += 2
        self.n_constraints = n_eq
        # bushings through Exudyn's own element (check: kx = ky, cx = cy only)
        if args.bushing == "cartesian":
            if p["kx"] != p["ky"] or p["cx"] != p["cy"]:
                raise ValueError("--bushing cartesian needs kx = ky and cx = cy")
            for idx, ic, js, yb in self.bearings:
                mbs.AddObject(
                    ObjectConnectorCartesianSpringDamper(
                        markerNumbers=[
                            mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodies[ic], localPosition=[0.0, yb, 0.0])),
                            mbs.AddMarker(MarkerBodyPosition(bodyNumber=bodies[idx], localPosition=[0.0, 0.0, 0.0])),
                        ],
                        stiffness=[p["kx"], p["ky"], 0.0],
                        damping=[p["cx"], p["cy"], 0.0],
                    )
                )
        # the user-function forces: bushings, friction, earthquake
        n = 3 * len(nodes)
        self.forces_obj = mbs.AddObject(
            ObjectGenericODE2(
                nodeNumbers=nodes,
                massMatrix=np.zeros((n, n)),
                forceUserFunction=self._user_force,
            )
        )
        mbs.Assemble()
        self.ode2_index = [mbs.GetNodeODE2Index(nd) for nd in nodes]
        if self.ode2_index != list(range(0, n, 3)):
            raise RuntimeError(f"unexpected ODE2 layout {self.ode2_index}")
        self.box_ae = [(mbs.systemData.GetObjectLTGAE(con)[0], idx) for con, idx in self.box_constraints]

    # --- forces -------------------------------------------------------------

    def joint_forces(self, t, X, V, with_eq=True, stats=None):
        """Generalised forces of the bushings, friction and earthquake on all
        coordinates (X total positions, V velocities, both (nbody, 3))."""
        p = self.p
        f = np.zeros(X.shape)
        e_bush = d_bush = p_fric = 0.0
        fb_max = ff_max = 0.0
        if self.args.bushing == "user":
            for idx, ic, js, yb in self.bearings:
                (fbx, fby), (fcx, fcy), mc, e, dp, mag = bushing(p, X[ic], X[ic, 2], V[ic], V[ic, 2], X[idx], V[idx], yb)
                f[idx, 0] += fbx
                f[idx, 1] += fby
                f[ic, 0] += fcx
                f[ic, 1] += fcy
                f[ic, 2] += mc
                e_bush += e
                d_bush += dp
                fb_max = max(fb_max, mag)
        for idx, ic, js, yb in self.bearings:
            (fx, fy), (sx, sy), ms, pw, mag = friction(p, X[idx], V[idx], X[js], V[js], V[js, 2])
            f[idx, 0] += fx
            f[idx, 1] += fy
            f[js, 0] += sx
            f[js, 1] += sy
            f[js, 2] += ms
            p_fric += pw
            ff_max = max(ff_max, mag)
        if with_eq:
            f[:, 0] -= self.masses * self.ag(t)
        if stats is not None:
            stats.update(e_bush=e_bush, d_bush=d_bush, p_fric=p_fric, fb_max=fb_max, ff_max=ff_max)
        return f

    def _user_force(self, mbs, t, item, q, q_t):
        X = self.ref + np.asarray(q).reshape(-1, 3)
        V = np.asarray(q_t).reshape(-1, 3)
        return self.joint_forces(t, X, V).ravel()

    # --- what a step reports --------------------------------------------------

    def bushing_check(self, X, V):
        """Energy and damper power of the bushings with Exudyn's own element
        (global axes; kx = ky, cx = cy), for the energy balance."""
        p = self.p
        e = d = fmax = 0.0
        for idx, ic, js, yb in self.bearings:
            c, s = rot(X[ic, 2])
            ax, ay = -s * yb, c * yb
            dx, dy = X[idx, 0] - X[ic, 0] - ax, X[idx, 1] - X[ic, 1] - ay
            vx = V[idx, 0] - (V[ic, 0] - V[ic, 2] * ay)
            vy = V[idx, 1] - (V[ic, 1] + V[ic, 2] * ax)
            e += 0.5 * (p["kx"] * dx * dx + p["ky"] * dy * dy)
            d += p["cx"] * vx * vx + p["cy"] * vy * vy
            fmax = max(fmax, math.hypot(p["kx"] * dx + p["cx"] * vx, p["ky"] * dy + p["cy"] * vy))
        return e, d, fmax

    def subgaps(self, X, u):
        """Clear sub-gaps [at y = -L/2, at y = +L/2], abutment side first."""
        half, w = self.p["lc"] / 2, self.p["width"]
        out = []
        prev = np.array([0.0, 0.0])
        for ic in self.cb:
            xe = np.array([X[ic, 0] + half * math.sin(X[ic, 2]), X[ic, 0] - half * math.sin(X[ic, 2])])
            out.append(xe - prev - w)
            prev = xe
        out.append(self.p["gap"] + u - prev - w)
        return np.array(out)

    def record_step(self, mbs, t):
        sd = mbs.systemData
        q = np.asarray(sd.GetODE2Coordinates())
        q_t = np.asarray(sd.GetODE2Coordinates_t())
        q_tt = np.asarray(sd.GetODE2Coordinates_tt())
        lam = np.asarray(sd.GetAECoordinates())
        X = self.ref + q.reshape(-1, 3)
        V = q_t.reshape(-1, 3)
        p = self.p
        d = self.deck
        u, v, acc = q[3 * d], q_t[3 * d], q_tt[3 * d]
        ag = self.ag(t)
        # joint force on the deck: the joist boxes' reactions along x
        fj = 0.0
        for ae, idx in self.box_ae:
            nx = -math.sin(X[idx, 2])  # (A(phi_j) e_y)_x
            fj += lam[ae] * nx
        fj_balance = p["deck_mass"] * (acc + ag) + p["k_deck"] * u + p["c_deck"] * v
        stats = {}
        self.joint_forces(t, X, V, with_eq=False, stats=stats)
        if self.args.bushing == "cartesian":
            e_b, d_b, fb_max = self.bushing_check(X, V)
            stats.update(e_bush=e_b, d_bush=d_b, fb_max=fb_max)
        kinetic = 0.5 * np.sum(self.masses * (V[:, 0] ** 2 + V[:, 1] ** 2) + self.inertias * V[:, 2] ** 2)
        stored = stats["e_bush"] + 0.5 * p["k_deck"] * u * u
        damper = stats["d_bush"] + p["c_deck"] * v * v
        eq_power = -ag * float(np.sum(self.masses * V[:, 0]))
        gaps = self.subgaps(X, u)
        self.rows.append(
            [t, ag, u, v, acc, fj, fj_balance, stats["p_fric"], damper, eq_power, kinetic, stored,
             stats["fb_max"], stats["ff_max"]] + list(gaps.ravel())
        )
        return True

    # --- the run --------------------------------------------------------------

    def run(self):
        a = self.args
        mbs = self.mbs
        self.rows = []
        ss = exu.SimulationSettings()
        n_steps = int(round(a.duration / a.h))
        per_sample = self.record_dt / a.h
        if abs(per_sample - round(per_sample)) > 1e-9:
            raise ValueError(f"--h {a.h} does not divide the record's step {self.record_dt}")
        ti = ss.timeIntegration
        ti.endTime = a.duration
        ti.numberOfSteps = n_steps
        ti.adaptiveStep = False
        ti.verboseMode = 0
        ti.generalizedAlpha.spectralRadius = a.rho
        ti.generalizedAlpha.computeInitialAccelerations = True
        ti.newton.relativeTolerance = a.newton_rtol
        ti.newton.absoluteTolerance = a.newton_atol
        ti.newton.useModifiedNewton = True
        ss.solution.file.write = False
        ss.solution.sensors.writePeriod = 1e9
        ss.show.statistics = False
        ss.show.computationTime = False
        ss.linearSolver.solverType = exu.LinearSolverType.EigenSparse
        mbs.SetPostStepUserFunction(self.record_step)
        t0 = time.perf_counter()
        # Exudyn calls the post-step function also for the initial state
        ok = mbs.SolveDynamic(ss)
        self.wall = time.perf_counter() - t0
        if not ok:
            raise RuntimeError("Exudyn's solver failed")
        it = mbs.sys["dynamicSolver"].it
        self.solver_counts = dict(newton_iterations=int(it.newtonStepsCount), jacobian_evaluations=int(it.newtonJacobiCount))
        return np.array(self.rows)


COLUMNS = ["t", "ag", "u", "v", "u_tt", "joint_force", "joint_force_balance", "friction_power",
           "damper_power", "eq_power", "kinetic", "stored", "bushing_force_max", "friction_force_max"]


def evaluate(model, H):
    """The run's results (docs/model.md, 'What a run reports')."""
    p = model.p
    col = {c: H[:, i] for i, c in enumerate(COLUMNS)}
    nc = p["nc"]
    gaps = H[:, len(COLUMNS):].reshape(len(H), nc + 1, 2)
    t = col["t"]
    # first row: the initial state; Exudyn's post-step call of the last step
    # comes with t = end time
    a_abs = (-p["k_deck"] * col["u"] - p["c_deck"] * col["v"] + col["joint_force"]) / p["deck_mass"]
    per_sample = int(round(model.record_dt / model.args.h))
    steps = np.arange(len(t))
    samples = steps % per_sample == 0
    if not np.allclose(t[samples], model.record_dt * np.arange(samples.sum()), atol=1e-9):
        raise RuntimeError("steps do not land on the record's samples")

    def peak(x, mask=None):
        x = np.abs(x if mask is None else np.where(mask, x, 0.0))
        i = int(np.argmax(x))
        return float(x[i]), float(t[i])

    def cumtrapz(y):
        return np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))])

    friction_energy = cumtrapz(col["friction_power"])
    damper_energy = cumtrapz(col["damper_power"])
    eq_work = cumtrapz(col["eq_power"])
    balance = col["kinetic"] + col["stored"] + friction_energy + damper_energy - eq_work
    equal = (p["gap"] + col["u"]) / (nc + 1) - p["width"]
    sa, t_sa = peak(a_abs, samples)
    sd, t_sd = peak(col["u"], samples)
    sv, t_sv = peak(col["v"], samples)
    fj, t_fj = peak(col["joint_force"])
    fj_s, _ = peak(col["joint_force"], samples)
    mismatch = np.max(np.abs(col["joint_force"] - col["joint_force_balance"]))
    res = dict(
        sa=sa, t_sa=t_sa, sd=sd, t_sd=t_sd, sv=sv, t_sv=t_sv, psa=p["w0"] ** 2 * sd,
        peak_joint_force=fj, t_peak_joint_force=t_fj, peak_joint_force_at_samples=fj_s,
        peak_bushing_force=float(np.max(col["bushing_force_max"])),
        peak_bushing_force_at_samples=float(np.max(col["bushing_force_max"][samples])),
        peak_friction_force=float(np.max(col["friction_force_max"])),
        friction_energy=float(friction_energy[-1]),
        damping_energy=float(damper_energy[-1]),
        earthquake_work=float(eq_work[-1]),
        min_subgap=float(np.min(gaps)), max_subgap=float(np.max(gaps)),
        min_subgap_at_samples=float(np.min(gaps[samples])), max_subgap_at_samples=float(np.max(gaps[samples])),
        max_subgap_deviation=float(np.max(np.abs(gaps - equal[:, None, None]))),
        max_subgap_deviation_at_samples=float(np.max(np.abs(gaps - equal[:, None, None])[samples])),
        energy_error=float(np.max(np.abs(balance)) / np.max(np.abs(eq_work))),
        joint_force_vs_balance_max_abs=float(mismatch),
        steps=int(len(t) - 1), h=model.args.h, duration=float(t[-1]),
    )
    hist = dict(t=t[samples], ag=col["ag"][samples], u=col["u"][samples], v=col["v"][samples],
                a_abs=a_abs[samples], joint_force=col["joint_force"][samples])
    return res, hist


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--record", default=DEFAULT_RECORD, help="PEER AT2 record (default: Corralitos 090 of ground_motions/)")
    ap.add_argument("--scale", type=float, default=0.15, help="record scale factor (default 0.15)")
    ap.add_argument("--duration", type=float, default=10.0, help="simulated time [s] (default 10)")
    ap.add_argument("--period", type=float, default=1.0, help="deck period [s] (default 1.0)")
    ap.add_argument("--damping", type=float, default=0.05, help="deck damping ratio (default 0.05)")
    ap.add_argument("--deck-mass", type=float, default=1e8, help="deck mass [kg] (default 1e8)")
    ap.add_argument("--h", type=float, default=1e-4, help="fixed time step [s], dividing the record's step (default 1e-4)")
    ap.add_argument("--rho", type=float, default=0.6,
                    help="generalized-alpha spectral radius (default 0.6: with 0.9 the multipliers, hence the joint "
                         "force, carry a high-frequency noise of ~0.1 N)")
    ap.add_argument("--newton-rtol", type=float, default=1e-10, help="Newton relative tolerance (default 1e-10)")
    ap.add_argument("--newton-atol", type=float, default=1e-10, help="Newton absolute tolerance (default 1e-10)")
    ap.add_argument("--friction", choices=["linear", "smooth"], default="linear", help="regularisation of the Coulomb law")
    ap.add_argument("--bushing", choices=["user", "cartesian"], default="user",
                    help="bushing as the user function (potential form, default) or Exudyn's CartesianSpringDamper")
    ap.add_argument("--history", help="write the deck's history every record step (CSV)")
    ap.add_argument("--summary", help="write the results (JSON)")
    args = ap.parse_args(argv)

    model = SmallJoint(args)
    H = model.run()
    res, hist = evaluate(model, H)
    # The joist boxes' reaction must match the deck's force balance
    # m (u'' + a_g) + k u + c u' with Exudyn's accelerations (a check of how
    # the multipliers are read, not of the physics).
    if res["joint_force_vs_balance_max_abs"] > 1e-4 * res["peak_joint_force"]:
        raise RuntimeError(f"joint force from the multipliers and from the deck's balance differ by "
                           f"{res['joint_force_vs_balance_max_abs']} N")
    res.update(
        wall_time_s=model.wall,
        **model.solver_counts,
        joint_bodies=model.n_joint_bodies,
        constraint_equations=model.n_constraints,
        coordinates=3 * model.n_joint_bodies + 1,
        record=os.path.basename(args.record), record_scale=args.scale, record_pga_m_s2=model.pga,
        period=args.period, damping=args.damping, deck_mass=args.deck_mass,
        rho=args.rho, newton_rtol=args.newton_rtol, newton_atol=args.newton_atol,
        friction_law=args.friction, bushing=args.bushing,
        exudyn=exu.__version__, numpy=np.__version__, python=platform.python_version(),
        command="python scripts/exudyn/small_joint.py " + " ".join(sys.argv[1:] if argv is None else argv),
    )
    for k in ("sa", "sd", "sv", "peak_joint_force", "peak_bushing_force", "peak_friction_force", "friction_energy",
              "min_subgap", "max_subgap", "max_subgap_deviation", "energy_error", "joint_force_vs_balance_max_abs",
              "steps", "wall_time_s"):
        print(f"{k:32s} {res[k]:.10g}")
    if args.summary:
        with open(args.summary, "w") as f:
            json.dump(res, f, indent=1, sort_keys=True)
            f.write("\n")
    if args.history:
        with open(args.history, "w") as f:
            f.write("t_s,ag_m_s2,u_m,v_m_s,a_abs_m_s2,joint_force_N\n")
            for row in zip(*(hist[c] for c in ("t", "ag", "u", "v", "a_abs", "joint_force"))):
                f.write("%.3f,%.9e,%.9e,%.9e,%.9e,%.6e\n" % row)
    return res


if __name__ == "__main__":
    main()

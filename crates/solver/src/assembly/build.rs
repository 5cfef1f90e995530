//! Compiling a [`System`] into an [`Assembly`].

use std::collections::BTreeSet;

use super::constraints::{AngleK, DriverK, LineK, PointK, PrimRef, Primitive, Primitives};
use super::contact::{ContactK, LawK};
use super::element::{ForceElements, ForceKernel, KindVisitor, ResidualOrder};
use super::forces::{BushingK, CoordSpringK, CustomK, LoadK, SpringK};
use super::friction::FrictionK;
use super::kin::{BodyStatic, Rot, V2};
use super::layout::{EquationSpec, Layout, NONE};
use super::linear::LinearK;
use super::maps::{CoordMap, GEntry, PairMap, PrimMap, Scatter};
use super::Assembly;
use crate::error::BuildError;
use crate::linalg::block_lu::BlockOrdering;
use crate::model::body::Body;
use crate::model::constraint::{Constraint, Linear};
use crate::model::force::ForceElement;
use crate::model::system::System;

/// Options of the compilation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AssemblyOptions {
    /// Block ordering for the elimination.
    pub ordering: BlockOrdering,
}

/// A constraint primitive before its scatter map is known.
enum Prim {
    Point(PointK),
    Angle(AngleK),
    Line(LineK),
    Driver(DriverK),
}

impl Prim {
    fn bodies(&self) -> (u32, u32) {
        match self {
            Prim::Point(k) => k.bodies(),
            Prim::Angle(k) => k.bodies(),
            Prim::Line(k) => k.bodies(),
            Prim::Driver(k) => k.bodies(),
        }
    }

    fn rows(&self) -> usize {
        match self {
            Prim::Point(_) => 2,
            _ => 1,
        }
    }

    /// Slots (0..6 over the two bodies) whose gradient entry can be non-zero, per row.
    fn structural_slots(&self, row: usize) -> Vec<usize> {
        match self {
            Prim::Point(k) => {
                let mut s = vec![row, 3 + row];
                if k.pa.norm() > 0.0 {
                    s.push(2);
                }
                if k.pb.norm() > 0.0 {
                    s.push(5);
                }
                s.sort_unstable();
                s
            }
            Prim::Angle(_) => vec![2, 5],
            Prim::Line(_) => vec![0, 1, 2, 3, 4, 5],
            Prim::Driver(k) => vec![k.slot as usize],
        }
    }
}

fn unit(d: [f64; 2]) -> V2 {
    let v = V2::from(d);
    v.scale(1.0 / v.norm())
}

pub(super) fn compile(system: &System, options: &AssemblyOptions) -> Result<Assembly, BuildError> {
    system.validate()?;
    let bodies = system.bodies();
    let names: Vec<String> = bodies.iter().map(|b| b.name.clone()).collect();
    let free: Vec<[bool; 3]> = bodies.iter().map(|b| b.free).collect();

    let (prims, linears) = constraint_primitives(system);
    let Equations { specs: equations, bodies: eq_bodies, constraint: eq_constraint } =
        equations(system, &prims, &linears);
    let couplings: Vec<(u32, u32)> = system
        .forces()
        .iter()
        .map(|(_, f)| {
            let (a, b) = f.bodies();
            (a.index() as u32, b.index() as u32)
        })
        .collect();
    let layout = Layout::new(&free, &names, &equations, &eq_bodies, &couplings, options.ordering)?;
    let n = layout.n as u32;
    let sink = layout.sink();

    let body_static: Vec<BodyStatic> = (0..bodies.len())
        .map(|b| BodyStatic { coord: layout.body_coord[b], pose0: bodies[b].pose, rot0: Rot::new(bodies[b].pose[2]) })
        .collect();
    let maps = Maps { layout: &layout, n, sink };
    let mut asm = Assembly {
        bodies: body_static,
        coord_mass: layout.coord_body.iter().map(|&(b, s)| bodies[b as usize].slot_mass(s as usize)).collect(),
        coord_tolerance_scale: layout.coord_body.iter().map(|&(b, _)| bodies[b as usize].tolerance_scale).collect(),
        mass_pos: (0..layout.n).map(|c| layout.entry(layout.unknown_of_coord[c], layout.unknown_of_coord[c])).collect(),
        elements: ForceElements::default(),
        body_group: system.groups().to_vec(),
        groups: system.groups().iter().filter(|&&g| g != crate::NO_GROUP).map(|&g| g as usize + 1).max().unwrap_or(0),
        contact_bodies: Vec::new(),
        prims: Primitives::default(),
        linear: Vec::new(),
        g_entries: Vec::new(),
        eq_mref: Vec::new(),
        eq_angular: vec![false; layout.eq_coord.len()],
        constraint_names: system.constraints().iter().map(|(n, _)| n.clone()).collect(),
        constraint_prims: vec![Vec::new(); system.constraints().len()],
        eq_constraint,
        gravity: V2::from(system.excitation().gravity),
        ground: [system.excitation().ground_x.clone(), system.excitation().ground_y.clone()],
        translational: [Vec::new(), Vec::new()],
        structural_nnz: 0,
        d_row_ptr: Vec::new(),
        d_cols: Vec::new(),
        initial: (Vec::new(), Vec::new()),
        layout: layout.clone(),
    };
    asm.eq_mref = layout.eq_coord.iter().map(|&c| asm.coord_mass[c as usize]).collect();

    compile_forces(&mut asm, system, &maps);
    let first_linear = compile_primitives(&mut asm, prims, &maps);
    for (eq, (ci, l)) in (first_linear..).zip(linears) {
        compile_linear(&mut asm, &layout, bodies, ci, l, eq);
    }
    finish(&mut asm, &layout, bodies);
    Ok(asm)
}

/// The primitives of the constraints (each with its constraint's index)
/// and the linear constraints.
type ConstraintPrimitives<'a> = (Vec<(usize, Prim)>, Vec<(usize, &'a Linear)>);

/// The constraints' primitives in the system's order, each with its
/// constraint's index, and the linear constraints apart.
fn constraint_primitives(system: &System) -> ConstraintPrimitives<'_> {
    let bodies = system.bodies();
    let pose = |b: usize| bodies[b].pose;
    let mut prims: Vec<(usize, Prim)> = Vec::new();
    let mut linears: Vec<(usize, &Linear)> = Vec::new();
    for (ci, (_, c)) in system.constraints().iter().enumerate() {
        let id = |b: crate::model::body::BodyId| b.index() as u32;
        match c {
            Constraint::Revolute(j) => prims.push((
                ci,
                Prim::Point(PointK {
                    a: id(j.body_a),
                    b: id(j.body_b),
                    pa: V2::from(j.point_a),
                    pb: V2::from(j.point_b),
                }),
            )),
            Constraint::Weld(j) => {
                let (a, b) = (id(j.body_a), id(j.body_b));
                prims.push((ci, Prim::Point(PointK { a, b, pa: V2::from(j.point_a), pb: V2::from(j.point_b) })));
                let phi0 = pose(a as usize)[2] - pose(b as usize)[2];
                prims.push((ci, Prim::Angle(AngleK { a, b, phi0 })));
            }
            Constraint::Prismatic(j) => {
                let (a, b) = (id(j.slider), id(j.base));
                let phi0 = pose(a as usize)[2] - pose(b as usize)[2];
                prims.push((ci, Prim::Angle(AngleK { a, b, phi0 })));
                prims.push((
                    ci,
                    Prim::Line(LineK {
                        a,
                        b,
                        pa: V2::from(j.point),
                        lb: V2::from(j.axis_point),
                        ub: unit(j.axis_direction),
                    }),
                ));
            }
            Constraint::PointOnLine(j) => prims.push((
                ci,
                Prim::Line(LineK {
                    a: id(j.body),
                    b: id(j.line_body),
                    pa: V2::from(j.point),
                    lb: V2::from(j.line_point),
                    ub: unit(j.line_direction),
                }),
            )),
            Constraint::Driver(d) => prims.push((
                ci,
                Prim::Driver(DriverK { a: id(d.body), slot: d.coord.slot() as u8, motion: d.motion.clone() }),
            )),
            Constraint::Linear(l) => linears.push((ci, l)),
        }
    }
    (prims, linears)
}

/// The equations: what each may be solved for, its bodies and its
/// constraint.
struct Equations {
    specs: Vec<EquationSpec>,
    bodies: Vec<Vec<u32>>,
    constraint: Vec<u32>,
}

/// The equations of the primitives, then of the linear constraints (see
/// `compile_linear`); bodies touched by fewer constraints take the
/// equations.
fn equations(system: &System, prims: &[(usize, Prim)], linears: &[(usize, &Linear)]) -> Equations {
    let nb = system.bodies().len();
    let mut touches = vec![0usize; nb];
    for (_, c) in system.constraints() {
        for b in c.bodies() {
            touches[b.index()] += 1;
        }
    }
    let mut equations = Vec::new();
    let mut eq_bodies = Vec::new();
    let mut eq_constraint = Vec::new();
    for (ci, p) in prims {
        let (a, b) = p.bodies();
        let mut order = vec![a, b];
        order.sort_by_key(|&x| touches[x as usize]);
        for row in 0..p.rows() {
            let slots = p.structural_slots(row);
            let mut candidates = Vec::new();
            for &body in &order {
                if body == 0 {
                    continue;
                }
                let base = if body == a { 0 } else { 3 };
                // translational slots before the rotation
                for &s in slots.iter().filter(|&&s| s >= base && s < base + 3) {
                    candidates.push((body, (s - base) as u8));
                }
            }
            equations.push(EquationSpec { constraint: system.constraints()[*ci].0.clone(), candidates });
            eq_bodies.push(vec![a, b]);
            eq_constraint.push(*ci as u32);
        }
    }
    // (the linear equations after the primitives': see `compile_linear`)
    for &(ci, l) in linears {
        // (in the terms' order: the first term's coordinate takes the
        // equation when it is free; see `Linear::terms`)
        let candidates: Vec<(u32, u8)> = l.terms.iter().map(|&(b, c, _)| (b.index() as u32, c.slot() as u8)).collect();
        equations.push(EquationSpec { constraint: system.constraints()[ci].0.clone(), candidates });
        eq_bodies.push(system.constraints()[ci].1.bodies().iter().map(|b| b.index() as u32).collect());
        eq_constraint.push(ci as u32);
    }
    Equations { specs: equations, bodies: eq_bodies, constraint: eq_constraint }
}

/// Where an element's or a primitive's values go: the coordinates of its
/// two bodies' slots and the iteration matrix's entries between them.
struct Maps<'a> {
    layout: &'a Layout,
    /// The number of coordinates (a slot without one maps to it).
    n: u32,
    /// The entry that takes what no matrix entry holds.
    sink: u32,
}

impl Maps<'_> {
    /// The coordinates of bodies `a`'s and `b`'s slots (`n`: none).
    fn slots(&self, a: u32, b: u32) -> [u32; 6] {
        let (layout, n) = (self.layout, self.n);
        let mut f = [n; 6];
        for s in 0..3 {
            let ca = layout.body_coord[a as usize][s];
            let cb = layout.body_coord[b as usize][s];
            f[s] = if ca == NONE { n } else { ca };
            f[3 + s] = if cb == NONE { n } else { cb };
        }
        f
    }

    /// The matrix entries between the coordinates `f`.
    fn jac(&self, f: &[u32; 6]) -> [u32; 36] {
        let (layout, n) = (self.layout, self.n);
        let mut jac = [self.sink; 36];
        for i in 0..6 {
            for j in 0..6 {
                if f[i] < n && f[j] < n {
                    jac[i * 6 + j] =
                        layout.entry(layout.unknown_of_coord[f[i] as usize], layout.unknown_of_coord[f[j] as usize]);
                }
            }
        }
        jac
    }

    /// The map of an element between bodies `a` and `b`.
    fn pair(&self, a: u32, b: u32) -> PairMap {
        let f = self.slots(a, b);
        PairMap { f, jac: self.jac(&f) }
    }
}

/// The force elements, each into its kind's list in the system's order,
/// and the bodies the contacts touch.
fn compile_forces(asm: &mut Assembly, system: &System, maps: &Maps<'_>) {
    let (bodies, layout) = (system.bodies(), maps.layout);
    let pair = |a: u32, b: u32| maps.pair(a, b);
    for (_, f) in system.forces() {
        let (a, b) = f.bodies();
        let (a, b) = (a.index() as u32, b.index() as u32);
        match f {
            ForceElement::Bushing(e) => asm.elements.bushings.push((
                BushingK {
                    a,
                    b,
                    pa: V2::from(e.frame_point),
                    pb: V2::from(e.point),
                    k: e.stiffness,
                    c: e.damping,
                    rest: V2::from(e.rest),
                },
                pair(a, b),
            )),
            ForceElement::Friction(e) => asm.elements.frictions.push((
                FrictionK { a, b, pa: V2::from(e.point), force: e.sliding_force(), v_eps: e.v_eps, law: e.law },
                pair(a, b),
            )),
            ForceElement::SpringDamper(e) => asm.elements.springs.push((
                SpringK {
                    a,
                    b,
                    pa: V2::from(e.point_a),
                    pb: V2::from(e.point_b),
                    k: e.stiffness,
                    c: e.damping,
                    l0: e.rest_length,
                },
                pair(a, b),
            )),
            ForceElement::CoordinateSpring(e) => {
                let c = layout.body_coord[a as usize][e.coord.slot()];
                let u = layout.unknown_of_coord[c as usize];
                asm.elements.coord_springs.push((
                    CoordSpringK { body: a, slot: e.coord.slot() as u8, k: e.stiffness, c: e.damping, rest: e.rest },
                    CoordMap { f: c, jac: layout.entry(u, u) },
                ));
            }
            ForceElement::AppliedLoad(e) => asm.elements.loads.push((
                LoadK { a, pa: V2::from(e.point), fx: e.fx.clone(), fy: e.fy.clone(), torque: e.torque.clone() },
                pair(a, 0),
            )),
            ForceElement::Custom(e) => asm.elements.customs.push((CustomK { a, b, law: e.clone() }, pair(a, b))),
            ForceElement::Contact(e) => {
                // reduced mass of the two bodies (the ground counts as infinite)
                let mass = |i: u32| if i == 0 { f64::INFINITY } else { bodies[i as usize].mass };
                let (ma, mb) = (mass(a), mass(b));
                let reduced = if let Some(m) = e.reduced_mass {
                    m
                } else if mb.is_infinite() {
                    ma
                } else if ma.is_infinite() {
                    mb
                } else {
                    ma * mb / (ma + mb)
                };
                asm.elements.contacts.push((
                    ContactK {
                        a,
                        b,
                        sa: V2::from(e.point),
                        sb: V2::from(e.edge_point),
                        nb: unit(e.edge_normal),
                        law: LawK::new(&e.law, reduced),
                    },
                    pair(a, b),
                ))
            }
        }
    }
    let touched: BTreeSet<usize> =
        asm.elements.contacts.iter().flat_map(|(k, _)| [k.a as usize, k.b as usize]).filter(|&b| b != 0).collect();
    asm.contact_bodies = touched.into_iter().collect();
}

/// The constraint primitives with their maps and gradient entries, in
/// order; the number of their equations.
fn compile_primitives(asm: &mut Assembly, prims: Vec<(usize, Prim)>, maps: &Maps<'_>) -> u32 {
    let (layout, n) = (maps.layout, maps.n);
    let mut eq = 0u32;
    for (ci, p) in prims {
        let (a, b) = p.bodies();
        let f = maps.slots(a, b);
        let g_start = asm.g_entries.len() as u32;
        for row in 0..p.rows() {
            let e = eq + row as u32;
            for slot in p.structural_slots(row) {
                let c = f[slot];
                if c >= n {
                    continue;
                }
                let (ue, uc) = (layout.unknown_of_eq[e as usize], layout.unknown_of_coord[c as usize]);
                asm.g_entries.push(GEntry {
                    pos: layout.entry(ue, uc),
                    pos_t: layout.entry(uc, ue),
                    eq: e,
                    coord: c,
                    row: row as u8,
                    slot: slot as u8,
                });
            }
        }
        let map = PrimMap {
            eq,
            rows: p.rows() as u8,
            f,
            h: maps.jac(&f),
            g_start,
            g_count: (asm.g_entries.len() as u32 - g_start) as u8,
        };
        if matches!(&p, Prim::Angle(_)) || matches!(&p, Prim::Driver(k) if k.slot == 2) {
            for row in 0..p.rows() {
                asm.eq_angular[(eq + row as u32) as usize] = true;
            }
        }
        eq += p.rows() as u32;
        let r = match p {
            Prim::Point(k) => {
                asm.prims.points.push((k, map));
                PrimRef::Point(asm.prims.points.len() as u32 - 1)
            }
            Prim::Angle(k) => {
                asm.prims.angles.push((k, map));
                PrimRef::Angle(asm.prims.angles.len() as u32 - 1)
            }
            Prim::Line(k) => {
                asm.prims.lines.push((k, map));
                PrimRef::Line(asm.prims.lines.len() as u32 - 1)
            }
            Prim::Driver(k) => {
                asm.prims.drivers.push((k, map));
                PrimRef::Driver(asm.prims.drivers.len() as u32 - 1)
            }
        };
        asm.constraint_prims[ci].push(r);
    }

    eq
}

/// The bodies' masses under the ground's motion, the initial state and
/// the damping matrix's structure.
fn finish(asm: &mut Assembly, layout: &Layout, bodies: &[Body]) {
    for (b, body) in bodies.iter().enumerate().skip(1) {
        for dir in 0..2 {
            // the ground's direction `dir` on the body's x and y (without a
            // base mass: its own mass on its own direction)
            for slot in 0..2 {
                let c = layout.body_coord[b][slot];
                let m = match body.base_mass {
                    Some(m) => m[slot][dir],
                    None if slot == dir => body.mass,
                    None => 0.0,
                };
                if c != NONE && m != 0.0 {
                    asm.translational[dir].push((c, m));
                }
            }
        }
    }
    let mut q0 = vec![0.0; layout.n];
    let mut v0 = vec![0.0; layout.n];
    for (c, &(b, s)) in layout.coord_body.iter().enumerate() {
        q0[c] = bodies[b as usize].pose[s as usize];
        v0[c] = bodies[b as usize].velocity[s as usize];
    }
    asm.initial = (q0, v0);
    asm.structural_nnz = structural_nnz(asm);
    // (sorted by position; the stable sort keeps that order within a row)
    let mut by_row = damping_entries(asm);
    by_row.sort_by_key(|&(r, _, _)| r);
    asm.d_row_ptr = (0..=layout.n as u32).map(|r| by_row.partition_point(|&(row, _, _)| row < r) as u32).collect();
    asm.d_cols = by_row.iter().map(|&(_, c, p)| (c, p)).collect();
}

/// Compiles the linear constraint `l` (user constraint `ci`) as equation
/// `eq`, with one gradient entry per term.
fn compile_linear(asm: &mut Assembly, layout: &Layout, bodies: &[Body], ci: usize, l: &Linear, eq: u32) {
    let g_start = asm.g_entries.len() as u32;
    let mut terms = Vec::with_capacity(l.terms.len());
    let mut offset = 0.0;
    for &(body, coord, c) in &l.terms {
        let (b, slot) = (body.index(), coord.slot());
        let col = layout.body_coord[b][slot];
        let (ue, uc) = (layout.unknown_of_eq[eq as usize], layout.unknown_of_coord[col as usize]);
        asm.g_entries.push(GEntry {
            pos: layout.entry(ue, uc),
            pos_t: layout.entry(uc, ue),
            eq,
            coord: col,
            row: 0,
            slot: slot as u8,
        });
        terms.push((b as u32, slot as u8, col, c));
        offset += c * bodies[b].pose[slot];
    }
    asm.eq_angular[eq as usize] = terms.iter().all(|&(_, s, _, _)| s == 2);
    // (scaled by the heaviest of its coordinates: the one it is paired with
    // may be a point of almost no mass of its own, whose scale would leave
    // the equation's row too small for the block elimination's pivots)
    asm.eq_mref[eq as usize] = terms.iter().map(|&(_, _, c, _)| asm.coord_mass[c as usize]).fold(0.0, f64::max);
    asm.linear.push(LinearK { eq, terms, offset, g_start });
    asm.constraint_prims[ci].push(PrimRef::Linear(asm.linear.len() as u32 - 1));
}

/// Distinct positions written by any element or constraint.
fn structural_nnz(asm: &Assembly) -> usize {
    structural_positions(asm).len()
}

/// The positions written by any element or constraint, sorted.
pub(super) fn structural_positions(asm: &Assembly) -> BTreeSet<u32> {
    let mut set: BTreeSet<u32> = asm.mass_pos.iter().copied().collect();
    set.extend(asm.element_entries().into_iter().map(|(_, _, p)| p));
    let sink = asm.layout.sink();
    for m in asm.prims.points.iter().map(|x| &x.1).chain(asm.prims.lines.iter().map(|x| &x.1)) {
        set.extend(m.h.iter().copied().filter(|&p| p != sink));
    }
    for e in &asm.g_entries {
        set.insert(e.pos);
        set.insert(e.pos_t);
    }
    set
}

/// Distinct (row, column, position) entries of the damping matrix.
fn damping_entries(asm: &Assembly) -> Vec<(u32, u32, u32)> {
    let mut entries = Entries { n: asm.layout.n as u32, damping_only: true, out: BTreeSet::new() };
    asm.elements.visit::<ResidualOrder, _>(&mut entries);
    entries.out.into_iter().map(|(p, r, c)| (r, c, p)).collect()
}

impl Assembly {
    /// The entries of the force elements' blocks between free coordinates,
    /// as distinct (row coordinate, column coordinate, position in the
    /// Jacobian arrays).
    pub(crate) fn element_entries(&self) -> Vec<(u32, u32, u32)> {
        let mut entries = Entries { n: self.layout.n as u32, damping_only: false, out: BTreeSet::new() };
        self.elements.visit::<ResidualOrder, _>(&mut entries);
        entries.out.into_iter().map(|(p, r, c)| (r, c, p)).collect()
    }
}

/// Collects the (position, row, column) entries of the elements' blocks
/// between free coordinates; with `damping_only`, of those with a damping
/// block.
struct Entries {
    n: u32,
    damping_only: bool,
    out: BTreeSet<(u32, u32, u32)>,
}

impl KindVisitor for Entries {
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
        if self.damping_only && !K::DAMPING {
            return;
        }
        for (_, map) in elements {
            map.for_each_entry(self.n, |r, c, p| {
                self.out.insert((p, r, c));
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::model::body::{Body, Coord};
    use crate::model::system::System;
    use crate::{Assembly, AssemblyOptions};

    /// Each coordinate takes the tolerance scale of its own body, whatever
    /// the bodies' free coordinates (the integrator's error weights read it
    /// by coordinate).
    #[test]
    fn each_coordinate_carries_its_bodys_tolerance_scale() {
        let mut sys = System::new();
        sys.add_body(Body::new("a", 1.0, 1.0, [0.0; 3]).with_tolerance_scale(3.0));
        sys.add_body(Body::new("b", 1.0, 1.0, [1.0, 0.0, 0.0]).only(&[Coord::X]));
        sys.add_body(Body::new("c", 1.0, 1.0, [2.0, 0.0, 0.0]).only(&[Coord::Y, Coord::Phi]).with_tolerance_scale(5.0));
        let asm = Assembly::new(&sys, &AssemblyOptions::default()).unwrap();
        assert_eq!(asm.coord_tolerance_scale, [3.0, 3.0, 3.0, 1.0, 5.0, 5.0]);
    }
}

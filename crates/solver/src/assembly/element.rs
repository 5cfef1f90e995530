//! The force-element trait and the per-kind element lists.
//!
//! Each force law (bushing, friction, spring-damper, coordinate spring,
//! applied load, custom force, contact) implements [`ForceKernel`] in one
//! place: its generalised forces, its stiffness and damping derivatives,
//! its stored energy, its power and its reaction (the force it transmits).
//! The assembly keeps one vector per kind ([`ForceElements`]) and walks them
//! through a [`KindVisitor`], whose one generic loop per operation (residual,
//! Jacobian, stored energy, powers, peak forces, structure) is compiled for
//! each kind, the kinds in a [`KindOrder`]: static dispatch, no trait
//! objects and no run-time choice of kind in the hot loops.

use super::contact::ContactK;
use super::forces::{BushingK, CoordSpringK, CustomK, LoadK, SpringK};
use super::friction::FrictionK;
use super::kin::BodyKin;
use super::maps::{CoordMap, PairMap, Scatter};

/// What a force law reads at one state besides its own parameters.
#[derive(Debug, Clone, Copy)]
pub(crate) struct At<'a> {
    /// Kinematics of every body (the ground's at index 0).
    pub kin: &'a [BodyKin],
    /// Time [s].
    pub t: f64,
    /// Whether each contact is closed (the integrator's mode of the step).
    pub closed: &'a [bool],
    /// Approach speed of each closed contact at its onset [m/s].
    pub v0: &'a [f64],
    /// The integrator's iteration Jacobian: per friction element, whether it
    /// enters with the slope of its regularisation zone
    /// (the derivatives of [`FrictionK`]); `None` for the exact derivatives.
    pub zone: Option<&'a [bool]>,
    /// Velocities of the free coordinates (read by [`ForceKernel::add_power`]
    /// only; empty elsewhere) [m/s, rad/s].
    pub v: &'a [f64],
}

impl<'a> At<'a> {
    /// The kinematics at time `t` with the contact modes `closed`, `v0`;
    /// exact derivatives, no coordinate velocities.
    #[inline(always)]
    pub fn new(kin: &'a [BodyKin], t: f64, closed: &'a [bool], v0: &'a [f64]) -> Self {
        Self { kin, t, closed, v0, zone: None, v: &[] }
    }

    /// The kinematics of bodies `a` and `b`.
    #[inline(always)]
    pub fn pair(&self, a: u32, b: u32) -> (&'a BodyKin, &'a BodyKin) {
        (&self.kin[a as usize], &self.kin[b as usize])
    }
}

/// Which power flow of [`crate::Powers`] an element's power belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PowerFlow {
    /// Dissipated by dampers (never negative).
    Damping,
    /// Dissipated by friction (never negative).
    Friction,
    /// Dissipated by the damping of closed contacts (never negative).
    Contact,
    /// Delivered by applied loads and custom forces.
    Applied,
}

/// Which of the largest forces of [`crate::ForceExtremes`] an element's
/// reaction counts in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PeakForce {
    /// The largest bushing force.
    Bushing,
    /// The largest friction force.
    Friction,
}

/// One force law, as the assembly's loops see it.
///
/// An element acts on the slots of its scatter map (`z = (x_a, y_a, phi_a,
/// x_b, y_b, phi_b)` of its two bodies, or one coordinate). Element `i` of
/// its kind's list reads the state through [`At`] (kinematics, time, its
/// contact mode) and gives
/// - its generalised forces `Q(t, z, z')` [N, N m],
/// - `K = -dQ/dz` and `D = -dQ/dz'`, added into blocks the caller has
///   zeroed; the assembly scatters them into the fixed sparse pattern and
///   the integrator forms `c^2 M + c D + K` from them, supplying the factors,
/// - its stored energy [J] and its power [W],
/// - its reaction: the square of the force it transmits [N^2].
///
/// The constants say which of these an element has, so that the loops skip
/// the others at compile time.
pub(crate) trait ForceKernel {
    /// Where the element's values go.
    type Map: Scatter;
    /// Whether it has a damping block `D` (every kind but the applied load).
    const DAMPING: bool;
    /// Whether it stores energy ([`Self::potential`]).
    const STORES_ENERGY: bool;
    /// The power flow of [`Self::add_power`], if it has one.
    const POWER: Option<PowerFlow>;
    /// The largest force its [`Self::reaction_squared`] counts in, if any.
    const PEAK: Option<PeakForce>;

    /// Whether element `i` acts at this state (a contact only while closed).
    #[inline(always)]
    fn acts(&self, _at: &At, _i: usize) -> bool {
        true
    }

    /// Generalised forces `Q` on the element's slots [N, N m].
    fn force(&self, at: &At, i: usize) -> <Self::Map as Scatter>::Vector;

    /// Adds `K = -dQ/dz` [N/m, N, N m] into `km` and, if [`Self::DAMPING`],
    /// `D = -dQ/dz'` [N s/m, N s, N m s] into `dm`.
    fn derivatives(
        &self,
        at: &At,
        i: usize,
        km: &mut <Self::Map as Scatter>::Matrix,
        dm: &mut <Self::Map as Scatter>::Matrix,
    );

    /// Stored energy [J] (read only if [`Self::STORES_ENERGY`]).
    #[inline(always)]
    fn potential(&self, _at: &At, _i: usize) -> f64 {
        0.0
    }

    /// Adds the element's power [W] into `acc`, the sum of its flow
    /// [`Self::POWER`]: dissipated (damping, friction, contact) or delivered
    /// (applied); `at.v` holds the coordinates' velocities.
    #[inline(always)]
    fn add_power(&self, _at: &At, _i: usize, _map: &Self::Map, _acc: &mut f64) {}

    /// Square of the force the element transmits [N^2] (read only if
    /// [`Self::PEAK`]; the largest of several magnitudes is the root of the
    /// largest square, bit for bit).
    #[inline(always)]
    fn reaction_squared(&self, _at: &At, _i: usize) -> f64 {
        0.0
    }
}

/// One operation over the elements, run on each kind's list in turn (see
/// [`ForceElements::visit`]).
pub(crate) trait KindVisitor {
    /// Runs the operation on the elements of one kind, in their order.
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]);
}

/// The compiled force elements, one list per kind, each element with its
/// scatter map, in the order the system added them.
#[derive(Debug, Clone, Default)]
pub(crate) struct ForceElements {
    pub contacts: Vec<(ContactK, PairMap)>,
    pub bushings: Vec<(BushingK, PairMap)>,
    pub frictions: Vec<(FrictionK, PairMap)>,
    pub springs: Vec<(SpringK, PairMap)>,
    pub coord_springs: Vec<(CoordSpringK, CoordMap)>,
    pub loads: Vec<(LoadK, PairMap)>,
    pub customs: Vec<(CustomK, PairMap)>,
}

impl ForceElements {
    /// Runs `visitor` on every kind's list, in the order `O`.
    #[inline(always)]
    pub fn visit<O: KindOrder, V: KindVisitor>(&self, visitor: &mut V) {
        O::visit(self, visitor);
    }
}

/// An order of the kinds: each operation adds the kinds' contributions to
/// one entry in a fixed order. Floating-point addition is not associative,
/// so the three orders below are those of the loops written out by hand
/// before the trait (ed5d205), which keeps every result the same to the
/// bit. Each is a list of calls, one per kind, compiled into the operation:
/// no dispatch at run time.
pub(crate) trait KindOrder {
    /// Runs `visitor` on each kind's list of `elements`, in this order.
    fn visit<V: KindVisitor>(elements: &ForceElements, visitor: &mut V);
}

/// The order in which the residual adds the kinds' forces into `F` (also
/// used where the order does not matter: the structure).
pub(crate) struct ResidualOrder;

impl KindOrder for ResidualOrder {
    #[inline(always)]
    fn visit<V: KindVisitor>(e: &ForceElements, visitor: &mut V) {
        visitor.visit(&e.contacts);
        visitor.visit(&e.bushings);
        visitor.visit(&e.frictions);
        visitor.visit(&e.springs);
        visitor.visit(&e.coord_springs);
        visitor.visit(&e.loads);
        visitor.visit(&e.customs);
    }
}

/// The order in which the Jacobian adds the kinds' blocks into `K` and `D`.
pub(crate) struct JacobianOrder;

impl KindOrder for JacobianOrder {
    #[inline(always)]
    fn visit<V: KindVisitor>(e: &ForceElements, visitor: &mut V) {
        visitor.visit(&e.bushings);
        visitor.visit(&e.contacts);
        visitor.visit(&e.frictions);
        visitor.visit(&e.springs);
        visitor.visit(&e.coord_springs);
        visitor.visit(&e.loads);
        visitor.visit(&e.customs);
    }
}

/// The order in which the stored energy, the powers and the peak forces
/// sum the kinds.
pub(crate) struct EnergyOrder;

impl KindOrder for EnergyOrder {
    #[inline(always)]
    fn visit<V: KindVisitor>(e: &ForceElements, visitor: &mut V) {
        visitor.visit(&e.bushings);
        visitor.visit(&e.frictions);
        visitor.visit(&e.springs);
        visitor.visit(&e.coord_springs);
        visitor.visit(&e.contacts);
        visitor.visit(&e.loads);
        visitor.visit(&e.customs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::force::{Contact, ContactLaw, ForceElement, HertzDamping};
    use crate::reference::element_zoo;
    use crate::{Assembly, AssemblyOptions, BodyId};

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    }

    /// Checks each element of every kind on its own, through the trait:
    /// its stiffness and damping blocks, scattered by its map, against
    /// central differences of its scattered force in each of its
    /// coordinates and their velocities.
    struct FiniteDifferences<'a> {
        asm: &'a Assembly,
        t: f64,
        q: &'a [f64],
        v: &'a [f64],
        closed: Vec<bool>,
        v0: Vec<f64>,
        /// Kinds visited and elements checked.
        kinds: usize,
        checked: usize,
    }

    impl FiniteDifferences<'_> {
        /// Element `i`'s forces, scattered over the coordinates, at `(q, v)`.
        fn eval<K: ForceKernel>(&self, e: &K, i: usize, map: &K::Map, q: &[f64], v: &[f64]) -> Vec<f64> {
            let mut ws = self.asm.workspace();
            self.asm.load_kin(&mut ws, q, v);
            let at = At::new(&ws.kin, self.t, &self.closed, &self.v0);
            let mut f = vec![0.0; self.asm.coordinates() + 1];
            map.add_vector(&mut f, &e.force(&at, i));
            f
        }
    }

    impl KindVisitor for FiniteDifferences<'_> {
        fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
            assert!(!elements.is_empty(), "the test system has every kind of element");
            self.kinds += 1;
            let n = self.asm.coordinates();
            let len = self.asm.layout.sym.nnz() + 1;
            for (i, (e, map)) in elements.iter().enumerate() {
                let mut ws = self.asm.workspace();
                self.asm.load_kin(&mut ws, self.q, self.v);
                let at = At::new(&ws.kin, self.t, &self.closed, &self.v0);
                assert!(e.acts(&at, i));
                let (mut km, mut dm) = (<K::Map as Scatter>::Matrix::default(), <K::Map as Scatter>::Matrix::default());
                e.derivatives(&at, i, &mut km, &mut dm);
                let (mut k, mut d) = (vec![0.0; len], vec![0.0; len]);
                map.add_matrix(&mut k, &km);
                if K::DAMPING {
                    map.add_matrix(&mut d, &dm);
                }
                let mut entries = Vec::new();
                map.for_each_entry(n as u32, |r, c, p| entries.push((r as usize, c as usize, p as usize)));
                let scale = entries.iter().fold(0.0f64, |s, &(_, _, p)| s.max(k[p].abs()).max(d[p].abs()));
                for &(_, c, _) in &entries {
                    let h = 1e-6 * self.q[c].abs().max(1.0);
                    let diff = |dq: f64, dv: f64| {
                        let (mut qp, mut qm, mut vp, mut vm) =
                            (self.q.to_vec(), self.q.to_vec(), self.v.to_vec(), self.v.to_vec());
                        qp[c] += dq;
                        qm[c] -= dq;
                        vp[c] += dv;
                        vm[c] -= dv;
                        let (fp, fm) = (self.eval(e, i, map, &qp, &vp), self.eval(e, i, map, &qm, &vm));
                        fp.iter().zip(&fm).map(|(p, m)| -(p - m) / (2.0 * (dq + dv))).collect::<Vec<f64>>()
                    };
                    let (k_fd, d_fd) = (diff(h, 0.0), diff(0.0, 1e-6));
                    for &(r, _, p) in entries.iter().filter(|&&(_, col, _)| col == c) {
                        for (what, analytic, fd) in [("K", k[p], k_fd[r]), ("D", d[p], d_fd[r])] {
                            assert!(
                                (analytic - fd).abs() <= 1e-6 * analytic.abs().max(1e-3 * scale).max(1e-9),
                                "{} {i}, {what}[{r}][{c}]: analytic {analytic}, finite differences {fd}",
                                std::any::type_name::<K>()
                            );
                        }
                    }
                }
                self.checked += 1;
            }
        }
    }

    /// Every kind's stiffness and damping derivatives, through
    /// [`ForceKernel`], against central differences of its own force: the
    /// element zoo (two bushings, friction of both laws, a spring-damper, a
    /// coordinate spring, an applied load, a custom force) with a linear
    /// and two Hertz contacts added, all closed, at random states where the
    /// friction slides and where it sticks (inside its zone).
    #[test]
    fn each_kind_matches_finite_differences_of_its_force() {
        let mut sys = element_zoo();
        let hertz = |damping| ContactLaw::Hertz { stiffness: 3e6, restitution: 0.6, damping };
        let (a, b, e) = (BodyId(1), BodyId(2), BodyId(5));
        for (body, base, law) in [
            (a, b, ContactLaw::Linear { stiffness: 2e5, restitution: 0.7 }),
            (b, a, hertz(HertzDamping::YeLiZhu)),
            (e, BodyId::GROUND, hertz(HertzDamping::LankaraniNikravesh)),
        ] {
            sys.add_force(ForceElement::Contact(Contact {
                body,
                point: [0.2, 0.1],
                base,
                edge_point: [-0.1, 0.05],
                edge_normal: [-0.8, 0.6],
                law,
                reduced_mass: None,
            }));
        }
        let asm = Assembly::new(&sys, &AssemblyOptions::default()).unwrap();
        for (seed, vscale) in [(1u64, 1.0), (2, 1.0), (3, 1.0), (11, 1e-3), (12, 1e-3)] {
            let mut s = seed;
            let (q0, _) = asm.initial_state();
            let q: Vec<f64> = q0.iter().map(|x| x + 0.3 * lcg(&mut s)).collect();
            let v: Vec<f64> = (0..q.len()).map(|_| vscale * 2.0 * lcg(&mut s)).collect();
            let contacts = asm.contact_count();
            let mut check = FiniteDifferences {
                asm: &asm,
                t: 0.37,
                q: &q,
                v: &v,
                closed: vec![true; contacts],
                v0: (0..contacts).map(|i| 0.2 + 0.1 * i as f64).collect(),
                kinds: 0,
                checked: 0,
            };
            asm.elements.visit::<ResidualOrder, _>(&mut check);
            assert_eq!((check.kinds, check.checked), (7, 12));
        }
    }

    /// Records the kinds in the order visited.
    struct Kinds(Vec<&'static str>);

    impl KindVisitor for Kinds {
        fn visit<K: ForceKernel>(&mut self, _elements: &[(K, K::Map)]) {
            self.0.push(std::any::type_name::<K>());
        }
    }

    /// Each order visits every kind once.
    #[test]
    fn each_order_visits_every_kind_once() {
        let elements = ForceElements::default();
        let mut orders = [Kinds(Vec::new()), Kinds(Vec::new()), Kinds(Vec::new())];
        elements.visit::<ResidualOrder, _>(&mut orders[0]);
        elements.visit::<JacobianOrder, _>(&mut orders[1]);
        elements.visit::<EnergyOrder, _>(&mut orders[2]);
        for Kinds(mut kinds) in orders {
            assert_eq!(kinds.len(), 7);
            kinds.sort_unstable();
            kinds.dedup();
            assert_eq!(kinds.len(), 7, "{kinds:?}");
        }
    }
}

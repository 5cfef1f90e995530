//! Energy accounting: kinetic and stored energy, and the power flows the
//! integrator's energy balance integrates.

use super::element::{At, EnergyOrder, ForceKernel, KindVisitor, PowerFlow};
use super::{Assembly, Powers, Workspace};

impl Assembly {
    /// Kinetic energy `1/2 q'^T M q'` \[J\].
    pub fn kinetic_energy(&self, v: &[f64]) -> f64 {
        0.5 * self.coord_mass.iter().zip(v).map(|(m, v)| m * v * v).sum::<f64>()
    }

    /// Energy stored in springs, bushings, closed contacts and the gravity
    /// field \[J\].
    pub fn potential_energy(&self, ws: &mut Workspace, q: &[f64]) -> f64 {
        // velocities do not enter stored energy; q stands in for them
        self.load_kin(ws, q, q);
        self.loaded_potential_energy(ws, q)
    }

    /// [`Assembly::potential_energy`] at the positions `q` whose kinematics
    /// the last evaluation loaded into `ws` (a residual at `q`, say), which
    /// saves loading them again.
    pub(crate) fn loaded_potential_energy(&self, ws: &Workspace, q: &[f64]) -> f64 {
        let mut stored = StoredEnergy { at: At::new(&ws.kin, 0.0, &ws.closed, &ws.v0), e: 0.0 };
        self.elements.visit::<EnergyOrder, _>(&mut stored);
        let mut e = stored.e;
        for dir in 0..2 {
            let gacc = if dir == 0 { self.gravity.x } else { self.gravity.y };
            if gacc != 0.0 {
                for &(c, mass) in &self.translational[dir] {
                    e -= mass * gacc * q[c as usize];
                }
            }
        }
        e
    }

    /// Power flows at a state.
    pub fn powers(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64]) -> Powers {
        crate::isa::run(
            #[inline(always)]
            || self.powers_impl(ws, t, q, v, lam),
        )
    }

    /// The power friction dissipates \[W\] in each group of bodies
    /// ([`crate::System::set_group`]) at `(t, q, v)`, added into `out` (one
    /// entry per group; an element in no group is left out).
    pub fn friction_powers_by_group(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.load_kin(ws, q, v);
        let at = At { v: &v[..self.layout.n], ..At::new(&ws.kin, t, &ws.closed, &ws.v0) };
        for (i, (k, map)) in self.elements.frictions.iter().enumerate() {
            if let Some(slot) = out.get_mut(self.group_of(k.a, k.b)) {
                if k.acts(&at, i) {
                    k.add_power(&at, i, map, slot);
                }
            }
        }
    }

    /// The number of groups of bodies ([`crate::System::set_group`]).
    pub fn group_count(&self) -> usize {
        self.groups
    }

    /// The group of an element between bodies `a` and `b`: `a`'s, else
    /// `b`'s ([`crate::NO_GROUP`] as an index past every group).
    pub(crate) fn group_of(&self, a: u32, b: u32) -> usize {
        let g = match self.body_group[a as usize] {
            crate::NO_GROUP => self.body_group[b as usize],
            g => g,
        };
        if g == crate::NO_GROUP {
            usize::MAX
        } else {
            g as usize
        }
    }

    /// [`Self::powers`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn powers_impl(&self, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64], lam: &[f64]) -> Powers {
        self.load_kin(ws, q, v);
        let at = At { v: &v[..self.layout.n], ..At::new(&ws.kin, t, &ws.closed, &ws.v0) };
        let mut flows = PowerFlows { at, p: Powers::default() };
        self.elements.visit::<EnergyOrder, _>(&mut flows);
        let mut p = flows.p;
        for dir in 0..2 {
            if let Some(a) = &self.ground[dir] {
                let ag = a.value(t);
                if ag != 0.0 {
                    // (the momentum in four partial sums: one sum's chain of
                    // additions would take longer than the products)
                    let mut momentum = [0.0; 4];
                    for (i, &(c, mass)) in self.translational[dir].iter().enumerate() {
                        momentum[i % 4] += mass * v[c as usize];
                    }
                    p.base -= ag * ((momentum[0] + momentum[1]) + (momentum[2] + momentum[3]));
                }
            }
        }
        for (k, m) in &self.prims.drivers {
            p.constraints += lam[m.eq as usize] * k.time_derivatives(t).0;
        }
        p
    }
}

/// Sums the elements' stored energy.
struct StoredEnergy<'a> {
    at: At<'a>,
    /// [J]
    e: f64,
}

impl KindVisitor for StoredEnergy<'_> {
    #[inline(always)]
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
        if !K::STORES_ENERGY {
            return;
        }
        // (a copy of the state and the sum in a local: the loop's calls
        // then cannot reach them)
        let (at, mut e) = (self.at, self.e);
        for (i, (k, _)) in elements.iter().enumerate() {
            if k.acts(&at, i) {
                e += k.potential(&at, i);
            }
        }
        self.e = e;
    }
}

/// Sums the elements' powers by flow.
struct PowerFlows<'a> {
    at: At<'a>,
    p: Powers,
}

impl KindVisitor for PowerFlows<'_> {
    #[inline(always)]
    fn visit<K: ForceKernel>(&mut self, elements: &[(K, K::Map)]) {
        let Some(flow) = K::POWER else { return };
        let sum = match flow {
            PowerFlow::Damping => &mut self.p.damping,
            PowerFlow::Friction => &mut self.p.friction,
            PowerFlow::Contact => &mut self.p.contact,
            PowerFlow::Applied => &mut self.p.applied,
        };
        // (a copy of the state and the sum in a local, as in `StoredEnergy`)
        let (at, mut acc) = (self.at, *sum);
        for (i, (k, map)) in elements.iter().enumerate() {
            if k.acts(&at, i) {
                k.add_power(&at, i, map, &mut acc);
            }
        }
        *sum = acc;
    }
}

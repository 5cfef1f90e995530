//! Readable names and positions of the iteration matrix's rows and
//! entries, for messages and for plotting its pattern.

use super::{build, Assembly};

impl Assembly {
    /// Structural non-zeros of the iteration matrix as (row, column) pairs in
    /// natural numbering: coordinates `0..n` in body order, then constraint
    /// equations `n..n+m` (for plotting the sparsity pattern).
    pub fn jacobian_pattern(&self) -> Vec<(u32, u32)> {
        let lay = &self.layout;
        let n = lay.n as u32;
        let mut natural = vec![0u32; self.dim()];
        for (c, &u) in lay.unknown_of_coord.iter().enumerate() {
            natural[u as usize] = c as u32;
        }
        for (e, &u) in lay.unknown_of_eq.iter().enumerate() {
            natural[u as usize] = n + e as u32;
        }
        let mut entries: Vec<(u32, u32)> = build::structural_positions(self)
            .into_iter()
            .filter_map(|p| self.position_unknowns(p as usize))
            .map(|(r, c)| (natural[r], natural[c]))
            .collect();
        entries.sort_unstable();
        entries
    }

    /// Body index of each coordinate (natural numbering).
    pub fn coordinate_bodies(&self) -> Vec<u32> {
        self.layout.coord_body.iter().map(|&(b, _)| b).collect()
    }

    /// Row and column unknowns of a position in the Jacobian arrays.
    pub fn position_unknowns(&self, pos: usize) -> Option<(usize, usize)> {
        let sym = &self.layout.sym;
        sym.sub_blocks().find_map(|(i, j, off, _)| {
            let (si, ni) = sym.span(i);
            let (sj, nj) = sym.span(j);
            (pos >= off && pos < off + ni * nj).then(|| (si + (pos - off) / nj, sj + (pos - off) % nj))
        })
    }

    /// A readable name of an unknown of the iteration matrix, such as
    /// `phi of "beam 3"` or `equation 1 of "pivot"`.
    pub fn unknown_label(&self, unknown: usize) -> String {
        if let Some(c) = self.layout.unknown_of_coord.iter().position(|&u| u as usize == unknown) {
            let (b, s) = self.layout.coord_body[c];
            let body = self.layout.position_names[self.layout.unknown_place[unknown].0 as usize].clone();
            let _ = b;
            return format!("{} of {body}", ["x", "y", "phi"][s as usize]);
        }
        if let Some(e) = self.layout.unknown_of_eq.iter().position(|&u| u as usize == unknown) {
            let ci = self.eq_constraint[e] as usize;
            let first = self.eq_constraint.iter().position(|&x| x as usize == ci).unwrap_or(e);
            return format!("equation {} of \"{}\"", e - first, self.constraint_names[ci]);
        }
        format!("unknown {unknown}")
    }

    /// Name of a constraint.
    pub fn constraint_name(&self, id: usize) -> &str {
        &self.constraint_names[id]
    }

    /// The user constraint an equation belongs to.
    pub fn equation_constraint(&self, eq: usize) -> usize {
        self.eq_constraint[eq] as usize
    }
}

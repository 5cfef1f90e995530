//! Numbering of coordinates, constraint equations and linear-system
//! unknowns, and the block structure of the iteration matrix.
//!
//! Every constraint equation is matched to a free coordinate of one of the
//! bodies it involves (a maximum bipartite matching, preferring the body with
//! the fewest constraints, so a bearing takes its own prismatic equations).
//! A block is then one body's free coordinates followed by the equations
//! matched to them; its diagonal block `[S G^T; G 0]` is nonsingular whenever
//! the matched gradients are independent, which is what lets the block
//! elimination pivot inside blocks only.

use crate::error::BuildError;
use crate::linalg::block_lu::{BlockOrdering, BlockSymbolic};

/// Marker for "no index" (a locked coordinate, the ground).
pub(crate) const NONE: u32 = u32::MAX;

/// One equation's candidate coordinates, in order of preference.
#[derive(Debug, Clone)]
pub(crate) struct EquationSpec {
    /// Name of the user constraint (for messages).
    pub constraint: String,
    /// Candidate (body, slot) pairs with a structurally non-zero gradient.
    pub candidates: Vec<(u32, u8)>,
}

/// Numbering and block structure.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// Free coordinates.
    pub n: usize,
    /// Constraint equations.
    pub m: usize,
    /// Coordinate index of each body slot (`NONE` if locked or ground).
    pub body_coord: Vec<[u32; 3]>,
    /// Body and slot of each coordinate.
    pub coord_body: Vec<(u32, u8)>,
    /// Coordinate each equation is matched to.
    pub eq_coord: Vec<u32>,
    /// Symbolic block factorisation structure.
    pub sym: BlockSymbolic,
    /// Unknown (row of the iteration matrix) of each coordinate.
    pub unknown_of_coord: Vec<u32>,
    /// Unknown of each equation.
    pub unknown_of_eq: Vec<u32>,
    /// Block position and local index of each unknown.
    pub unknown_place: Vec<(u32, u8)>,
    /// Body name of each block position (for error messages).
    pub position_names: Vec<String>,
}

impl Layout {
    /// Builds the numbering. `couplings` are pairs of bodies coupled by force
    /// elements; `equations` lists each equation's candidates and `eq_bodies`
    /// the bodies each equation involves (two for a primitive, any number
    /// for a linear constraint).
    pub fn new(
        free: &[[bool; 3]],
        names: &[String],
        equations: &[EquationSpec],
        eq_bodies: &[Vec<u32>],
        couplings: &[(u32, u32)],
        ordering: BlockOrdering,
    ) -> Result<Self, BuildError> {
        let nbodies = free.len();
        let mut body_coord = vec![[NONE; 3]; nbodies];
        let mut coord_body = Vec::new();
        for (b, f) in free.iter().enumerate() {
            for s in 0..3 {
                if f[s] {
                    body_coord[b][s] = coord_body.len() as u32;
                    coord_body.push((b as u32, s as u8));
                }
            }
        }
        let n = coord_body.len();
        if n == 0 {
            return Err(BuildError::EmptySystem);
        }
        let m = equations.len();
        let eq_coord = match_equations(equations, &body_coord, n)?;
        let eq_owner: Vec<u32> = eq_coord.iter().map(|&c| coord_body[c as usize].0).collect();

        // Blocks: bodies with free coordinates.
        let mut block_of_body = vec![NONE; nbodies];
        let mut block_body = Vec::new();
        for b in 0..nbodies {
            if body_coord[b].iter().any(|&c| c != NONE) {
                block_of_body[b] = block_body.len() as u32;
                block_body.push(b as u32);
            }
        }
        let mut eqs_of_block: Vec<Vec<u32>> = vec![Vec::new(); block_body.len()];
        for (e, &owner) in eq_owner.iter().enumerate() {
            eqs_of_block[block_of_body[owner as usize] as usize].push(e as u32);
        }
        let sizes: Vec<u32> = block_body
            .iter()
            .zip(&eqs_of_block)
            .map(|(&b, eqs)| body_coord[b as usize].iter().filter(|&&c| c != NONE).count() as u32 + eqs.len() as u32)
            .collect();
        let block = |b: u32| block_of_body[b as usize];
        let mut edges = Vec::new();
        for &(a, b) in couplings {
            if block(a) != NONE && block(b) != NONE {
                edges.push((block(a), block(b)));
            }
        }
        for (e, bodies) in eq_bodies.iter().enumerate() {
            let o = block(eq_owner[e]);
            for &x in bodies {
                if block(x) != NONE {
                    edges.push((o, block(x)));
                }
            }
            // a two-body primitive's Hessian couples its bodies
            if let [a, b] = bodies[..] {
                if block(a) != NONE && block(b) != NONE {
                    edges.push((block(a), block(b)));
                }
            }
        }
        let sym = BlockSymbolic::analyse(&sizes, &edges, ordering);

        let mut unknown_of_coord = vec![NONE; n];
        let mut unknown_of_eq = vec![NONE; m];
        let mut unknown_place = vec![(0u32, 0u8); sym.dim()];
        let mut position_names = Vec::with_capacity(sym.blocks());
        for p in 0..sym.blocks() {
            let blk = sym.block_at(p);
            let body = block_body[blk] as usize;
            position_names.push(format!("body \"{}\"", names[body]));
            let (start, _) = sym.span(p);
            let mut local = 0usize;
            for s in 0..3 {
                let c = body_coord[body][s];
                if c != NONE {
                    unknown_of_coord[c as usize] = (start + local) as u32;
                    local += 1;
                }
            }
            for &e in &eqs_of_block[blk] {
                unknown_of_eq[e as usize] = (start + local) as u32;
                local += 1;
            }
            for l in 0..local {
                unknown_place[start + l] = (p as u32, l as u8);
            }
        }
        Ok(Self {
            n,
            m,
            body_coord,
            coord_body,
            eq_coord,
            sym,
            unknown_of_coord,
            unknown_of_eq,
            unknown_place,
            position_names,
        })
    }

    /// Position in the block value array of entry (row unknown, column unknown).
    pub fn entry(&self, row: u32, col: u32) -> u32 {
        let (pi, li) = self.unknown_place[row as usize];
        let (pj, lj) = self.unknown_place[col as usize];
        let (_, nj) = self.sym.span(pj as usize);
        let off = self.sym.block_offset(pi as usize, pj as usize).expect("entry inside the block pattern");
        off + li as u32 * nj as u32 + lj as u32
    }

    /// Index that receives values of locked coordinates (one past the end).
    pub fn sink(&self) -> u32 {
        self.sym.nnz() as u32
    }
}

/// Maximum bipartite matching of equations to coordinates (Kuhn's augmenting
/// paths), trying candidates in the given order of preference.
fn match_equations(equations: &[EquationSpec], body_coord: &[[u32; 3]], n: usize) -> Result<Vec<u32>, BuildError> {
    let cands: Vec<Vec<u32>> = equations
        .iter()
        .map(|e| e.candidates.iter().map(|&(b, s)| body_coord[b as usize][s as usize]).filter(|&c| c != NONE).collect())
        .collect();
    let mut coord_eq = vec![NONE; n];
    let mut eq_coord = vec![NONE; equations.len()];
    for e in 0..equations.len() {
        // Greedy first: a free preferred candidate.
        if let Some(&c) = cands[e].iter().find(|&&c| coord_eq[c as usize] == NONE) {
            coord_eq[c as usize] = e as u32;
            eq_coord[e] = c;
            continue;
        }
        let mut visited = vec![false; n];
        if !augment(e, &cands, &mut coord_eq, &mut eq_coord, &mut visited) {
            let detail = if cands[e].is_empty() {
                "it involves no free coordinate".to_string()
            } else {
                format!("{} equations compete for the same coordinates", equations.len().min(e + 1))
            };
            return Err(BuildError::RedundantConstraints { constraint: equations[e].constraint.clone(), detail });
        }
    }
    Ok(eq_coord)
}

fn augment(e: usize, cands: &[Vec<u32>], coord_eq: &mut [u32], eq_coord: &mut [u32], visited: &mut [bool]) -> bool {
    for &c in &cands[e] {
        if visited[c as usize] {
            continue;
        }
        visited[c as usize] = true;
        let owner = coord_eq[c as usize];
        if owner == NONE || augment(owner as usize, cands, coord_eq, eq_coord, visited) {
            coord_eq[c as usize] = e as u32;
            eq_coord[e] = c;
            return true;
        }
    }
    false
}

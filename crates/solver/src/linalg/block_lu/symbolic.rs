//! The symbolic analysis of the block elimination, done once per model:
//! the elimination order of the blocks (minimum size-weighted degree), the
//! filled block pattern with each sub-block's offset in the value array,
//! the list of block updates and the solve's kernel shapes.

use std::collections::BTreeSet;

use crate::linalg::scalar::Scalar;

/// How the blocks are ordered for elimination.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlockOrdering {
    /// Minimum size-weighted degree (default).
    #[default]
    MinimumDegree,
    /// The order in which the blocks were given (for comparison).
    Natural,
}

/// The symbolic analysis: elimination order, filled pattern and update lists.
#[derive(Debug, Clone)]
pub struct BlockSymbolic {
    /// Original block index of each elimination position.
    pub(super) order: Vec<u32>,
    /// Elimination position of each original block.
    pub(super) position: Vec<u32>,
    /// Block sizes by position.
    pub(super) sizes: Vec<u32>,
    /// First unknown of each position.
    pub(super) starts: Vec<u32>,
    /// Number of unknowns.
    pub(super) n: usize,
    /// Row pointers of the filled block pattern (by position).
    pub(super) row_ptr: Vec<u32>,
    /// Column positions, sorted within each row.
    pub(super) cols: Vec<u32>,
    /// Offset of each sub-block in the value array.
    pub(super) offs: Vec<u32>,
    /// Offset of each diagonal block.
    pub(super) diag: Vec<u32>,
    /// Whether the sub-block is fill (absent from the original pattern).
    pub(super) fill: Vec<bool>,
    /// Number of stored values.
    pub(super) nnz: usize,
    /// Later neighbours of each position: pointers into the three arrays below.
    pub(super) later_ptr: Vec<u32>,
    pub(super) later_pos: Vec<u32>,
    pub(super) off_kj: Vec<u32>,
    pub(super) off_jk: Vec<u32>,
    /// For position k, the offsets of the targets (i, j) over later x later.
    pub(super) update_ptr: Vec<u32>,
    pub(super) update_off: Vec<u32>,
    /// Floating-point multiply-adds of one real factorisation.
    pub(super) flops: u64,
    /// Per position, the solve kernel of fixed sizes that fits it
    /// ([`Shape`]).
    pub(super) shapes: Vec<Shape>,
}

/// The shapes the solve has kernels of fixed size for: a block of 3
/// unknowns whose later neighbours have 3, 5 or 6 unknowns each (every
/// bearing of the expansion joint, eliminated first and coupled to its
/// center beam and its support beam, and every center beam). Everything
/// else goes through the general loop; fixed sizes save its per-block size
/// lookups, slice bounds and dispatch. (Kernels with the sizes of both
/// neighbours of a bearing fixed at compile time were no faster: 10.7
/// against 11.0 us for the real solve, 21.5 against 21.0 us for the
/// complex one, within the noise.)
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Shape {
    General,
    /// A block of 3 unknowns whose later neighbours have 3, 5 or 6 each.
    Three,
}

impl BlockSymbolic {
    /// Analyses a block pattern given by block `sizes` and undirected coupling
    /// `edges` between blocks (the diagonal is implied).
    pub fn analyse(sizes: &[u32], edges: &[(u32, u32)], ordering: BlockOrdering) -> Self {
        let nb = sizes.len();
        let (adj, original) = adjacency(nb, edges);
        // Elimination (simulated): order and later-neighbour sets.
        let (order, later_sets) = eliminate(sizes, adj, ordering);
        let mut position = vec![0u32; nb];
        for (p, &b) in order.iter().enumerate() {
            position[b as usize] = p as u32;
        }
        let sizes_p: Vec<u32> = order.iter().map(|&b| sizes[b as usize]).collect();
        let mut starts = Vec::with_capacity(nb);
        let mut n = 0u32;
        for &s in &sizes_p {
            starts.push(n);
            n += s;
        }
        let Pattern { row_ptr, cols, offs, fill, nnz, later: later_p } =
            Pattern::filled(&order, &position, &sizes_p, &later_sets, &original);
        let mut sym = Self {
            order,
            position,
            sizes: sizes_p,
            starts,
            n: n as usize,
            row_ptr,
            cols,
            offs,
            diag: Vec::new(),
            fill,
            nnz: nnz as usize,
            later_ptr: vec![0],
            later_pos: Vec::new(),
            off_kj: Vec::new(),
            off_jk: Vec::new(),
            update_ptr: vec![0],
            update_off: Vec::new(),
            flops: 0,
            shapes: Vec::new(),
        };
        sym.diag = (0..nb).map(|k| sym.block_offset(k, k).expect("diagonal")).collect();
        sym.schedule(&later_p);
        sym
    }

    /// Each block's shape, and the elimination's schedule: each block's
    /// later blocks with their offsets, the updates they receive, and the
    /// flops (`later_p`: each block's later blocks by position).
    fn schedule(&mut self, later_p: &[Vec<u32>]) {
        self.shapes = later_p
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let fixed = |j: &u32| matches!(self.sizes[*j as usize], 3 | 5 | 6);
                if self.sizes[k] == 3 && l.iter().all(fixed) {
                    Shape::Three
                } else {
                    Shape::General
                }
            })
            .collect();
        for (k, l) in later_p.iter().enumerate() {
            let nk = self.sizes[k] as u64;
            self.flops += nk * nk * nk;
            for &j in l {
                self.later_pos.push(j);
                self.off_kj.push(self.block_offset(k, j as usize).expect("filled"));
                self.off_jk.push(self.block_offset(j as usize, k).expect("filled"));
                self.flops += nk * nk * self.sizes[j as usize] as u64;
            }
            self.later_ptr.push(self.later_pos.len() as u32);
            for &i in l {
                for &j in l {
                    self.update_off.push(self.block_offset(i as usize, j as usize).expect("filled"));
                    self.flops += self.sizes[i as usize] as u64 * nk * self.sizes[j as usize] as u64;
                }
            }
            self.update_ptr.push(self.update_off.len() as u32);
        }
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Number of stored values (the sub-blocks of the filled pattern).
    pub fn nnz(&self) -> usize {
        self.nnz
    }

    /// Number of blocks.
    pub fn blocks(&self) -> usize {
        self.sizes.len()
    }

    /// Multiply-adds of one real numeric factorisation.
    pub fn flops(&self) -> u64 {
        self.flops
    }

    /// Elimination position of an original block.
    pub fn position_of(&self, block: usize) -> usize {
        self.position[block] as usize
    }

    /// Original block at an elimination position.
    pub fn block_at(&self, position: usize) -> usize {
        self.order[position] as usize
    }

    /// First unknown and size of the block at a position.
    pub fn span(&self, position: usize) -> (usize, usize) {
        (self.starts[position] as usize, self.sizes[position] as usize)
    }

    /// Offset of sub-block (i, j) (positions) in the value array.
    pub fn block_offset(&self, i: usize, j: usize) -> Option<u32> {
        let (a, b) = (self.row_ptr[i] as usize, self.row_ptr[i + 1] as usize);
        let row = &self.cols[a..b];
        row.binary_search(&(j as u32)).ok().map(|p| self.offs[a + p])
    }

    /// Iterates over the sub-blocks: (row position, column position, offset, is fill).
    pub fn sub_blocks(&self) -> impl Iterator<Item = (usize, usize, usize, bool)> + '_ {
        (0..self.sizes.len()).flat_map(move |i| {
            (self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize)
                .map(move |p| (i, self.cols[p] as usize, self.offs[p] as usize, self.fill[p]))
        })
    }

    /// Number of values in original (non-fill) sub-blocks.
    pub fn nnz_original(&self) -> usize {
        self.sub_blocks().filter(|s| !s.3).map(|(i, j, _, _)| (self.sizes[i] * self.sizes[j]) as usize).sum()
    }
}

/// `y = A x` for a matrix in block layout (`values` as filled by the formation).
pub fn block_matvec<T: Scalar>(sym: &BlockSymbolic, values: &[T], x: &[T], y: &mut [T]) {
    y.iter_mut().for_each(|v| *v = T::ZERO);
    for (i, j, off, _) in sym.sub_blocks() {
        let (si, ni) = sym.span(i);
        let (sj, nj) = sym.span(j);
        for r in 0..ni {
            let mut s = T::ZERO;
            for c in 0..nj {
                s += values[off + r * nj + c] * x[sj + c];
            }
            y[si + r] += s;
        }
    }
}

/// The blocks' undirected adjacency (without the diagonal), and the
/// coupled pairs as given (lower block first).
fn adjacency(nb: usize, edges: &[(u32, u32)]) -> (Vec<BTreeSet<u32>>, BTreeSet<(u32, u32)>) {
    let mut adj: Vec<BTreeSet<u32>> = vec![BTreeSet::new(); nb];
    let mut original: BTreeSet<(u32, u32)> = BTreeSet::new();
    for &(a, b) in edges {
        if a != b {
            adj[a as usize].insert(b);
            adj[b as usize].insert(a);
            original.insert((a.min(b), a.max(b)));
        }
    }
    (adj, original)
}

/// Simulates the elimination: the order of the blocks and each block's
/// neighbours when it is eliminated (its later blocks).
fn eliminate(sizes: &[u32], mut adj: Vec<BTreeSet<u32>>, ordering: BlockOrdering) -> (Vec<u32>, Vec<Vec<u32>>) {
    let nb = sizes.len();
    let mut eliminated = vec![false; nb];
    let mut order = Vec::with_capacity(nb);
    let mut later_sets: Vec<Vec<u32>> = vec![Vec::new(); nb];
    let weight = |adj: &BTreeSet<u32>| -> u64 { adj.iter().map(|&u| sizes[u as usize] as u64).sum() };
    let mut wdeg: Vec<u64> = adj.iter().map(weight).collect();
    for step in 0..nb {
        let v = match ordering {
            BlockOrdering::Natural => step,
            BlockOrdering::MinimumDegree => {
                (0..nb).filter(|&v| !eliminated[v]).min_by_key(|&v| (wdeg[v], v)).expect("a block remains")
            }
        };
        eliminated[v] = true;
        order.push(v as u32);
        let nbrs: Vec<u32> = adj[v].iter().copied().collect();
        for &u in &nbrs {
            let au = &mut adj[u as usize];
            au.remove(&(v as u32));
            for &w in &nbrs {
                if w != u {
                    au.insert(w);
                }
            }
            wdeg[u as usize] = weight(&adj[u as usize]);
        }
        later_sets[v] = nbrs;
        adj[v].clear();
    }
    (order, later_sets)
}

/// The filled block pattern by position: rows, columns, each block's
/// offset, whether it is fill, the number of entries and each block's later
/// blocks.
struct Pattern {
    row_ptr: Vec<u32>,
    cols: Vec<u32>,
    offs: Vec<u32>,
    fill: Vec<bool>,
    nnz: u32,
    later: Vec<Vec<u32>>,
}

impl Pattern {
    /// The pattern of the blocks eliminated in `order` (each at its
    /// `position`, of `sizes_p` there) with their later blocks, fill being
    /// what `original` lacks.
    fn filled(
        order: &[u32],
        position: &[u32],
        sizes_p: &[u32],
        later_sets: &[Vec<u32>],
        original: &BTreeSet<(u32, u32)>,
    ) -> Self {
        let nb = order.len();
        let mut rows: Vec<BTreeSet<u32>> = vec![BTreeSet::new(); nb];
        let mut later_p: Vec<Vec<u32>> = vec![Vec::new(); nb];
        for (b, set) in later_sets.iter().enumerate() {
            let k = position[b];
            rows[k as usize].insert(k);
            let mut l: Vec<u32> = set.iter().map(|&u| position[u as usize]).collect();
            l.sort_unstable();
            for &j in &l {
                rows[k as usize].insert(j);
                rows[j as usize].insert(k);
            }
            later_p[k as usize] = l;
        }
        let mut row_ptr = vec![0u32];
        let mut cols = Vec::new();
        let mut offs = Vec::new();
        let mut fill = Vec::new();
        let mut nnz = 0u32;
        for (i, r) in rows.iter().enumerate() {
            for &j in r {
                cols.push(j);
                offs.push(nnz);
                let (bi, bj) = (order[i], order[j as usize]);
                fill.push(i as u32 != j && !original.contains(&(bi.min(bj), bi.max(bj))));
                nnz += sizes_p[i] * sizes_p[j as usize];
            }
            row_ptr.push(cols.len() as u32);
        }
        Pattern { row_ptr, cols, offs, fill, nnz, later: later_p }
    }
}

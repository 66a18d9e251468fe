//! B = A(q)⁻¹ for models that give no inverse: an LU factorization with partial pivoting,
//! unrolled into the right-hand side and evaluated numerically at every call.
//!
//! A(q) is mostly structure: rows of constants (ω = α̇), rows that touch two coordinates. A
//! dense factorization of run-time values would throw that away and cost n³; instead, as
//! sparse direct solvers do (KLU), the matrix is first permuted to block-triangular form from
//! its sparsity pattern, which is valid for every q:
//!
//! 1. a maximum matching of rows to columns puts a structurally nonzero entry on the
//!    diagonal (none exists: A(q) is singular for every q, a compile-time error);
//! 2. the strongly connected components of the matched graph are the diagonal blocks, in an
//!    order in which every block only needs unknowns of earlier blocks.
//!
//! Each diagonal block is factored with partial pivoting among the rows whose entry can be
//! nonzero: the largest magnitude wins at run time, through selects; where only one row is a
//! candidate the choice is static. Divisions are by the chosen pivots, which the generated
//! code checks against the matrix's scale before any result is used. Several right-hand
//! sides share the factorization, because it is built from the same nodes each time and the
//! graph is hash-consed.

use crate::engine::graph::{Cmp, Func, Graph, NodeId};

/// Why A(q) is singular for every q: a column (coordinate) that no matching reaches.
pub struct StructurallySingular {
    pub column: usize,
}

#[derive(Clone)]
pub struct SparseLu {
    a: Vec<Vec<NodeId>>,
    /// Diagonal blocks in solving order: (rows, columns), rows matched to columns in order.
    blocks: Vec<(Vec<usize>, Vec<usize>)>,
}

impl SparseLu {
    /// n, the number of rows and columns of A.
    pub fn len(&self) -> usize {
        self.a.len()
    }

    pub fn new(g: &Graph, a: &[Vec<NodeId>]) -> Result<SparseLu, StructurallySingular> {
        let n = a.len();
        let nonzero: Vec<Vec<bool>> = a
            .iter()
            .map(|row| row.iter().map(|&e| !g.is_zero(e)).collect())
            .collect();
        let row_of = matching(&nonzero).map_err(|column| StructurallySingular { column })?;
        // Column j depends on column k when the row matched to j involves k.
        let edges: Vec<Vec<usize>> = (0..n)
            .map(|j| {
                (0..n)
                    .filter(|&k| k != j && nonzero[row_of[j]][k])
                    .collect()
            })
            .collect();
        let blocks = strongly_connected(&edges)
            .into_iter()
            .map(|columns| (columns.iter().map(|&j| row_of[j]).collect(), columns))
            .collect();
        Ok(SparseLu {
            a: a.to_vec(),
            blocks,
        })
    }

    /// The solution of A x = b, and the pivots the factorization divided by, each with the
    /// column (coordinate) it solved for.
    pub fn solve(&self, g: &mut Graph, b: &[NodeId]) -> (Vec<NodeId>, Vec<(NodeId, usize)>) {
        let n = self.a.len();
        let mut x: Vec<Option<NodeId>> = vec![None; n];
        let mut pivots = Vec::new();
        for (rows, columns) in &self.blocks {
            // Right-hand side of the block: b minus what earlier blocks contribute.
            let mut augmented: Vec<Vec<NodeId>> = rows
                .iter()
                .map(|&r| {
                    let rhs = reduced(g, b[r], &x, columns, |k| self.a[r][k]);
                    let mut row: Vec<NodeId> = columns.iter().map(|&c| self.a[r][c]).collect();
                    row.push(rhs);
                    row
                })
                .collect();
            let mut block_pivots = Vec::new();
            let solved = eliminate(g, &mut augmented, &mut block_pivots);
            pivots.extend(block_pivots.into_iter().zip(columns.iter().copied()));
            for (&c, v) in columns.iter().zip(solved) {
                x[c] = Some(v);
            }
        }
        let zero = g.zero();
        (x.into_iter().map(|v| v.unwrap_or(zero)).collect(), pivots)
    }
}

impl SparseLu {
    /// The solution y of Aᵀ y = r, one entry per row of A. Column c of A meets only the rows
    /// of its own block and of later ones, so the blocks are solved in reverse order, each
    /// transposed and eliminated with partial pivoting like the forward solve (its pivots
    /// are nonzero wherever the forward ones are: the block is the same matrix).
    pub fn solve_transposed(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        let mut y: Vec<Option<NodeId>> = vec![None; self.a.len()];
        for (rows, columns) in self.blocks.iter().rev() {
            let mut augmented: Vec<Vec<NodeId>> = columns
                .iter()
                .map(|&c| {
                    let rhs = self.transposed_rhs(g, r, &y, rows, c);
                    let mut row: Vec<NodeId> = rows.iter().map(|&i| self.a[i][c]).collect();
                    row.push(rhs);
                    row
                })
                .collect();
            let solved = eliminate(g, &mut augmented, &mut Vec::new());
            for (&i, v) in rows.iter().zip(solved) {
                y[i] = Some(v);
            }
        }
        let zero = g.zero();
        y.into_iter().map(|v| v.unwrap_or(zero)).collect()
    }

    /// r_c minus what the rows already solved (those of later blocks) contribute to
    /// column c of Aᵀ y = r.
    fn transposed_rhs(
        &self,
        g: &mut Graph,
        r: &[NodeId],
        y: &[Option<NodeId>],
        rows: &[usize],
        c: usize,
    ) -> NodeId {
        reduced(g, r[c], y, rows, |i| self.a[i][c])
    }
}

/// `start − Σ_k entry(k)·solved[k]` over the unknowns already solved, but those of the
/// block at hand (`own`): a block's right-hand side once the blocks solved before it are
/// substituted (with `entry` a row of A, or a column for the transposed solve).
fn reduced(
    g: &mut Graph,
    start: NodeId,
    solved: &[Option<NodeId>],
    own: &[usize],
    entry: impl Fn(usize) -> NodeId,
) -> NodeId {
    let mut acc = start;
    for (k, value) in solved.iter().enumerate() {
        if let Some(value) = value
            && !own.contains(&k)
        {
            let t = g.mul(entry(k), *value);
            acc = g.sub(acc, t);
        }
    }
    acc
}

/// Gaussian elimination with partial pivoting on an augmented block [M | r], unrolled.
fn eliminate(g: &mut Graph, rows: &mut [Vec<NodeId>], pivots: &mut Vec<NodeId>) -> Vec<NodeId> {
    let s = rows.len();
    let mut inverse_pivots = Vec::with_capacity(s);
    for k in 0..s {
        let candidates: Vec<usize> = (k..s).filter(|&i| !g.is_zero(rows[i][k])).collect();
        match candidates.as_slice() {
            [] => {}
            [only] => rows.swap(k, *only),
            _ => pivot_at_run_time(g, rows, k, &candidates),
        }
        let pivot = rows[k][k];
        pivots.push(pivot);
        let one = g.one();
        let inverse = g.div(one, pivot);
        inverse_pivots.push(inverse);
        for i in k + 1..s {
            if g.is_zero(rows[i][k]) {
                continue;
            }
            let factor = g.mul(rows[i][k], inverse);
            let pivot_row = rows[k].clone();
            for (entry, &above) in rows[i].iter_mut().zip(&pivot_row).skip(k + 1) {
                let t = g.mul(factor, above);
                *entry = g.sub(*entry, t);
            }
            rows[i][k] = g.zero();
        }
    }
    let mut x = vec![g.zero(); s];
    for k in (0..s).rev() {
        let mut acc = rows[k][s];
        for j in k + 1..s {
            let t = g.mul(rows[k][j], x[j]);
            acc = g.sub(acc, t);
        }
        x[k] = g.mul(acc, inverse_pivots[k]);
    }
    x
}

/// Bring the candidate with the largest |entry| in column k to row k, with selects: the
/// comparisons run at run time, and the displaced row k takes the pivot row's place.
fn pivot_at_run_time(g: &mut Graph, rows: &mut [Vec<NodeId>], k: usize, candidates: &[usize]) {
    let magnitudes: Vec<NodeId> = candidates
        .iter()
        .map(|&i| g.unary(Func::Abs, rows[i][k]))
        .collect();
    // takes[i]: candidate i beats every earlier one (strictly, so ties keep the first).
    let mut best = magnitudes[0];
    let mut takes = vec![g.boolean(true)];
    for &m in &magnitudes[1..] {
        let t = g.compare(Cmp::Gt, m, best);
        best = g.select(t, m, best);
        takes.push(t);
    }
    // chosen[i]: i took the lead and nobody after it did.
    let mut chosen = vec![g.boolean(false); candidates.len()];
    let mut none_later = g.boolean(true);
    for i in (0..candidates.len()).rev() {
        chosen[i] = g.and(takes[i], none_later);
        let not = g.not(takes[i]);
        none_later = g.and(none_later, not);
    }
    let width = rows[k].len();
    let old_k = rows[k].clone();
    let mut pivot_row = rows[candidates[0]].clone();
    for (i, &c) in candidates.iter().enumerate().skip(1) {
        for j in 0..width {
            pivot_row[j] = g.select(chosen[i], rows[c][j], pivot_row[j]);
        }
    }
    for (i, &c) in candidates.iter().enumerate() {
        if c == k {
            continue;
        }
        for j in 0..width {
            rows[c][j] = g.select(chosen[i], old_k[j], rows[c][j]);
        }
    }
    rows[k] = pivot_row;
}

/// A perfect matching row_of[column] of a square pattern, or a column left unmatched.
fn matching(nonzero: &[Vec<bool>]) -> Result<Vec<usize>, usize> {
    let n = nonzero.len();
    let mut col_of_row: Vec<Option<usize>> = vec![None; n];
    fn augment(
        j: usize,
        nonzero: &[Vec<bool>],
        seen: &mut [bool],
        col_of_row: &mut [Option<usize>],
    ) -> bool {
        for r in 0..nonzero.len() {
            if nonzero[r][j] && !seen[r] {
                seen[r] = true;
                if col_of_row[r].is_none_or(|other| augment(other, nonzero, seen, col_of_row)) {
                    col_of_row[r] = Some(j);
                    return true;
                }
            }
        }
        false
    }
    for j in 0..n {
        let mut seen = vec![false; n];
        if !augment(j, nonzero, &mut seen, &mut col_of_row) {
            return Err(j);
        }
    }
    let mut row_of = vec![0; n];
    for (r, c) in col_of_row.iter().enumerate() {
        if let Some(c) = c {
            row_of[*c] = r;
        }
    }
    Ok(row_of)
}

/// Tarjan's strongly connected components; each component comes after the components it
/// has edges into, which is the order to solve the blocks in.
fn strongly_connected(edges: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct State<'e> {
        edges: &'e [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(v: usize, st: &mut State<'_>) {
        st.index[v] = Some(st.next);
        st.low[v] = st.next;
        st.next += 1;
        st.stack.push(v);
        st.on_stack[v] = true;
        for &w in &st.edges[v] {
            match st.index[w] {
                None => {
                    visit(w, st);
                    st.low[v] = st.low[v].min(st.low[w]);
                }
                Some(iw) if st.on_stack[w] => st.low[v] = st.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(st.low[v]) == st.index[v] {
            let mut component = Vec::new();
            while let Some(w) = st.stack.pop() {
                st.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            component.sort_unstable();
            st.out.push(component);
        }
    }
    let n = edges.len();
    let mut st = State {
        edges,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if st.index[v].is_none() {
            visit(v, &mut st);
        }
    }
    st.out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robot_like_pattern_splits_into_small_blocks() {
        // Rows of the robot's A: [s, −c, 0, 0, 0], [−c, −s, r, r/2, r/2], [0, 0, 1, 0, 0],
        // [c, s, 0, 0, 0], [0, 0, 0, r/b, −r/b].
        let mut g = Graph::new();
        let s = g.new_input("s");
        let c = g.new_input("c");
        let r = g.new_input("r");
        let h = g.new_input("h");
        let k = g.new_input("k");
        let (z, one) = (g.zero(), g.one());
        let (nc, ns, nk) = (g.neg(c), g.neg(s), g.neg(k));
        let a = vec![
            vec![s, nc, z, z, z],
            vec![nc, ns, r, h, h],
            vec![z, z, one, z, z],
            vec![c, s, z, z, z],
            vec![z, z, z, k, nk],
        ];
        let lu = SparseLu::new(&g, &a).ok().unwrap();
        let sizes: Vec<usize> = lu.blocks.iter().map(|(_, cols)| cols.len()).collect();
        assert_eq!(sizes.iter().sum::<usize>(), 5);
        assert!(sizes.iter().all(|&s| s <= 2), "{sizes:?}");
        let b: Vec<NodeId> = (0..5).map(|i| g.new_input(format!("b{i}"))).collect();
        let (x, _) = lu.solve(&mut g, &b);
        // Check A x = b numerically at a configuration where pivoting matters (|c| > |s|).
        let theta: f64 = 0.3;
        let vals = [
            theta.sin(),
            theta.cos(),
            0.1,
            0.05,
            0.2,
            1.0,
            -2.0,
            0.5,
            3.0,
            0.25,
        ];
        let xs = g.evaluate(&x, &vals);
        let am = [
            [vals[0], -vals[1], 0.0, 0.0, 0.0],
            [-vals[1], -vals[0], 0.1, 0.05, 0.05],
            [0.0, 0.0, 1.0, 0.0, 0.0],
            [vals[1], vals[0], 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.2, -0.2],
        ];
        for i in 0..5 {
            let ax: f64 = (0..5).map(|j| am[i][j] * xs[j]).sum();
            assert!(
                (ax - vals[5 + i]).abs() < 1e-14,
                "row {i}: {ax} vs {}",
                vals[5 + i]
            );
        }
    }

    #[test]
    fn structurally_singular_names_a_column() {
        let mut g = Graph::new();
        let x = g.new_input("x");
        let z = g.zero();
        let a = vec![vec![x, z], vec![x, z]];
        assert_eq!(SparseLu::new(&g, &a).err().map(|e| e.column), Some(1));
    }

    #[test]
    fn pivoting_picks_the_larger_entry() {
        // [[ε, 1], [1, 1]] x = [1, 2]: without pivoting the ε pivot loses all accuracy.
        let mut g = Graph::new();
        let e = g.new_input("e");
        let one = g.one();
        let a = vec![vec![e, one], vec![one, one]];
        let lu = SparseLu::new(&g, &a).ok().unwrap();
        let two = g.constant(2.0);
        let (x, pivots) = lu.solve(&mut g, &[one, two]);
        let v = g.evaluate(&x, &[1e-20]);
        assert!(
            (v[0] - 1.0).abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15,
            "{v:?}"
        );
        let pivots: Vec<NodeId> = pivots.into_iter().map(|(p, _)| p).collect();
        let p = g.evaluate(&pivots, &[1e-20]);
        assert!(p.iter().all(|p| p.abs() > 0.5), "{p:?}");
    }
}

/// The largest diagonal block inverted in closed form, by its adjugate: the cofactors of a
/// 3 × 3 block are 2 × 2 determinants, and beyond that the expressions grow faster than the
/// elimination they replace.
pub const MAX_CLOSED_BLOCK: usize = 3;

/// A⁻¹ in closed form: the closed-form inverses of A's diagonal blocks, to solve with, and the
/// determinants to check at run time.
pub struct ClosedInverse {
    /// Each diagonal block's determinant that is not a constant, with the scale it must
    /// exceed n·ε times ([`SparseLu::determinant_checks`]) and the first coordinate the
    /// block determines.
    pub checks: Vec<(NodeId, NodeId, usize)>,
    /// Solves with the same block inverses, for other right-hand sides.
    pub solver: BlockSolver,
}

impl SparseLu {
    /// B = A⁻¹ in closed form when every diagonal block of the block-triangular form has at
    /// most [`MAX_CLOSED_BLOCK`] rows: each block inverted as adj(M)/det(M), the blocks
    /// solved in order. No pivot is chosen, so B is exact wherever A is invertible
    /// (det A is the product of the blocks' determinants), and the graph's normal form sees
    /// what cancels through it (sin² + cos² of a rotation block, r/b·b/r).
    ///
    /// Only where it replaces pivoting at run time: when every block is a single row, A is
    /// triangular up to permutation and the LU is already plain substitution with no pivot
    /// to choose.
    pub fn closed_inverse(&self, g: &mut Graph, varying: &[NodeId]) -> Option<ClosedInverse> {
        let largest = self.blocks.iter().map(|(rows, _)| rows.len()).max()?;
        if !(2..=MAX_CLOSED_BLOCK).contains(&largest) {
            return None;
        }
        let blocks: Vec<Vec<Vec<NodeId>>> = self
            .blocks
            .iter()
            .map(|(rows, columns)| {
                rows.iter()
                    .map(|&r| columns.iter().map(|&c| self.a[r][c]).collect())
                    .collect()
            })
            .collect();
        let determinants: Vec<NodeId> = blocks.iter().map(|m| determinant(g, m)).collect();
        let checks = self.determinant_checks(g, varying, &blocks, &determinants);
        let mut inverses = Vec::with_capacity(blocks.len());
        for (m, &det) in blocks.iter().zip(&determinants) {
            let one = g.one();
            let reciprocal = g.div(one, det);
            // inverse[j][i] = C_ij / det: the adjugate is the cofactors transposed.
            let s = m.len();
            let mut inverse = vec![vec![g.zero(); s]; s];
            for i in 0..s {
                for (j, inverse_row) in inverse.iter_mut().enumerate() {
                    let cofactor = cofactor(g, m, i, j);
                    inverse_row[i] = g.mul(cofactor, reciprocal);
                }
            }
            inverses.push(inverse);
        }
        let solver = BlockSolver {
            lu: self.clone(),
            inverses,
        };
        Some(ClosedInverse { checks, solver })
    }
}

/// Solves A x = r block by block with the blocks' closed-form inverses: as sparse as the LU's
/// substitution (a dense B·r would cost n² where A's rows are sparse).
#[derive(Clone)]
pub struct BlockSolver {
    lu: SparseLu,
    /// Each block's inverse, `inverses[b][j][i]`: column j of the block per unit of row i.
    inverses: Vec<Vec<Vec<NodeId>>>,
}

impl BlockSolver {
    /// n, the number of rows and columns of A.
    pub fn len(&self) -> usize {
        self.lu.len()
    }

    pub fn solve(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        let n = self.lu.a.len();
        let mut x: Vec<Option<NodeId>> = vec![None; n];
        for ((rows, columns), inverse) in self.lu.blocks.iter().zip(&self.inverses) {
            let rhs: Vec<NodeId> = rows
                .iter()
                .map(|&row| reduced(g, r[row], &x, columns, |c| self.lu.a[row][c]))
                .collect();
            for (j, &c) in columns.iter().enumerate() {
                let terms: Vec<NodeId> = inverse[j]
                    .iter()
                    .zip(&rhs)
                    .map(|(&m, &v)| g.mul(m, v))
                    .collect();
                x[c] = Some(g.sum(&terms));
            }
        }
        let zero = g.zero();
        x.into_iter().map(|v| v.unwrap_or(zero)).collect()
    }
}

impl BlockSolver {
    /// The solution y of Aᵀ y = r (one entry per row of A) with the same block inverses,
    /// the blocks in reverse order ([`SparseLu::solve_transposed`]).
    pub fn solve_transposed(&self, g: &mut Graph, r: &[NodeId]) -> Vec<NodeId> {
        let mut y: Vec<Option<NodeId>> = vec![None; self.lu.a.len()];
        for ((rows, columns), inverse) in self.lu.blocks.iter().zip(&self.inverses).rev() {
            let rhs: Vec<NodeId> = columns
                .iter()
                .map(|&c| self.lu.transposed_rhs(g, r, &y, rows, c))
                .collect();
            // (M⁻ᵀ)_{ij} = (M⁻¹)_{ji} = inverse[j][i].
            for (i, &row) in rows.iter().enumerate() {
                let terms: Vec<NodeId> = inverse
                    .iter()
                    .zip(&rhs)
                    .map(|(column, &v)| g.mul(column[i], v))
                    .collect();
                y[row] = Some(g.sum(&terms));
            }
        }
        let zero = g.zero();
        y.into_iter().map(|v| v.unwrap_or(zero)).collect()
    }
}

impl SparseLu {
    /// A's scale S = Σ|A_ij| that pivots and determinants are checked against: a plain sum
    /// of magnitudes, where a NaN-aware `max` chain would cost more than the factorization
    /// it guards.
    pub fn scale(&self, g: &mut Graph) -> NodeId {
        let entries: Vec<NodeId> = self
            .a
            .iter()
            .flatten()
            .copied()
            .filter(|&e| !g.is_zero(e))
            .collect();
        let magnitudes: Vec<NodeId> = entries.into_iter().map(|e| g.unary(Func::Abs, e)).collect();
        g.sum(&magnitudes)
    }

    /// What to check of each block's determinant before B is used: nothing for a constant
    /// (nonzero: A is never singular, or the rank check would have refused the model); that
    /// it is not zero for one that depends on the parameters only; and for one that varies
    /// with q or t, |det| > n·ε·S^k with S = Σ|A_ij| (the LU's scale) for a k × k block.
    /// The first coordinate each block determines names it.
    fn determinant_checks(
        &self,
        g: &mut Graph,
        varying: &[NodeId],
        blocks: &[Vec<Vec<NodeId>>],
        determinants: &[NodeId],
    ) -> Vec<(NodeId, NodeId, usize)> {
        let active = g.depends_on(varying);
        let mut scale = None;
        let mut checks = Vec::new();
        for ((m, &det), (_, columns)) in blocks.iter().zip(determinants).zip(&self.blocks) {
            if g.const_value(det).is_some() {
                continue;
            }
            let bound = if active[det.index()] {
                let s = *scale.get_or_insert_with(|| self.scale(g));
                let mut power = s;
                for _ in 1..m.len() {
                    power = g.mul(power, s);
                }
                power
            } else {
                g.zero()
            };
            checks.push((det, bound, columns[0]));
        }
        checks
    }
}

/// det M by expansion along the first row (M has at most [`MAX_CLOSED_BLOCK`] rows).
fn determinant(g: &mut Graph, m: &[Vec<NodeId>]) -> NodeId {
    match m.len() {
        0 => g.one(),
        1 => m[0][0],
        _ => {
            let mut terms = Vec::with_capacity(m.len());
            for j in 0..m.len() {
                if g.is_zero(m[0][j]) {
                    continue;
                }
                let c = cofactor(g, m, 0, j);
                terms.push(g.mul(m[0][j], c));
            }
            g.sum(&terms)
        }
    }
}

/// The cofactor C_ij = (−1)^{i+j} det(M without row i and column j).
fn cofactor(g: &mut Graph, m: &[Vec<NodeId>], i: usize, j: usize) -> NodeId {
    let minor: Vec<Vec<NodeId>> = m
        .iter()
        .enumerate()
        .filter(|&(r, _)| r != i)
        .map(|(_, row)| {
            row.iter()
                .enumerate()
                .filter(|&(c, _)| c != j)
                .map(|(_, &e)| e)
                .collect()
        })
        .collect();
    let d = determinant(g, &minor);
    if (i + j) % 2 == 1 { g.neg(d) } else { d }
}

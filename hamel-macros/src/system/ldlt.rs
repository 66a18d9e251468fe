//! The reduced mass matrix is factored at run time, by an LDLᵀ factorization the macro
//! unrolls into the right-hand side. Its entries are graph nodes, so structural zeros fold:
//! for the mobile robot, whose mass matrix has a zero block, the emitted solve has only the
//! operations that the nonzero pattern needs. No symbolic inverse is ever formed.

use crate::engine::graph::{Graph, NodeId};

pub struct Solution {
    /// The solution x of M x = b.
    pub x: Vec<NodeId>,
    /// The pivots D of M = L D Lᵀ; all must be positive for a mass matrix.
    pub pivots: Vec<NodeId>,
}

/// Solve M x = b for a symmetric positive definite M (only its lower triangle is read).
pub fn solve(g: &mut Graph, m: &[Vec<NodeId>], b: &[NodeId]) -> Solution {
    let d = b.len();
    // l[r][j] (r > j) is L; e[r][j] = l[r][j]·D[j] saves a product in every update.
    let mut l = vec![vec![g.zero(); d]; d];
    let mut e = vec![vec![g.zero(); d]; d];
    let mut pivots = Vec::with_capacity(d);
    let mut inverse_pivots = Vec::with_capacity(d);
    for j in 0..d {
        let terms: Vec<NodeId> = (0..j).map(|i| g.mul(l[j][i], e[j][i])).collect();
        let s = g.sum(&terms);
        let dj = g.sub(m[j][j], s);
        let one = g.one();
        let inv = g.div(one, dj);
        pivots.push(dj);
        inverse_pivots.push(inv);
        for r in j + 1..d {
            let terms: Vec<NodeId> = (0..j).map(|i| g.mul(l[r][i], e[j][i])).collect();
            let s = g.sum(&terms);
            let t = g.sub(m[r][j], s);
            e[r][j] = t;
            l[r][j] = g.mul(t, inv);
        }
    }
    // L y = b, then Lᵀ x = D⁻¹ y.
    let mut y = b.to_vec();
    for r in 0..d {
        let terms: Vec<NodeId> = (0..r).map(|i| g.mul(l[r][i], y[i])).collect();
        let s = g.sum(&terms);
        y[r] = g.sub(y[r], s);
    }
    let mut x = vec![g.zero(); d];
    for r in (0..d).rev() {
        let z = g.mul(y[r], inverse_pivots[r]);
        let terms: Vec<NodeId> = (r + 1..d).map(|i| g.mul(l[i][r], x[i])).collect();
        let s = g.sum(&terms);
        x[r] = g.sub(z, s);
    }
    Solution { x, pivots }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_folds_structural_zeros() {
        let mut g = Graph::new();
        let a = g.new_input("a");
        let c = g.new_input("c");
        let dd = g.new_input("d");
        let j = g.new_input("j");
        let zero = g.zero();
        let m = vec![vec![a, c, zero], vec![c, dd, zero], vec![zero, zero, j]];
        let b: Vec<NodeId> = (0..3).map(|i| g.new_input(format!("b{i}"))).collect();
        let s = solve(&mut g, &m, &b);
        // The decoupled last unknown is b2 / j, with nothing from the 2×2 block.
        let vals = [4.0, 1.0, 3.0, 2.0, 1.0, 2.0, 3.0];
        let x = g.evaluate(&s.x, &vals);
        let (a, c, d, j) = (4.0, 1.0, 3.0, 2.0);
        let det = a * d - c * c;
        let expect = [
            (d * 1.0 - c * 2.0) / det,
            (a * 2.0 - c * 1.0) / det,
            3.0 / j,
        ];
        for (got, want) in x.iter().zip(expect) {
            assert!((got - want).abs() < 1e-15, "{got} vs {want}");
        }
        assert_eq!(crate::engine::ops::count(&g, &[s.x[2]]).total(), 2); // 1/j and b2·(1/j)
    }
}

//! Where each entry of the compiled Jacobian and second derivatives goes in CasADi's output
//! blocks, computed when the exporting crate compiles (`const fn`, from the tables
//! `#[hamel_system]` emits and the parameters' places in `Parameters::NAMES`).
//!
//! The compiled code hands each entry to a `put(k, value)` with k a constant (its index in
//! the table); [`crate::model!`] makes `put` store the value at `to[output].add(slot)` with
//! (output, slot) from these tables, constants too: one store an entry, straight into the
//! block CasADi asked for (or into a scratch buffer for a block it did not ask for). The
//! macro cannot place the entries itself: the blocks by p are in the order of the struct's
//! fields, which `#[hamel_system]` on the impl block does not see.
//!
//! A block's slots are its entries in CasADi's order (compressed columns: by column, then by
//! row). [`crate::casadi::plan`] checks these tables against the outputs' sparsity when a
//! library is loaded, and takes the dual-number path for a function whose tables disagree.

/// The output index of a destination that is not an output (an entry by a column that is
/// in no input block, such as the time of a model that does not depend on it): the last of
/// the [`Destinations`], always the scratch buffer.
pub const DISCARD: usize = 24;

/// The pointers the compiled code's `put` writes through, by output index (`jac_f`: one per
/// input block; `jac_adj1_f`: its outputs, at most 4 × 6), and [`DISCARD`]. None is null:
/// an output CasADi did not ask for points to a scratch buffer.
pub type Destinations = [*mut f64; DISCARD + 1];

/// A destination: (output index, slot within the output's nonzeros).
pub type Slot = (usize, usize);

/// The compiled code's columns (x, u, the parameters it reads, t) as the input blocks of a
/// function (x, u if `with_u`, p, t if `time`).
#[derive(Clone, Copy, Debug)]
pub struct Columns {
    pub nx: usize,
    pub nu: usize,
    /// The parameters the code reads, as positions in `Parameters::NAMES`.
    pub read: &'static [usize],
    /// Whether the function takes u (the right-hand side; not the outputs).
    pub with_u: bool,
    /// Whether the function takes t.
    pub time: bool,
}

impl Columns {
    /// How many input blocks.
    pub const fn blocks(&self) -> usize {
        2 + self.with_u as usize + self.time as usize
    }

    /// The input block of column `c` and its place in it, or `None`.
    pub const fn block(&self, c: usize) -> Option<(usize, usize)> {
        if c < self.nx {
            return Some((0, c));
        }
        let c = c - self.nx;
        if c < self.nu {
            return if self.with_u { Some((1, c)) } else { None };
        }
        let c = c - self.nu;
        let p = 1 + self.with_u as usize;
        if c < self.read.len() {
            return Some((p, self.read[c]));
        }
        if c == self.read.len() && self.time {
            return Some((p + 1, 0));
        }
        None
    }
}

/// Whether (column, row) `a` comes before `b` in compressed-column order.
const fn before(a: (usize, usize), b: (usize, usize)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

/// A place in an output: (output, column, row); `None` for no output.
type Place = Option<(usize, usize, usize)>;

/// The slot of `place` among `places` (those of the same output before it); `DISCARD` for
/// no output.
const fn slot_of(place: Place, places: &[[Place; 2]], count: usize) -> Slot {
    let Some((output, column, row)) = place else {
        return (DISCARD, 0);
    };
    let mut slot = 0;
    let mut k = 0;
    while k < count {
        let mut h = 0;
        while h < 2 {
            if let Some((o, c, r)) = places[k][h] {
                if o == output && before((c, r), (column, row)) {
                    slot += 1;
                }
            }
            h += 1;
        }
        k += 1;
    }
    (output, slot)
}

/// `jac_f`: entry (row r, column c) of block b goes to output b at (column within b, r).
pub const fn jacobian<const N: usize>(entries: &[(usize, usize)], columns: Columns) -> [Slot; N] {
    jacobian_slots(entries, columns, false)
}

/// The slots of the Jacobian's entries: in `jac_f`'s outputs, or `transposed` in
/// `jac_adj1_f`'s blocks by the adjoint seed.
const fn jacobian_slots<const N: usize>(
    entries: &[(usize, usize)],
    columns: Columns,
    transposed: bool,
) -> [Slot; N] {
    let nb = columns.blocks();
    let mut places = [[None; 2]; N];
    let mut k = 0;
    while k < N {
        let (r, c) = entries[k];
        if let Some((b, w)) = columns.block(c) {
            places[k][0] = Some(if transposed {
                (second_output(&columns, b, nb + 1), r, w)
            } else {
                (b, w, r)
            });
        }
        k += 1;
    }
    let mut out = [(DISCARD, 0); N];
    let mut k = 0;
    while k < N {
        out[k] = slot_of(places[k][0], &places, N);
        k += 1;
    }
    out
}

/// The output index of `jac_adj1_f`'s block by input blocks (i, j): for each i, the blocks
/// by every j, by the nominal output and by the adjoint seed (the transposed Jacobian).
const fn second_output(columns: &Columns, i: usize, j: usize) -> usize {
    i * (columns.blocks() + 2) + j
}

/// `jac_adj1_f`'s weighted second derivatives: entry (a, b), a ≥ b, goes to block (block of
/// a, block of b) at (row a, column b) and, for a ≠ b, to the block the other way round.
pub const fn second<const N: usize>(
    entries: &[(usize, usize)],
    columns: Columns,
) -> [[Slot; 2]; N] {
    let mut places = [[None; 2]; N];
    let mut k = 0;
    while k < N {
        let (a, b) = entries[k];
        if let (Some((ka, wa)), Some((kb, wb))) = (columns.block(a), columns.block(b)) {
            places[k][0] = Some((second_output(&columns, ka, kb), wb, wa));
            if a != b {
                places[k][1] = Some((second_output(&columns, kb, ka), wa, wb));
            }
        }
        k += 1;
    }
    let mut out = [[(DISCARD, 0); 2]; N];
    let mut k = 0;
    while k < N {
        out[k] = [
            slot_of(places[k][0], &places, N),
            slot_of(places[k][1], &places, N),
        ];
        k += 1;
    }
    out
}

/// `jac_adj1_f`'s transposed Jacobian blocks: Jacobian entry (r, c) of block b goes to the
/// block of b by the adjoint seed at (row within b, column r).
pub const fn transposed<const N: usize>(entries: &[(usize, usize)], columns: Columns) -> [Slot; N] {
    jacobian_slots(entries, columns, true)
}

/// The largest slot + 1 of `slots` (for the scratch buffer's length).
pub const fn most(slots: &[Slot]) -> usize {
    let mut most = 0;
    let mut k = 0;
    while k < slots.len() {
        if slots[k].1 + 1 > most {
            most = slots[k].1 + 1;
        }
        k += 1;
    }
    most
}

/// The compiled layout of one family's functions, for `plan` to check.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    /// `jac_f`'s destination of each Jacobian entry.
    pub jacobian: &'static [Slot],
    /// `jac_adj1_f`'s destinations of each second-derivative entry (the second `DISCARD`
    /// for a diagonal entry).
    pub second: &'static [[Slot; 2]],
    /// `jac_adj1_f`'s destination of each Jacobian entry (its transposed blocks).
    pub transposed: &'static [Slot],
}

#[cfg(test)]
mod tests {
    use super::*;

    const COLUMNS: Columns = Columns {
        nx: 2,
        nu: 1,
        read: &[1, 0],
        with_u: true,
        time: false,
    };

    #[test]
    fn the_blocks_by_p_follow_the_fields_order() {
        // Local columns: x0 x1 u0 p1 p0 t; block p is output 2, in the fields' order.
        assert_eq!(COLUMNS.block(3), Some((2, 1)));
        assert_eq!(COLUMNS.block(4), Some((2, 0)));
        assert_eq!(COLUMNS.block(5), None);
        let entries = [(0, 0), (1, 0), (0, 3), (1, 4), (0, 4), (0, 5)];
        let slots: [Slot; 6] = jacobian(&entries, COLUMNS);
        // Block p: (row 1, p0), (row 0, p0), (row 0, p1) in CasADi's order: p0's column
        // (rows 0, 1), then p1's.
        assert_eq!(
            slots,
            [(0, 0), (0, 1), (2, 2), (2, 1), (2, 0), (DISCARD, 0)]
        );
    }

    #[test]
    fn second_derivatives_go_to_both_blocks() {
        // (x1, x0), (x0, x0), (p1, x0), (p0, p1): the off-diagonal ones twice.
        let entries = [(1, 0), (0, 0), (3, 0), (4, 3)];
        let slots: [[Slot; 2]; 4] = second(&entries, COLUMNS);
        // Outputs: (x, x) = 0, (x, p) = 2, (p, x) = 10, (p, p) = 12 (five blocks a row).
        assert_eq!(slots[0], [(0, 1), (0, 2)]);
        assert_eq!(slots[1], [(0, 0), (DISCARD, 0)]);
        assert_eq!(slots[2], [(10, 0), (2, 0)]);
        // H(p0, p1) at (row 0, column 1) after H(p1, p0) at (row 1, column 0).
        assert_eq!(slots[3], [(12, 1), (12, 0)]);
        let transposed: [Slot; 2] = transposed(&[(1, 0), (0, 4)], COLUMNS);
        // Jᵀ of x (output 4): (x0, row 1); of p (output 14): (p0, row 0).
        assert_eq!(transposed, [(4, 0), (14, 0)]);
    }
}

//! CasADi's sparsity patterns: compressed column storage in one array of `casadi_int`,
//! `[nrow, ncol, colind[0..=ncol], row[0..nnz]]`, values stored column by column.

/// `casadi_int` as CasADi builds it (`long long int`).
pub type CasadiInt = i64;

/// A pattern, with its compressed form ready to hand out.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    pub nrow: usize,
    pub ncol: usize,
    /// `[nrow, ncol, colind…, row…]`.
    pub compressed: Vec<CasadiInt>,
}

impl Pattern {
    /// The entries (r, c) for which `nonzero(r, c)` holds.
    pub fn new(nrow: usize, ncol: usize, nonzero: impl Fn(usize, usize) -> bool) -> Pattern {
        let mut colind = Vec::with_capacity(ncol + 1);
        let mut rows = Vec::new();
        colind.push(0);
        for c in 0..ncol {
            rows.extend((0..nrow).filter(|&r| nonzero(r, c)).map(|r| r as CasadiInt));
            colind.push(rows.len() as CasadiInt);
        }
        let mut compressed = vec![nrow as CasadiInt, ncol as CasadiInt];
        compressed.extend(colind);
        compressed.extend(rows);
        Pattern {
            nrow,
            ncol,
            compressed,
        }
    }

    pub fn dense(nrow: usize, ncol: usize) -> Pattern {
        Pattern::new(nrow, ncol, |_, _| true)
    }

    pub fn empty(nrow: usize, ncol: usize) -> Pattern {
        Pattern::new(nrow, ncol, |_, _| false)
    }

    /// The number of stored entries.
    pub fn nnz(&self) -> usize {
        self.compressed[2 + self.ncol] as usize
    }

    /// Where the entries of column `c` are stored: `start..end`.
    pub fn column(&self, c: usize) -> core::ops::Range<usize> {
        let colind = &self.compressed[2..3 + self.ncol];
        colind[c] as usize..colind[c + 1] as usize
    }

    /// The row of stored entry `k`.
    pub fn row(&self, k: usize) -> usize {
        self.compressed[3 + self.ncol + k] as usize
    }

    /// The transposed pattern.
    pub fn transposed(&self) -> Pattern {
        Pattern::new(self.ncol, self.nrow, |r, c| self.position(c, r).is_some())
    }

    /// Where entry (r, c) is stored, if it is.
    pub fn position(&self, r: usize, c: usize) -> Option<usize> {
        let range = self.column(c);
        let rows = &self.compressed[3 + self.ncol + range.start..3 + self.ncol + range.end];
        rows.binary_search(&(r as CasadiInt))
            .ok()
            .map(|k| range.start + k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compressed_column_storage() {
        // [[1, 0], [1, 1], [0, 1]]
        let p = Pattern::new(3, 2, |r, c| (c == 0 && r < 2) || (c == 1 && r > 0));
        assert_eq!(p.compressed, vec![3, 2, 0, 2, 4, 0, 1, 1, 2]);
        assert_eq!(p.nnz(), 4);
        assert_eq!(p.position(1, 1), Some(2));
        assert_eq!(p.position(2, 0), None);
        assert_eq!(Pattern::dense(2, 1).compressed, vec![2, 1, 0, 2, 0, 1]);
        assert_eq!(Pattern::empty(2, 2).compressed, vec![2, 2, 0, 0, 0]);
    }
}

//! Generic points: values of every graph input (coordinates, parameters, velocity symbols)
//! at which a property of the model that should hold for every q, or fail for every q, is
//! checked numerically. Pseudo-random in [0.3, 1.3], away from the special values (0, 1,
//! π/2) where identities happen to hold; the same every build, so that a verdict does not
//! change from one build to the next.

/// `count` points of `inputs` values each.
pub fn points(count: usize, inputs: usize) -> Vec<Vec<f64>> {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    (0..count)
        .map(|_| {
            (0..inputs)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    0.3 + (state >> 11) as f64 / (1u64 << 53) as f64
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn points_are_in_range_and_distinct() {
        let p = super::points(3, 4);
        assert_eq!(p.len(), 3);
        for point in &p {
            assert!(point.iter().all(|x| (0.3..1.3).contains(x)));
        }
        assert_ne!(p[0], p[1]);
    }
}

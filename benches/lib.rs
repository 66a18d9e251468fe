//! hamel's benchmarks (`cargo bench -p hamel-benches`): `rhs.rs` times the generated
//! right-hand side against a hand-written closed form, `expand.rs` the macro's expansion.

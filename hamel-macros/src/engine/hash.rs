//! The maps and sets of the macro, with rustc's own hash function (`rustc-hash`, Fx) instead
//! of std's SipHash: the keys are node ids, nodes and names the macro made itself, never input
//! chosen to collide, and SipHash was a sixth of the catalogue's expansion time (hash-consing
//! the graph's nodes, the emitter's and the differentiation's node maps). Iteration order is
//! never relied on (std's was random per process).

pub type HashMap<K, V> = rustc_hash::FxHashMap<K, V>;
pub type HashSet<T> = rustc_hash::FxHashSet<T>;

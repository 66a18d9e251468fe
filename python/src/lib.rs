//! `hamel._native`, the extension module of the wheel: the catalogue's models, each one line
//! of `hamel_python::export_models!`. The N-trailer of 24 trailers is left out (its build
//! costs more than the other models together, and a user compiles it with `hamel.compile`).

use hamel::models::{
    BallOnTurntable, ChaplyginBall, ChaplyginSleigh, ContactOscillator, KnifeEdge, MobileRobot,
    MobileRobotPaper, NTrailer1, NTrailer2, NTrailer8, Rattleback, RollingDisk, VerticalDisk,
    WhippleBicycle,
};

hamel_python::export_models!(
    _native: MobileRobot,
    MobileRobotPaper,
    WhippleBicycle,
    ChaplyginSleigh,
    RollingDisk,
    ChaplyginBall,
    Rattleback,
    KnifeEdge,
    VerticalDisk,
    BallOnTurntable,
    ContactOscillator,
    NTrailer1,
    NTrailer2,
    NTrailer8;
    functions(rust_sources)
);

/// The Rust sources `hamel.compile` builds against (see `build.rs`), and their hash.
#[pyo3::pyfunction]
fn rust_sources(py: pyo3::Python<'_>) -> (pyo3::Bound<'_, pyo3::types::PyBytes>, &'static str) {
    let bytes = include_bytes!(concat!(env!("OUT_DIR"), "/sources.bin"));
    (
        pyo3::types::PyBytes::new(py, bytes),
        include_str!(concat!(env!("OUT_DIR"), "/sources.hash")),
    )
}

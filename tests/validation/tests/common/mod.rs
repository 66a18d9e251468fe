//! References and helpers shared by several of the suite's modules: closed forms, models
//! written by hand, independent formulations, and the seeded random generator. The benchmarks
//! include some of these files on their own (`#[path]`), so none of them depends on another
//! except `same_system` on `xorshift`.

pub mod affine_multipliers;
pub mod disk_closed_forms;
pub mod planar_closed_forms;
pub mod robot_by_hand;
pub mod robot_closed_form;
pub mod robot_projected_lagrange;
pub mod same_system;
pub mod stiff_problems;
pub mod whipple_by_hand;
pub mod xorshift;

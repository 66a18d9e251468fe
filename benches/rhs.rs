//! The generated right-hand side of the paper's robot against a hand-written closed form of
//! the same equations, in one run: (a) generated with the inverse B given (the paper's input
//! form), (b) generated with B obtained numerically (the everyday form), (c) by hand.
//! Each iteration evaluates the same 64 seeded random states and inputs. Criterion's figures
//! show trends; the figures of record are `speed.rs`'s, measured interleaved.

use criterion::{Criterion, criterion_group, criterion_main};
use hamel::HamelSystem;
use hamel::models::{MobileRobot, MobileRobotPaper};
use hamel_benches::robot_samples;
use std::hint::black_box;

#[path = "../tests/validation/tests/common/robot_closed_form.rs"]
mod closed_form;

fn robot_rhs(c: &mut Criterion) {
    let everyday = MobileRobot::default();
    let paper = MobileRobotPaper::from(&everyday);
    let inputs = robot_samples();
    let mut group = c.benchmark_group("robot_rhs_64_states");
    group.bench_function("c_hand_written_closed_form", |b| {
        b.iter(|| {
            let mut dx = [0.0; 8];
            for (x, u) in &inputs {
                closed_form::robot_rhs(&everyday, black_box(x), black_box(u), &mut dx);
                black_box(&dx);
            }
        })
    });
    group.bench_function("a_generated_inverse_given", |b| {
        b.iter(|| {
            let mut dx = [0.0; 8];
            for (x, u) in &inputs {
                let ok = paper.rhs(0.0, black_box(x), black_box(u), &mut dx).is_ok();
                black_box((ok, &dx));
            }
        })
    });
    group.bench_function("b_generated_inverse_numeric", |b| {
        b.iter(|| {
            let mut dx = [0.0; 8];
            for (x, u) in &inputs {
                let ok = everyday
                    .rhs(0.0, black_box(x), black_box(u), &mut dx)
                    .is_ok();
                black_box((ok, &dx));
            }
        })
    });
    group.finish();
}

criterion_group!(benches, robot_rhs);
criterion_main!(benches);

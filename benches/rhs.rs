//! The generated right-hand side of the paper's robot against a hand-written closed form of
//! the same equations, in one run: (a) generated with the inverse B given (the paper's input
//! form), (b) generated with B obtained numerically (the everyday form), (c) by hand.
//! Each iteration evaluates the same 64 seeded random states and inputs.

use criterion::{Criterion, criterion_group, criterion_main};
use hamel::HamelSystem;
use hamel::models::{MobileRobot, MobileRobotPaper};
use std::hint::black_box;

#[path = "../validation/tests/common/robot_closed_form.rs"]
mod closed_form;

/// Seeded states and inputs (xorshift64*), the same in every run.
fn samples() -> Vec<([f64; 8], [f64; 2])> {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        let bits = s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        (bits as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    (0..64)
        .map(|_| {
            let mut x = [0.0; 8];
            for v in &mut x {
                *v = 3.0 * next();
            }
            (
                [x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]],
                [next(), next()],
            )
        })
        .collect()
}

fn robot_rhs(c: &mut Criterion) {
    let everyday = MobileRobot::default();
    let paper = MobileRobotPaper::from(&everyday);
    let inputs = samples();
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

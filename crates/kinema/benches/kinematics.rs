//! Forward kinematics and Jacobian benchmarks for every built-in robot, with
//! the [`k`](https://crates.io/crates/k) crate on the same chains for comparison.
//!
//! Run all of them:
//!
//! ```text
//! cargo bench -p kinema --bench kinematics
//! ```
//!
//! or only some (the argument is a regular expression on the benchmark id):
//!
//! ```text
//! cargo bench -p kinema --bench kinematics -- lbr-iiwa
//! cargo bench -p kinema --bench kinematics -- 'iiwa|panda'
//! cargo bench -p kinema --bench kinematics -- '^fk/'
//! ```
//!
//! Benchmark ids:
//!
//! * `fk/<robot>` — `Robot::fk` (checks q, computes the tool pose, flags limits).
//! * `jacobian/<robot>` — `kin::jacobian_into(q, Frame::Base, &mut buf)` into a
//!   preallocated `Matrix6xX`.
//! * `jacobian/rows/<robot>` — `kin::jacobian_rows_into(q, Frame::Base, &mut buf)`,
//!   row-major into a preallocated slice: the layout of a C or numpy array (the
//!   Python package's `jacob0`).
//! * `fk/k/<robot>` — k: `set_joint_positions_unchecked` + `update_transforms`
//!   (k's usual FK; computes and caches every node's world transform) and the
//!   end node's `world_transform()`.
//! * `fk/k-end/<robot>` — k: `set_joint_positions_unchecked` +
//!   `SerialChain::end_transform` (k's cheapest way to the end pose only).
//! * `jacobian/k/<robot>` — k: `set_joint_positions_unchecked` + `k::jacobian`.
//!
//! Every timed call takes the next of 1024 seeded random configurations (within
//! the joint limits), so branch predictors cannot learn one input. The k chain
//! is built from kinema's own model description (DH rows / general joints,
//! offsets, base, tool) and checked against kinema's FK and Jacobian at 100
//! random configurations per robot before anything is timed.
//!
//! `cargo test -p kinema --benches` runs every benchmark once (Criterion's
//! test mode), including the cross-checks.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use kinema::nalgebra::Matrix6xX;
use kinema::{Frame, Robot};

mod common;
use common::*;

// ---------------------------------------------------------------------------
// Benchmarks.
// ---------------------------------------------------------------------------

fn kinematics(c: &mut Criterion) {
    let robots: Vec<Robot> =
        kinema::builtin_names().map(|name| Robot::builtin(name).expect("built-in robot loads")).collect();
    assert!(!robots.is_empty());

    // Every k chain is verified before anything is timed.
    let chains: Vec<k::SerialChain<f64>> = robots
        .iter()
        .map(|robot| {
            let chain = k_chain(robot);
            cross_check(robot, &chain);
            chain
        })
        .collect();

    for (robot, chain) in robots.iter().zip(&chains) {
        let name = robot.name();
        let n = robot.dof();
        let cycle = Cycle::new(robot, 0x5EED_0001);
        let q_at = |i: usize| cycle.at(i);

        {
            let mut g = c.benchmark_group("fk");
            g.bench_function(name, |b| {
                let mut i = 0usize;
                b.iter(|| {
                    let q = black_box(q_at(i));
                    i = i.wrapping_add(1);
                    black_box(robot.fk(q))
                })
            });
            g.bench_function(format!("k/{name}"), |b| {
                let mut i = 0usize;
                b.iter(|| {
                    let q = black_box(q_at(i));
                    i = i.wrapping_add(1);
                    chain.set_joint_positions_unchecked(q);
                    let all = chain.update_transforms();
                    black_box(all.last().copied())
                })
            });
            g.bench_function(format!("k-end/{name}"), |b| {
                let mut i = 0usize;
                b.iter(|| {
                    let q = black_box(q_at(i));
                    i = i.wrapping_add(1);
                    chain.set_joint_positions_unchecked(q);
                    black_box(chain.end_transform())
                })
            });
            g.finish();
        }

        {
            let mut g = c.benchmark_group("jacobian");
            let mut buf = Matrix6xX::<f64>::zeros(n);
            g.bench_function(name, |b| {
                let mut i = 0usize;
                b.iter(|| {
                    let q = black_box(q_at(i));
                    i = i.wrapping_add(1);
                    black_box(kinema::kin::jacobian_into(robot, q, Frame::Base, black_box(&mut buf)))
                })
            });
            black_box(&buf);
            let mut rows = vec![0.0; 6 * n];
            g.bench_function(format!("rows/{name}"), |b| {
                let mut i = 0usize;
                b.iter(|| {
                    let q = black_box(q_at(i));
                    i = i.wrapping_add(1);
                    black_box(kinema::kin::jacobian_rows_into(robot, q, Frame::Base, black_box(&mut rows)))
                })
            });
            g.bench_function(format!("k/{name}"), |b| {
                let mut i = 0usize;
                b.iter(|| {
                    let q = black_box(q_at(i));
                    i = i.wrapping_add(1);
                    chain.set_joint_positions_unchecked(q);
                    black_box(k::jacobian(chain))
                })
            });
            g.finish();
        }
    }
}

criterion_group! {
    name = benches;
    config = per_call_criterion();
    targets = kinematics
}
criterion_main!(benches);

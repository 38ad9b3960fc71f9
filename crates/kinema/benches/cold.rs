//! One call at a time, starting with cold instruction caches: what a call
//! from Python (or from any large program) pays, which a loop over the same
//! call hides.
//!
//! ```text
//! cargo bench -p kinema --bench cold
//! cargo bench -p kinema --bench cold -- 'iiwa|panda'
//! ```
//!
//! In a loop, a kernel's code sits in the L1 instruction cache and the
//! decoded-op cache, and the branch predictors know its jumps. Called from
//! Python, each call starts after the interpreter has run its own code, so
//! the kernel's bytes are fetched again and every taken jump costs more. Code
//! size and the number of taken jumps then matter as much as the loop's
//! time (docs/internals.md, "The hot loops"; benchmarks/README.md, "Exact-length
//! walks, one function per shape").
//!
//! Each timed iteration here first runs 40 KB of straight-line additions
//! (more than the 32 KB L1 instruction cache and the op cache hold), then
//! reads the time-stamp counter between `lfence`s around exactly one call.
//! The same is done around an empty call just before, and its ticks are
//! subtracted, so the figure is the call's own cost. Each Criterion sample
//! is the mean of its calls after dropping the slowest 10 % (interrupts and
//! migrations, microseconds each), of both the calls and the empty calls. Ticks become nanoseconds
//! by a calibration against the monotonic clock at start-up (an invariant TSC,
//! which every x86-64 CPU of the last fifteen years has).
//!
//! Benchmark ids (`<robot>` is every built-in robot; each call takes the next
//! of 1024 seeded random configurations):
//!
//! * `cold/fk/<robot>`, `warm/fk/<robot>` — `kin::fk_matrix_into`, the pose as
//!   a row-major 4×4 (the Python package's `fkine`).
//! * `cold/jacobian/rows/<robot>`, `warm/jacobian/rows/<robot>` —
//!   `kin::jacobian_rows_into(q, Frame::Base, ..)` (the Python package's
//!   `jacob0`).
//! * `cold/fk/k-end/<robot>`, `cold/jacobian/k/<robot>` — the `k` crate's
//!   `SerialChain::end_transform` and `k::jacobian` on the same chain,
//!   measured the same way (the chain is checked equal to kinema's first).
//!
//! `warm/…` is the same one-call-at-a-time timing without the eviction, so
//! cold − warm is what the cold start costs. Only on x86-64; elsewhere the
//! benchmark prints that and exits.

#[cfg(target_arch = "x86_64")]
mod common;

#[cfg(target_arch = "x86_64")]
mod cold {
    use std::arch::x86_64::{_mm_lfence, _rdtsc};
    use std::hint::black_box;
    use std::time::{Duration, Instant};

    use criterion::Criterion;
    use kinema::{Frame, Robot};

    use super::common::*;

    /// 10 000 four-byte additions on four registers: 40 KB of code run once
    /// from top to bottom, which leaves none of the timed call's code in the
    /// L1 instruction cache or the op cache.
    #[inline(never)]
    fn evict_code_caches() {
        // SAFETY: the block only adds to r8–r11, which are declared clobbered;
        // it touches no memory and no stack.
        unsafe {
            std::arch::asm!(
                ".rept 2500",
                "add r8d, 1",
                "add r9d, 1",
                "add r10d, 1",
                "add r11d, 1",
                ".endr",
                out("r8") _, out("r9") _, out("r10") _, out("r11") _,
                options(nostack, nomem)
            );
        }
    }

    /// Time-stamp counter ticks taken by one call of `f`, fenced so that the
    /// reads neither start early nor let the call's work leak past them.
    #[inline(always)]
    fn ticks(f: &mut impl FnMut()) -> u64 {
        // SAFETY: `lfence` and `rdtsc` are part of the x86-64 baseline.
        unsafe {
            _mm_lfence();
            let t0 = _rdtsc();
            _mm_lfence();
            f();
            _mm_lfence();
            let t1 = _rdtsc();
            t1.wrapping_sub(t0)
        }
    }

    /// TSC ticks per nanosecond, against the monotonic clock over 100 ms.
    fn ticks_per_ns() -> f64 {
        // SAFETY: as in `ticks`.
        let (t0, c0) = (Instant::now(), unsafe { _rdtsc() });
        while t0.elapsed() < Duration::from_millis(100) {}
        // SAFETY: as above.
        let (ns, c1) = (t0.elapsed().as_nanos(), unsafe { _rdtsc() });
        (c1.wrapping_sub(c0)) as f64 / ns as f64
    }

    /// Mean of the fastest 90 % of `ticks`: drops the calls that an
    /// interrupt, a migration or a page fault hit (one of those costs
    /// microseconds and would swamp a sample of 70 ns calls).
    fn trimmed_mean(ticks: &mut [u64]) -> f64 {
        ticks.sort_unstable();
        let keep = &ticks[..(ticks.len() * 9).div_ceil(10)];
        keep.iter().sum::<u64>() as f64 / keep.len() as f64
    }

    /// `iters` single calls of `call(i)` (i = 0, 1, …), each after an empty
    /// call, both preceded by the eviction when `cold`. Returns `iters` times
    /// the calls' trimmed mean less the empty calls' trimmed mean.
    fn one_at_a_time(iters: u64, cold: bool, per_ns: f64, mut call: impl FnMut(usize)) -> Duration {
        let iters = iters as usize;
        if iters == 0 {
            return Duration::ZERO;
        }
        let (mut empty, mut full) = (Vec::with_capacity(iters), Vec::with_capacity(iters));
        for i in 0..iters {
            if cold {
                evict_code_caches();
            }
            empty.push(ticks(&mut || black_box(())));
            if cold {
                evict_code_caches();
            }
            full.push(ticks(&mut || call(i)));
        }
        let per_call = (trimmed_mean(&mut full) - trimmed_mean(&mut empty)).max(0.0) / per_ns;
        Duration::from_secs_f64(per_call * iters as f64 * 1e-9)
    }

    pub fn benches(c: &mut Criterion) {
        let per_ns = ticks_per_ns();
        assert!(per_ns.is_finite() && per_ns > 0.1, "time-stamp counter calibration gave {per_ns} ticks/ns");
        for name in kinema::builtin_names() {
            let robot = Robot::builtin(name).expect("built-in robot loads");
            let chain = k_chain(&robot);
            cross_check(&robot, &chain);
            let n = robot.dof();
            let cycle = Cycle::new(&robot, 0x5EED_0002);
            let q_at = |i: usize| black_box(cycle.at(i));
            let mut pose = [0.0; 16];
            let mut rows = vec![0.0; 6 * n];

            for (label, cold) in [("cold", true), ("warm", false)] {
                let mut g = c.benchmark_group(label);
                g.bench_function(format!("fk/{name}"), |b| {
                    b.iter_custom(|iters| {
                        one_at_a_time(iters, cold, per_ns, |i| {
                            black_box(kinema::kin::fk_matrix_into(&robot, q_at(i), black_box(&mut pose)).is_ok());
                        })
                    })
                });
                g.bench_function(format!("jacobian/rows/{name}"), |b| {
                    b.iter_custom(|iters| {
                        one_at_a_time(iters, cold, per_ns, |i| {
                            black_box(
                                kinema::kin::jacobian_rows_into(&robot, q_at(i), Frame::Base, black_box(&mut rows))
                                    .is_ok(),
                            );
                        })
                    })
                });
                if cold {
                    g.bench_function(format!("fk/k-end/{name}"), |b| {
                        b.iter_custom(|iters| {
                            one_at_a_time(iters, cold, per_ns, |i| {
                                chain.set_joint_positions_unchecked(q_at(i));
                                black_box(chain.end_transform());
                            })
                        })
                    });
                    g.bench_function(format!("jacobian/k/{name}"), |b| {
                        b.iter_custom(|iters| {
                            one_at_a_time(iters, cold, per_ns, |i| {
                                chain.set_joint_positions_unchecked(q_at(i));
                                black_box(k::jacobian(&chain));
                            })
                        })
                    });
                }
                g.finish();
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
fn main() {
    let mut c = common::per_call_criterion().configure_from_args();
    cold::benches(&mut c);
    c.final_summary();
}

#[cfg(not(target_arch = "x86_64"))]
fn main() {
    println!("the cold-call benchmark reads the x86-64 time-stamp counter; skipped on this architecture");
}

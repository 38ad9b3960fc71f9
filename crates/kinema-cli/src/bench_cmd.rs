//! `kinema bench`: FK, Jacobian and IK timings on this machine.

use std::time::Instant;

use anyhow::Result;
use clap::Args;
use kinema::nalgebra::Matrix6xX;
use kinema::{Frame, Pose, Robot};
use kinema_io::{BenchAnswer, IkBench};

use crate::stdout::outln;
use crate::{count, print_json, seed, RobotArg, MAX_CONFIGURATIONS};

#[derive(Args)]
pub struct BenchArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// Number of random configurations, 1000 to 10 000 000 (1 000 000 or more is meaningful).
    #[arg(long, default_value_t = 1_000_000, value_parser = count(1000, MAX_CONFIGURATIONS))]
    n: usize,
    /// Seed of the random configurations.
    #[arg(long, default_value_t = 1, value_parser = seed)]
    seed: u64,
    /// Also time numeric inverse kinematics on --ik-n reachable targets (FK of random
    /// within-limit configurations; tolerance 1e-6 m / 1e-6 rad; limits enforced).
    #[arg(long)]
    ik: bool,
    /// Number of inverse-kinematics targets for --ik, 1 to 1 000 000.
    #[arg(long, default_value_t = 10_000, value_parser = count(1, 1_000_000))]
    ik_n: usize,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

pub fn bench(a: BenchArgs) -> Result<()> {
    use rand::SeedableRng;
    let r = a.robot.load()?;
    let n = r.dof();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(a.seed);
    let mut qs = vec![0.0; a.n * n];
    for q in qs.chunks_exact_mut(n) {
        r.random_q_into(&mut rng, q);
    }
    const BATCH: usize = 1000;
    let time_batches = |f: &mut dyn FnMut(&[f64])| -> Vec<f64> {
        // Warm-up on the first batches, then one sample per batch of calls.
        for q in qs.chunks_exact(n).take(10 * BATCH) {
            f(q);
        }
        let mut samples: Vec<f64> = qs
            .chunks(BATCH * n)
            .map(|batch| {
                let t = Instant::now();
                for q in batch.chunks_exact(n) {
                    f(q);
                }
                t.elapsed().as_nanos() as f64 / (batch.len() / n) as f64
            })
            .collect();
        samples.sort_by(f64::total_cmp);
        samples
    };
    let mut sink = 0.0;
    let fk = time_batches(&mut |q| {
        sink += std::hint::black_box(r.fk(std::hint::black_box(q)).map(|f| f.world_from_tool.pos.x).unwrap_or(0.0));
    });
    let mut jbuf = Matrix6xX::zeros(n);
    let jac = time_batches(&mut |q| {
        let _ = kinema::kin::jacobian_into(&r, std::hint::black_box(q), Frame::Base, &mut jbuf);
        sink += std::hint::black_box(jbuf[(0, 0)]);
    });
    let t = Instant::now();
    let batch = r.fk_batch(&qs)?;
    let batch_ns = t.elapsed().as_nanos() as f64 / a.n as f64;
    std::hint::black_box((sink, batch.len()));
    let pct = |s: &[f64], p: f64| s[((s.len() - 1) as f64 * p).round() as usize];
    let ik = if a.ik { Some(bench_ik(&r, a.ik_n, a.seed)?) } else { None };
    if a.json {
        return print_json(&BenchAnswer {
            robot: r.name().to_string(),
            dof: n,
            configurations: a.n,
            seed: a.seed,
            fk_ns: pct(&fk, 0.5),
            fk_ns_p10: pct(&fk, 0.1),
            fk_ns_p90: pct(&fk, 0.9),
            jacobian_ns: pct(&jac, 0.5),
            jacobian_ns_p10: pct(&jac, 0.1),
            jacobian_ns_p90: pct(&jac, 0.9),
            fk_batch_ns_per_config: batch_ns,
            threads: rayon::current_num_threads(),
            ik,
        });
    }
    outln!("robot {} ({} DOF), {} random configurations, seed {}", r.name(), n, a.n, a.seed)?;
    outln!("fk        median {:>8.1} ns/call  (p10 {:.1}, p90 {:.1})", pct(&fk, 0.5), pct(&fk, 0.1), pct(&fk, 0.9))?;
    outln!("jacobian  median {:>8.1} ns/call  (p10 {:.1}, p90 {:.1})", pct(&jac, 0.5), pct(&jac, 0.1), pct(&jac, 0.9))?;
    outln!("fk batch         {:>8.1} ns/config on {} threads", batch_ns, rayon::current_num_threads())?;
    if let Some(ik) = ik {
        outln!(
            "numeric ik       {} targets: success {:.3} %, mean {:.1} µs, median {:.1} µs, mean {:.1} iterations, {} restarts in all",
            ik.targets, ik.success_rate * 100.0, ik.mean_us, ik.median_us, ik.mean_iterations, ik.restarts
        )?;
    }
    Ok(())
}

/// Times the numeric IK solver on `count` reachable targets: FK of random
/// within-limit configurations (seed `seed + 1`), default options (tolerance
/// 1e-6 m / 1e-6 rad, limits enforced, seeded restarts), started from `home`.
fn bench_ik(r: &Robot, count: usize, seed: u64) -> Result<IkBench> {
    use kinema::ik::{IkSolver, NumericIk};
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed.wrapping_add(1));
    let targets: Vec<Pose> =
        (0..count).map(|_| r.fk(&r.random_q(&mut rng)).map(|f| f.world_from_tool)).collect::<Result<_, _>>()?;
    let solver = NumericIk::new(r);
    let bar = indicatif::ProgressBar::new(count as u64);
    let (mut ok, mut iters, mut restarts) = (0usize, 0usize, 0usize);
    let mut times = Vec::with_capacity(count);
    for t in &targets {
        let start = Instant::now();
        let res = solver.solve(std::hint::black_box(t));
        times.push(start.elapsed().as_secs_f64() * 1e6);
        if let Ok(s) = res {
            let s = &s[0];
            if s.within_limits() && s.position_error <= 1e-6 && s.orientation_error <= 1e-6 {
                ok += 1;
            }
            if let Some(n) = s.numeric {
                iters += n.iterations;
                restarts += n.restarts;
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mean = times.iter().sum::<f64>() / count as f64;
    times.sort_by(f64::total_cmp);
    Ok(IkBench {
        targets: count,
        success_rate: ok as f64 / count as f64,
        mean_us: mean,
        median_us: times[count / 2],
        p99_us: times[(count * 99 / 100).min(count - 1)],
        mean_iterations: iters as f64 / ok.max(1) as f64,
        restarts,
    })
}

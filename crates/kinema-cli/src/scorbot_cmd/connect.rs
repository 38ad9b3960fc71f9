//! `kinema scorbot connect`: a session with the real arm's controller over
//! its serial line (or the simulator), sending a planned path or commands.

use super::*;

pub(super) fn connect(a: ConnectArgs) -> Result<()> {
    let secs = |v: f64, what: &str| -> Result<Duration> {
        if !(v.is_finite() && v > 0.0 && v <= 86_400.0) {
            bail!("{what} {v}: seconds, > 0");
        }
        Ok(Duration::from_secs_f64(v))
    };
    let reply_timeout = secs(a.timeout, "--timeout")?;
    let motion_timeout = secs(a.motion_timeout, "--motion-timeout")?;
    let robot = robot()?;
    let c = a.constants.load()?;
    // A dry run needs no controller.
    if let Action::Follow { path, deg, max_step, dry_run: true, .. } = &a.action {
        let points = read_path(path, *deg)?;
        let plan = follow::plan(&robot, &c, &points, &PlanOptions { max_step: *max_step, q0: None })?;
        return print_json(&FollowPlanAnswer {
            points: plan.points.len(),
            counts: plan.counts,
            branches: plan.branches,
        });
    }
    let mut arm = match (&a.port, &a.tcp) {
        (Some(p), _) => Client::open_serial(p)?,
        (None, Some(t)) => Client::connect_tcp(t, reply_timeout)?,
        (None, None) => bail!("give --port DEVICE or --tcp ADDRESS"),
    };
    arm.reply_timeout = reply_timeout;
    arm.motion_timeout = motion_timeout;
    match a.action {
        Action::Home => {
            arm.home()?;
            eprintln!("homed");
        }
        Action::Abort => {
            arm.abort()?;
            eprintln!("aborted");
        }
        Action::Move { q, deg, time } => {
            let q = robot.parse_q(&q, deg)?;
            let outside = limits_text(&robot, &q);
            if !outside.is_empty() {
                bail!("not sent: {}", outside.join("; "));
            }
            let counts = c.counts_rounded(&q)?;
            arm.defp("KMOVE")?;
            arm.set_joint_position("KMOVE", counts)?;
            arm.move_d("KMOVE", seconds_to_hundredths(time, "--time")?)?;
            eprintln!("moved to counts {counts:?}");
        }
        Action::Follow { path, deg, max_step, mode, time, dry_run: _ } => {
            let points = read_path(&path, deg)?;
            let plan = follow::plan(&robot, &c, &points, &PlanOptions { max_step, q0: None })?;
            let bar = indicatif::ProgressBar::new(plan.points.len() as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template("{msg} {bar:30} {pos}/{len} [{elapsed}]")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_message("sending");
            let mode = match mode {
                ModeArg::Vector => SendMode::Vector,
                ModeArg::Points => SendMode::Points,
            };
            let result = follow::execute(
                &mut arm,
                &plan,
                "KPATH",
                mode,
                seconds_to_hundredths(time, "--time")?,
                &mut |done, total| {
                    bar.set_length(total as u64);
                    bar.set_position(done as u64);
                },
            );
            bar.finish_and_clear();
            result?;
            eprintln!("followed {} points ({} given)", plan.points.len(), points.len());
        }
        Action::Where { json } => {
            arm.here("KHERE")?;
            let r = arm.listpv("KHERE")?;
            let q = c.angles(&r.counts.map(|v| v as f64))?;
            let p = robot.fk(&q)?.world_from_tool.pos;
            if json {
                return print_json(&WhereAnswer {
                    counts: r.counts,
                    q,
                    tool_position: [p.x, p.y, p.z],
                    controller_cartesian: r.cartesian,
                });
            }
            outln!("counts    {}", r.counts.map(|v| v.to_string()).join("  "))?;
            outln!("q         {} deg", q.map(|v| format!("{:.3}", v.to_degrees())).join("  "))?;
            outln!("tool      x {:.2}  y {:.2}  z {:.2} mm (this model)", p.x * 1e3, p.y * 1e3, p.z * 1e3)?;
            if let Some(x) = r.cartesian {
                outln!(
                    "controller X {:.1}  Y {:.1}  Z {:.1} mm  P {:.1}  R {:.1} deg",
                    x[0] as f64 / 10.0,
                    x[1] as f64 / 10.0,
                    x[2] as f64 / 10.0,
                    x[3] as f64 / 10.0,
                    x[4] as f64 / 10.0
                )?;
            }
        }
    }
    Ok(())
}

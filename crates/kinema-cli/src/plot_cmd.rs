//! `kinema plot …`: pictures (SVG or PNG by the output's extension).

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use kinema::nalgebra::Vector3;
use kinema::Robot;
use kinema_plot::{
    render, CartesianCurves, EllipsoidView, Format, IkErrorPlot, JointCurves, ManipulabilityCurve, Plot, Robot3d,
    RobotView, Section, SelfMotionView, ToolPath3d, TrackingPlot, WorkspaceCloud, WorkspaceOptions,
};

use crate::{lang_cmd, traj_cmd, write_atomically, QArg, RobotArg};

#[derive(Subcommand)]
pub enum PlotCmd {
    /// The robot at a configuration: side and top views (seed 000 Fig. 2), or --3d with the link frames.
    Robot {
        #[command(flatten)]
        robot: RobotArg,
        #[command(flatten)]
        q: QArg,
        /// An oblique 3D view with every link frame (seed 004 Fig. 5).
        #[arg(long = "3d")]
        three_d: bool,
        #[command(flatten)]
        out: OutArg,
    },
    /// The tool's workspace from random configurations: side section and top view, points and boundary.
    Workspace {
        #[command(flatten)]
        robot: RobotArg,
        /// Number of random configurations, 1 to 10 000 000.
        #[arg(long, default_value_t = 200_000, value_parser = crate::count(1, crate::MAX_CONFIGURATIONS))]
        samples: usize,
        /// Seed of the random configurations.
        #[arg(long, default_value_t = 1, value_parser = crate::seed)]
        seed: u64,
        /// Side panel: r–z section (default when joint 1 is revolute) or the x–z projection.
        #[arg(long, value_enum)]
        section: Option<SectionArg>,
        /// Cells per side of the grid that outlines the boundary, 10 to 1000.
        #[arg(long, default_value_t = 120, value_parser = crate::count(10, 1000))]
        grid: usize,
        #[command(flatten)]
        out: OutArg,
    },
    /// A trajectory (CSV from `kinema traj`/`kinema run`, or a program): joint, Cartesian, 3D path or manipulability curves.
    Traj {
        #[command(flatten)]
        robot: RobotArg,
        /// A trajectory CSV with columns t, q1..qn (and optionally qd1.., qdd1..).
        #[arg(long, required_unless_present = "program", conflicts_with = "program")]
        csv: Option<PathBuf>,
        /// A robot program to run (see docs/language.md).
        #[arg(long)]
        program: Option<PathBuf>,
        /// Sample period for --program [s].
        #[arg(long, default_value_t = 0.01)]
        dt: f64,
        /// What to draw.
        #[arg(long, value_enum, default_value = "joint")]
        kind: TrajKind,
        #[command(flatten)]
        out: OutArg,
    },
    /// Manipulability ellipsoids (translation at the tool over the robot, and rotation) at a configuration.
    Ellipsoid {
        #[command(flatten)]
        robot: RobotArg,
        #[command(flatten)]
        q: QArg,
        #[command(flatten)]
        out: OutArg,
    },
    /// The iiwa's self-motion through a configuration: elbow circle and joint values against ψ (seed 004 Fig. 7).
    Selfmotion {
        #[command(flatten)]
        robot: RobotArg,
        #[command(flatten)]
        q: QArg,
        /// Samples of the arm angle over a full turn, 1 to 100 000.
        #[arg(long, default_value_t = 360, value_parser = crate::count(1, 100_000))]
        steps: usize,
        #[command(flatten)]
        out: OutArg,
    },
    /// IK round-trip error per case over random configurations (seed 004 Fig. 6; the iiwa with each case's q3).
    IkError {
        #[command(flatten)]
        robot: RobotArg,
        /// Number of random configurations, 1 to 10 000 000.
        #[arg(long, default_value_t = 1000, value_parser = crate::count(1, crate::MAX_CONFIGURATIONS))]
        cases: usize,
        /// Seed of the random configurations.
        #[arg(long, default_value_t = 1, value_parser = crate::seed)]
        seed: u64,
        #[command(flatten)]
        out: OutArg,
    },
    /// Desired versus measured paths and the tracking error (seed 000 Fig. 5–6); CSV columns x,y,z in metres.
    Tracking {
        /// The desired path (a polyline).
        #[arg(long)]
        desired: PathBuf,
        /// One or more measured runs.
        #[arg(long, num_args = 1.., required = true)]
        measured: Vec<PathBuf>,
        #[command(flatten)]
        out: OutArg,
    },
}

#[derive(Clone, Copy, ValueEnum)]
pub enum SectionArg {
    /// Distance from the base z axis against height.
    Radial,
    /// Projection on the x–z plane.
    Xz,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum TrajKind {
    /// Joint positions, velocities and accelerations with the limits.
    Joint,
    /// Tool position, velocity and acceleration.
    Cartesian,
    /// The tool path in 3D with the robot at both ends.
    Path,
    /// Manipulability along the trajectory.
    Manipulability,
}

#[derive(Args)]
pub struct OutArg {
    /// The picture to write: .svg or .png.
    #[arg(long)]
    out: PathBuf,
    /// Width x height in pixels, each 100 to 10000 (default depends on the plot).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
}

impl OutArg {
    fn write(&self, plot: &impl Plot, default: (u32, u32)) -> Result<()> {
        let format = Format::from_path(&self.out)
            .with_context(|| format!("`{}`: the output must end in .svg or .png", self.out.display()))?;
        let size = self.size.unwrap_or(default);
        let bytes = render(plot, format, size)?;
        write_atomically(&self.out, |w| Ok(w.write_all(&bytes)?))?;
        eprintln!("wrote {} ({}×{})", self.out.display(), size.0, size.1);
        Ok(())
    }
}

/// WIDTHxHEIGHT, each side 100 to 10000 pixels (as `kinema_plot::render`
/// takes), checked before any sampling or solving starts.
fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let parse = |(w, h): (&str, &str)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?));
    let (w, h) = s
        .split_once(['x', 'X', '×'])
        .and_then(parse)
        .ok_or_else(|| format!("`{s}`: expected WIDTHxHEIGHT in pixels, e.g. 1200x800"))?;
    if !(100..=10_000).contains(&w) || !(100..=10_000).contains(&h) {
        return Err(format!("{w}×{h}: each side must be 100 to 10000 pixels"));
    }
    Ok((w, h))
}

/// A CSV file read into memory, positioned after its header.
type CsvReader = csv::Reader<std::io::Cursor<Vec<u8>>>;

/// A CSV file with a header line (at most [`crate::input::MAX_CSV_BYTES`],
/// cells trimmed, `#` lines skipped): the reader positioned at the first
/// record and the header's names. A first line with numbers in it is not
/// taken as the header: it is an error naming the line.
fn open_csv(path: &std::path::Path) -> Result<(CsvReader, Vec<String>)> {
    use crate::input::{first_row, read_limited, FirstRow, MAX_CSV_BYTES};
    let bytes = read_limited(path, MAX_CSV_BYTES, "CSV input")?;
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(std::io::Cursor::new(bytes));
    let mut head = csv::StringRecord::new();
    loop {
        if !rd.read_record(&mut head).with_context(|| format!("`{}`: not readable as CSV", path.display()))? {
            bail!("`{}`: no CSV header", path.display());
        }
        if !head.iter().all(str::is_empty) {
            break;
        }
    }
    let byte = head.position().map_or(0, |p| p.byte());
    let line = crate::input::LineCounter::new(rd.get_ref().get_ref()).line_at(byte);
    if first_row(head.iter(), path, line)? == FirstRow::Numbers {
        bail!(
            "`{}` line {line}: `{}` is numbers; the first line must be a header naming the columns",
            path.display(),
            head.iter().collect::<Vec<_>>().join(",")
        );
    }
    Ok((rd, head.iter().map(str::to_string).collect()))
}

fn read_points(path: &Path) -> Result<Vec<Vector3<f64>>> {
    let (mut rd, head) = open_csv(path)?;
    let cols: Option<Vec<usize>> = ["x", "y", "z"].iter().map(|c| head.iter().position(|h| h == c)).collect();
    let cols = cols
        .with_context(|| format!("`{}`: the header must name x, y, z (it has {})", path.display(), head.join(",")))?;
    let mut pts = Vec::new();
    for (i, rec) in rd.records().enumerate() {
        let rec = rec.with_context(|| format!("`{}`: not readable as CSV", path.display()))?;
        let mut p = Vector3::zeros();
        for (k, &c) in cols.iter().enumerate() {
            let cell = rec.get(c).unwrap_or("");
            p[k] = cell
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| format!("`{}` row {}: `{cell}` is not a finite number", path.display(), i + 2))?;
        }
        pts.push(p);
    }
    if pts.is_empty() {
        bail!("`{}`: no points", path.display());
    }
    Ok(pts)
}

pub fn plot(cmd: PlotCmd) -> Result<()> {
    match cmd {
        PlotCmd::Robot { robot, q, three_d, out } => {
            let r = robot.load()?;
            let q = r.parse_q(&q.q, q.deg)?;
            if three_d {
                out.write(&Robot3d::new(&r, &q)?, (900, 800))
            } else {
                out.write(&RobotView::new(&r, &q)?, (1100, 550))
            }
        }
        PlotCmd::Workspace { robot, samples, seed, section, grid, out } => {
            let r = robot.load()?;
            let section = section.map(|s| match s {
                SectionArg::Radial => Section::Radial,
                SectionArg::Xz => Section::Xz,
            });
            let bar = indicatif::ProgressBar::new(samples as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} configurations ({per_sec}, eta {eta})")
                    .expect("a valid template"),
            );
            let cloud = WorkspaceCloud::sample(&r, &WorkspaceOptions { samples, seed, section, grid }, |done| {
                bar.set_position(done as u64)
            });
            bar.finish_and_clear();
            out.write(&cloud?, (1200, 600))
        }
        PlotCmd::Traj { robot, csv, program, dt, kind, out } => {
            let (r, traj) = match (csv, program) {
                (Some(path), _) => {
                    let r = robot.load()?;
                    let (t, _) = traj_cmd::read_trajectory_with_resolution(&r, &path)?;
                    (r, t)
                }
                (None, Some(program)) => {
                    let plan = lang_cmd::build(&lang_cmd::ProgramArgs {
                        program,
                        robot,
                        dt,
                        start: None,
                        time_limit: lang_cmd::DEFAULT_TIME_LIMIT,
                        skip_unreachable: false,
                        body: Default::default(),
                    })?
                    .plan;
                    (plan.robot, plan.trajectory)
                }
                (None, None) => bail!("give --csv or --program"),
            };
            match kind {
                TrajKind::Joint => out.write(&JointCurves::new(&r, &traj)?, (1200, 900)),
                TrajKind::Cartesian => out.write(&CartesianCurves::new(&r, &traj)?, (1200, 900)),
                TrajKind::Path => out.write(&ToolPath3d::new(&r, &traj)?, (900, 800)),
                TrajKind::Manipulability => out.write(&ManipulabilityCurve::new(&r, &traj)?, (1200, 700)),
            }
        }
        PlotCmd::Ellipsoid { robot, q, out } => {
            let r = robot.load()?;
            let q = r.parse_q(&q.q, q.deg)?;
            out.write(&EllipsoidView::new(&r, &q)?, (1400, 700))
        }
        PlotCmd::Selfmotion { robot, q, steps, out } => {
            let r = robot.load()?;
            let q = r.parse_q(&q.q, q.deg)?;
            out.write(&SelfMotionView::new(&r, &q, steps)?, (1400, 700))
        }
        PlotCmd::IkError { robot, cases, seed, out } => {
            let r = robot.load()?;
            let plot = ik_error(&r, cases, seed)?;
            let (max, mean) = plot.max_mean();
            eprintln!("{cases} cases: max error {max:.3e}, mean {mean:.3e}");
            out.write(&plot, (1100, 600))
        }
        PlotCmd::Tracking { desired, measured, out } => {
            let d = read_points(&desired)?;
            let m = measured.iter().map(|p| read_points(p)).collect::<Result<Vec<_>>>()?;
            let plot = TrackingPlot::new(d, m)?;
            let (mean, sd) = plot.mean_error();
            eprintln!("tracking error {:.3} ± {:.3} mm", mean * 1e3, sd * 1e3);
            out.write(&plot, (1300, 600))
        }
    }
}

/// The iiwa's own validation (same q3 per case) when the robot has that
/// shape, else the analytic solver's round trip, else the numeric solver's.
fn ik_error(r: &Robot, cases: usize, seed: u64) -> Result<IkErrorPlot> {
    if kinema::ik::IiwaIk::new(r).is_ok() {
        return Ok(IkErrorPlot::iiwa(r, cases, seed)?);
    }
    let solver: Box<dyn kinema::ik::IkSolver> = match kinema::ik::analytic_solver(r) {
        Some(s) => s,
        None => Box::new(kinema::ik::NumericIk::new(r)),
    };
    Ok(IkErrorPlot::round_trip(r, solver.as_ref(), cases, seed)?)
}

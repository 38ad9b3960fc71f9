//! Seed 000's accuracy experiment (§IV-B, Fig. 5–6) run on the controller
//! simulator: a path (by default the square of Fig. 6 in the xz plane) is
//! planned with each model's encoder constants, sent through the ACL client
//! to the simulated controller, and the physical tool path the simulator
//! records is compared with the desired one.
//!
//! # What is simulated, and how
//!
//! * **The arm** moves by [`ExperimentOptions::truth`] (default: seed 000's
//!   calibrated Tabla II and measured Tabla III columns): for the counts it is
//!   sent, its joint angles are eq. 24 inverted with those constants, and the
//!   tool position is forward kinematics of the DH model of Tabla I.
//! * **A model** is a set of constants used to plan: the path is resampled to
//!   ≤ 1 cm steps ([`follow::SEED_MAX_STEP`]), solved with the seed's
//!   closed-form IK and converted to counts with eq. 24 ([`follow::plan`]),
//!   then sent as one vector and `MOVES` ([`follow::execute`]). Planned with
//!   the factory columns the arm misses the path by what separates the two
//!   tables; planned with the true constants it follows it up to the rounding
//!   to whole counts and the interpolation between points.
//! * **The measurement** (the seed's external camera): the simulator records
//!   the physical tool position every 10 ms of nominal motion time and adds
//!   Gaussian noise of standard deviation [`ExperimentOptions::noise`] to each
//!   coordinate, drawn from a ChaCha8 generator seeded with
//!   [`ExperimentOptions::seed`] (one generator for the whole session, so each
//!   run gets different noise). Only the samples of the path itself are kept:
//!   the arm is first moved to the path's start, and what is recorded from
//!   then to the end of the `MOVES` is one run.
//!
//! Everything is deterministic for given options: the motion is sampled in
//! nominal (not wall-clock) time.
//!
//! # Examples
//! ```no_run
//! use kinema::nalgebra::Vector3;
//! use kinema_scorbot::encoder::Constants;
//! use kinema_scorbot::experiment::{run, square, ExperimentOptions, Model, Plane};
//! let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
//! let path = square(Plane::Xz, Vector3::new(0.35, 0.0, 0.30), 0.10, 60f64.to_radians(), 0.0)?;
//! let options = ExperimentOptions {
//!     models: vec![Model::named("factory")?, Model::named("calibrated")?],
//!     ..ExperimentOptions::default()
//! };
//! let e = run(&robot, &path, &options)?;
//! assert!(e.models[0].report.mean_error > e.models[1].report.mean_error);
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```

use std::fmt;
use std::str::FromStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use kinema::nalgebra::Vector3;
use kinema::Robot;

use crate::acl::Client;
use crate::encoder::Constants;
use crate::error::{Error, Result};
use crate::follow::{self, PathPoint, PlanOptions, SendMode, SEED_MAX_STEP};
use crate::metrics::{self, TrackOptions, TrackingReport};
use crate::sim::{self, SimConfig};

/// A coordinate plane of the robot's world frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    /// Horizontal: x and y vary, z is fixed.
    Xy,
    /// Vertical, through the base axis when y = 0 (seed 000 Fig. 6): x and z vary.
    Xz,
    /// Vertical, across the arm when it points along x: y and z vary.
    Yz,
}

impl Plane {
    /// The indices of the two coordinates that vary in this plane.
    fn axes(self) -> (usize, usize) {
        match self {
            Plane::Xy => (0, 1),
            Plane::Xz => (0, 2),
            Plane::Yz => (1, 2),
        }
    }
}

impl fmt::Display for Plane {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Plane::Xy => "xy",
            Plane::Xz => "xz",
            Plane::Yz => "yz",
        })
    }
}

impl FromStr for Plane {
    type Err = Error;
    fn from_str(s: &str) -> Result<Plane> {
        match s.to_ascii_lowercase().as_str() {
            "xy" | "yx" => Ok(Plane::Xy),
            "xz" | "zx" => Ok(Plane::Xz),
            "yz" | "zy" => Ok(Plane::Yz),
            _ => Err(Error::UnknownName { what: "plane".into(), name: s.into(), known: "xy, xz, yz".into() }),
        }
    }
}

/// A closed square of side `side` \[m\] in `plane`, centred at `center` \[m\],
/// as its five corners (the first repeated at the end): starting at the
/// corner where both varying coordinates are smallest and going first along
/// the plane's first axis. Every point has the same `pitch` and `roll`
/// \[rad\] (seed 000 eq. 13).
///
/// Errors: a side that is not finite and positive, a non-finite value.
///
/// # Examples
/// ```
/// use kinema::nalgebra::Vector3;
/// use kinema_scorbot::experiment::{square, Plane};
/// let sq = square(Plane::Xz, Vector3::new(0.35, 0.0, 0.30), 0.10, 1.0, 0.0)?;
/// assert_eq!(sq.len(), 5);
/// assert!(sq.iter().all(|p| p.position.y == 0.0)); // y is fixed in the xz plane
/// assert!((sq[2].position - Vector3::new(0.40, 0.0, 0.35)).norm() < 1e-12);
/// # Ok::<(), kinema_scorbot::Error>(())
/// ```
pub fn square(plane: Plane, center: Vector3<f64>, side: f64, pitch: f64, roll: f64) -> Result<Vec<PathPoint>> {
    if !(side.is_finite() && side > 0.0) {
        return Err(Error::out_of_range("side", side, "a finite, positive length [m]"));
    }
    let values =
        [("centre x", center.x), ("centre y", center.y), ("centre z", center.z), ("pitch", pitch), ("roll", roll)];
    if let Some((what, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
        return Err(Error::not_finite(*what, *v));
    }
    let h = side / 2.0;
    let (a, b) = plane.axes();
    let corners = [(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)];
    Ok(corners
        .iter()
        .map(|&(u, v)| {
            let mut p = center;
            p[a] += u;
            p[b] += v;
            PathPoint::new(p, pitch, roll)
        })
        .collect())
}

/// Encoder constants used to plan, with a label for reports and file names.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// A short name (`factory`, `calibrated`, a file stem …).
    pub label: String,
    /// The constants the path is planned with.
    pub constants: Constants,
}

impl Model {
    /// A preset of [`Constants::named`], labelled with its name.
    pub fn named(name: &str) -> Result<Model> {
        Ok(Model { label: name.to_string(), constants: Constants::named(name)? })
    }
}

/// Options of [`run`].
#[derive(Debug, Clone, PartialEq)]
pub struct ExperimentOptions {
    /// The models to compare, each followed [`ExperimentOptions::runs`] times.
    pub models: Vec<Model>,
    /// The constants stored in the simulated controller (its joint-limit
    /// check and motor speeds). Default: factory.
    pub controller: Constants,
    /// The constants the simulated arm really moves by. Default: seed 000's
    /// calibrated counts per degree and measured home offsets.
    pub truth: Constants,
    /// Repetitions of the path per model (seed 000 Fig. 6: two). At least 1.
    pub runs: usize,
    /// Standard deviation of the measurement noise per coordinate \[m\]
    /// (default 1 mm, the precision the seed quotes for its camera system).
    pub noise: f64,
    /// Seed of the measurement noise.
    pub seed: u64,
    /// Largest step between the points sent \[m\] (seed 000: 1 cm).
    pub max_step: f64,
    /// Factor applied to the simulator's motion durations (results do not
    /// depend on it; smaller is faster). Default 0.001.
    pub time_scale: f64,
}

impl Default for ExperimentOptions {
    fn default() -> Self {
        let sim = SimConfig::default();
        ExperimentOptions {
            models: Vec::new(),
            controller: sim.constants,
            truth: sim.true_constants,
            runs: 2,
            noise: 0.001,
            seed: 0,
            max_step: SEED_MAX_STEP,
            time_scale: 0.001,
        }
    }
}

/// The runs of one model and their tracking figures.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelRuns {
    /// The model's label.
    pub label: String,
    /// The IK branch of the first point of the plan.
    pub branch: String,
    /// Each run's recorded tool positions (with the measurement noise) \[m\].
    pub runs: Vec<Vec<Vector3<f64>>>,
    /// Seed 000's mean error and the ISO 9283 figures of these runs
    /// against [`Experiment::desired`].
    pub report: TrackingReport,
}

/// The result of [`run`].
#[derive(Debug, Clone, PartialEq)]
pub struct Experiment {
    /// The desired path as sent: the given path resampled to ≤ `max_step` \[m\].
    pub desired: Vec<Vector3<f64>>,
    /// One entry per model, in the order given.
    pub models: Vec<ModelRuns>,
}

/// The simulator on a loopback port, stopped when dropped.
struct Server {
    addr: String,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<Result<()>>>,
}

impl Server {
    fn start(config: SimConfig) -> Result<Server> {
        let listener = std::net::TcpListener::bind("127.0.0.1:0")
            .map_err(|e| Error::io("simulator: cannot listen on 127.0.0.1", e))?;
        let addr = listener.local_addr().map_err(|e| Error::io("simulator: no local address", e))?.to_string();
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let thread = std::thread::spawn(move || sim::serve_tcp(listener, config, s));
        Ok(Server { addr, stop, thread: Some(thread) })
    }

    /// Stops the server and returns its error, if it had one.
    fn finish(mut self) -> Result<()> {
        self.stop.store(true, Ordering::SeqCst);
        match self.thread.take().map(|t| t.join()) {
            Some(Ok(r)) => r,
            Some(Err(_)) => Err(Error::SimulatorPanicked),
            None => Ok(()),
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Runs the experiment: starts the simulator on a loopback TCP port with a
/// recording in a temporary directory, homes the arm, and for each model
/// plans `path` and follows it [`ExperimentOptions::runs`] times (each run
/// starts with a move to the path's first point, which is not part of the
/// run). See the module documentation for what is simulated.
///
/// Errors: no model, `runs` = 0, a noise or time scale out of range, a path
/// point without a solution within the joint limits, or any error of the
/// simulator or the client.
pub fn run(robot: &Robot, path: &[PathPoint], options: &ExperimentOptions) -> Result<Experiment> {
    if options.models.is_empty() {
        return Err(Error::too_few("models", 0, 1, "models"));
    }
    if options.runs == 0 || options.runs > 1000 {
        return Err(Error::out_of_range("runs", options.runs as f64, "1 to 1000"));
    }
    if !(options.time_scale.is_finite() && options.time_scale > 0.0 && options.time_scale <= 1.0) {
        return Err(Error::out_of_range("time scale", options.time_scale, "a number > 0 and ≤ 1"));
    }
    let desired: Vec<Vector3<f64>> = follow::resample(path, options.max_step)?.iter().map(|p| p.position).collect();
    let plan_options = PlanOptions { max_step: options.max_step, q0: None };
    let plans = options
        .models
        .iter()
        .map(|m| {
            follow::plan(robot, &m.constants, path, &plan_options)
                .map_err(|e| Error::ForModel { label: m.label.clone(), source: Box::new(e) })
        })
        .collect::<Result<Vec<_>>>()?;

    let dir = tempfile::Builder::new()
        .prefix("kinema-scorbot-experiment-")
        .tempdir()
        .map_err(|e| Error::io("cannot create a temporary directory", e))?;
    let record = dir.path().join("record.csv");
    let server = Server::start(SimConfig {
        constants: options.controller.clone(),
        true_constants: options.truth.clone(),
        time_scale: options.time_scale,
        faults: Vec::new(),
        record: Some(record.clone()),
        noise: options.noise,
        seed: options.seed,
    })?;
    let mut client = Client::connect_tcp(&server.addr, Duration::from_secs(5))?;
    client.reply_timeout = Duration::from_secs(5);
    client.motion_timeout = Duration::from_secs(600);
    client.home()?;
    let mut models = Vec::with_capacity(plans.len());
    for (model, plan) in options.models.iter().zip(&plans) {
        let mut runs = Vec::with_capacity(options.runs);
        for _ in 0..options.runs {
            client.defp("KSTART")?;
            client.set_joint_position("KSTART", plan.counts[0])?;
            client.move_d("KSTART", None)?;
            let before = recorded(&record)?.len();
            follow::execute(&mut client, plan, "KPATH", SendMode::Vector, None, &mut |_, _| {})?;
            runs.push(recorded(&record)?.split_off(before));
        }
        let report = metrics::track(&desired, &runs, &TrackOptions::default())?;
        models.push(ModelRuns { label: model.label.clone(), branch: plan.branches[0].clone(), runs, report });
    }
    drop(client);
    server.finish()?;
    Ok(Experiment { desired, models })
}

/// The rows recorded so far.
fn recorded(path: &std::path::Path) -> Result<Vec<Vector3<f64>>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(format!("cannot read `{}`", path.display()), e))?;
    metrics::parse_points_csv(&text, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squares_lie_in_their_plane_with_the_given_side() {
        let c = Vector3::new(0.3, 0.1, 0.4);
        for (plane, fixed) in [(Plane::Xy, 2), (Plane::Xz, 1), (Plane::Yz, 0)] {
            let sq = square(plane, c, 0.2, 0.5, -0.25).unwrap();
            assert_eq!(sq.len(), 5);
            assert_eq!(sq[0], sq[4]);
            for w in sq.windows(2) {
                assert!(((w[1].position - w[0].position).norm() - 0.2).abs() < 1e-12);
            }
            assert!(sq.iter().all(|p| p.position[fixed] == c[fixed] && p.pitch == 0.5 && p.roll == -0.25));
            let mean = sq[..4].iter().map(|p| p.position).sum::<Vector3<f64>>() / 4.0;
            assert!((mean - c).norm() < 1e-12);
            assert_eq!(plane.to_string().parse::<Plane>().unwrap(), plane);
        }
        assert!("xw".parse::<Plane>().is_err());
        assert!(square(Plane::Xz, c, 0.0, 0.0, 0.0).is_err());
        assert!(square(Plane::Xz, c, f64::NAN, 0.0, 0.0).is_err());
    }

    #[test]
    fn the_xz_square_separates_the_factory_model_from_the_true_one() {
        let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let path = square(Plane::Xz, Vector3::new(0.35, 0.0, 0.30), 0.10, 60f64.to_radians(), 0.0).unwrap();
        let options = ExperimentOptions {
            models: vec![Model::named("factory").unwrap(), Model::named("calibrated").unwrap()],
            noise: 0.0,
            runs: 1,
            ..ExperimentOptions::default()
        };
        let e = run(&robot, &path, &options).unwrap();
        assert_eq!(e.desired.len(), 41);
        let (factory, truth) = (&e.models[0], &e.models[1]);
        // Every recorded point lies near the xz plane for the true model.
        assert!(truth.runs[0].iter().all(|p| p.y.abs() < 1e-3), "{:?}", truth.runs[0]);
        assert!(truth.report.mean_error < 0.3e-3, "{:?}", truth.report);
        assert!(factory.report.mean_error > 5e-3, "{:?}", factory.report);
        // Without noise the runs of one model repeat exactly.
        let again = run(&robot, &path, &ExperimentOptions { runs: 2, ..options }).unwrap();
        assert_eq!(again.models[0].runs[0], again.models[0].runs[1]);
        assert_eq!(again.models[0].runs[0], factory.runs[0]);
    }
}

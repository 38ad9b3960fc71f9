//! Analytic inverse kinematics of the KUKA LBR iiwa 14 R820 and of any 7R
//! arm of the same shape (an "SRS" arm: spherical shoulder, revolute elbow,
//! spherical wrist), after seed 004 §V.
//!
//! The arm is described by a standard DH table with all a = 0, twists
//! α = −90°, 90°, −90°, 90°, −90°, 90°, 0°, d2 = d4 = d6 = 0 and zero joint
//! offsets. Only four lengths matter: d1 (base–shoulder), d3
//! (shoulder–elbow), d5 (elbow–wrist) and d7 (wrist–flange). The base and
//! tool transforms of the [`Robot`] are stripped from every target.
//!
//! Geometry used throughout (derived here, it is the basis of all formulas):
//! with this DH table, Rx(−90°)·Rz(θ)·Rx(90°) = Ry(θ), so
//!
//! ```text
//! R₀₃·Rx(90°) = Rz(q1)·Ry(q2)·Rz(q3)     R₀₄ = Rz(q1)·Ry(q2)·Rz(q3)·Ry(q4)
//! R₄₇ = Rz(q5)·Ry(q6)·Rz(q7)             (two ZYZ Euler triples)
//! W − S = Rz(q1)·Ry(q2)·(d5·c3·s4, d5·s3·s4, d3 + d5·c4)
//! ```
//!
//! with S = (0, 0, d1) the shoulder, E = S + d3·R₀₂·ẑ the elbow and
//! W = p − d7·R₀₇·ẑ the wrist point.
//!
//! The formulas of both forms live in the SRS kernel shared with
//! [`SrsIk`](crate::ik::geo::SrsIk) (`ik/families/geo/srs_kernel.rs`),
//! built here from d3 and d5 in frame 0 with the shoulder as origin, where
//! they reduce to seed 004's; this type reads and checks the DH table,
//! strips base, tool and d1, d7, and keeps the labels, errors and the
//! selection and search over the self-motion.
//!
//! Two parameterisations of the one-dimensional self-motion are offered:
//!
//! * **q3 fixed** (seed 004 eq. 3–11, [`IiwaIk::solve_q3`]): up to 8
//!   solutions for a given q3; this is the paper's method, and the
//!   [`IkSolver`](crate::ik::IkSolver) implementation uses it with q3 = 0 by default
//!   ([`IiwaIk::with_q3`]).
//! * **arm angle ψ** (Shimizu et al. 2008; Faria et al. 2018,
//!   [`IiwaIk::solve_psi`]): the rotation of the shoulder–elbow–wrist plane
//!   about the shoulder–wrist line, measured from the reference plane of the
//!   arm with q3 = 0; with the three configuration bits it determines one
//!   solution.
//!
//! Without a previous configuration, [`IiwaIk::solve_searching`] takes the
//! closed form at a preferred q3 when it has a solution within limits and
//! otherwise searches ψ over the whole self-motion; [`IiwaIk::select`] falls
//! back to the same search when its q3 window has none.
//!
//! # Configuration bits
//!
//! A configuration is labelled by three bits ([`SHOULDER`], [`ELBOW`],
//! [`WRIST`]); a bit is set when q2, q4 or q6 respectively is negative (the
//! GC2, GC4, GC6 of Shimizu and Faria). Labels read
//! `shoulder+/elbow-/wrist+` (+ = bit clear, joint ≥ 0). These bits are
//! constant along the ψ self-motion. For a fixed q3 the 8 solutions come as
//! 2 elbows × 2 shoulders × 2 wrists; the elbow and wrist pairs always differ
//! in the sign of q4 and q6, but the two shoulder solutions often have the
//! same sign of q2 (the sign of q2 flips under the ψ shoulder flip
//! (q1, q2, q3) → (q1 + π, −q2, q3 + π), which changes q3). Labels of
//! fixed-q3 solutions therefore carry the bits of the solution itself, as
//! [`IiwaIk::config_of`] computes them, plus `/front` or `/back`: whether
//! the wrist point lies in front of or behind the shoulder along the x axis
//! of DH frame 1 — the fixed-q3 shoulder choice, which makes the 8 labels
//! distinct, e.g. `shoulder+/elbow-/wrist+/back`.
//!
//! # Singular cases (conventions, never NaN)
//!
//! * Wrist singularity (|sin q6| < 1e-12): q5 and q7 turn about one axis;
//!   q5 = 0 and q7 takes the sum.
//! * Shoulder singularity (wrist point on the axis of joint 1 with the arm
//!   plane containing it): q1 = 0 (or the previous q1 in
//!   [`IiwaIk::select`]) and q2, q3 follow; in the ψ form, when
//!   |sin q2| < 1e-12, q1 = 0 and q3 takes the sum.
//! * Stretched or folded elbow (sin q4 = 0): both elbow solutions coincide
//!   and are returned once.
//! * Arm-angle reference: when the wrist point is on the axis of joint 1,
//!   the reference plane is undefined; q1 = 0 is used for it (ψ jumps there —
//!   the algorithmic singularity of the arm-angle method).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::{Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::analysis::{manipulability_along, Axes};
use crate::error::{Error, InputError, Result};
use crate::ik::family::{Choice, Redundancy, SelfMotionParameter};
use crate::ik::geo::srs_kernel::{Miss, Options, Solutions, SrsKernel};
use crate::ik::{check_target, joint_distance, wrap_angle, Candidates, Solution, Unreachable};
use crate::kin::Frame;
use crate::math::FastMath;
use crate::math::{rot_y, rot_z, Pose};
use crate::model::{DhConvention, JointType, LinkGeometry};
use crate::robot::Robot;

mod psi_search;
mod redundancy;
mod select;
mod validation;

pub use validation::{ValidationCase, ValidationReport};

/// Configuration bit: set when q2 < 0 (shoulder).
pub const SHOULDER: u8 = 1;
/// Configuration bit: set when q4 < 0 (elbow).
pub const ELBOW: u8 = 2;
/// Configuration bit: set when q6 < 0 (wrist).
pub const WRIST: u8 = 4;

/// Half-width \[rad\] of the q3 window searched by [`IiwaIk::select`] around the previous q3.
pub const SELECT_WINDOW: f64 = 0.05;
/// Step \[rad\] of the q3 grid searched by [`IiwaIk::select`] (21 values over the window: the window / 10).
pub const SELECT_STEP: f64 = 0.005;
/// Largest joint change \[rad\] per call that [`IiwaIk::select`] prefers; candidates
/// that change any joint more are used only if there is no other.
pub const SELECT_MAX_STEP: f64 = 0.05;
/// Number of ψ samples over (−π, π] used by [`IiwaIk::feasible_psi_intervals`].
pub const PSI_SAMPLES: usize = 2048;
/// Width \[rad\] to which [`IiwaIk::feasible_psi_intervals`] refines interval ends.
pub const PSI_TOLERANCE: f64 = 1e-9;
/// Arm-angle samples per configuration in the search of [`IiwaIk::solve_searching`].
pub const SEARCH_SAMPLES: usize = 96;
/// Local maxima of the limit margin refined per configuration by [`IiwaIk::solve_searching`].
pub const SEARCH_PEAKS: usize = 3;
/// Golden-section steps per refined maximum: the bracket of two sample spacings
/// shrinks to about 1e-9 rad.
pub const SEARCH_STEPS: usize = 40;
/// Error \[rad\] below which [`IiwaIk::validate`] counts a case as recovered.
pub const RECOVERED_TOLERANCE: f64 = 1e-9;
/// [`ValidationCase::limit`] up to which a case counts as well conditioned in
/// [`ValidationReport::max_error_well_conditioned`]: one rounding of the target
/// moves the exact solution by at most 1e-13 rad there, so an error of 1e-12
/// (seed 004 §V-C) is a fair demand.
pub const WELL_CONDITIONED_LIMIT: f64 = 1e-13;

pub use crate::ik::family::SelfMotionSample;

/// The analytic solver for the LBR iiwa and arms of the same shape.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, iiwa::IiwaIk};
/// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
/// let ik = IiwaIk::new(&robot)?;
/// let q = [0.3, 0.5, 0.0, -1.2, 0.4, 0.8, 0.1];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?; // q3 = 0 by default
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-10)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct IiwaIk {
    robot: Robot,
    d1: f64,
    d3: f64,
    d5: f64,
    d7: f64,
    base_inv: Pose,
    tool_inv: Pose,
    q3: f64,
    /// The closed forms (fixed q3 and arm angle), shared with `geo-srs`, built from the lengths.
    kernel: SrsKernel,
}

/// A target in the arm's own frame 0: flange rotation and wrist point relative to the shoulder.
struct ArmTarget {
    r07: Matrix3<f64>,
    w: Vector3<f64>,
}

/// What the ψ search found for one configuration.
struct PsiFound {
    config: u8,
    /// The largest limit margin seen \[rad\] and its joint values.
    best: (f64, [f64; 7]),
    /// Every sample and refined peak within limits.
    feasible: Vec<[f64; 7]>,
}

/// The argument in \[a, b\] at which golden-section search puts the maximum of `f`
/// after `steps` steps (a local maximum when `f` is not unimodal there).
pub(crate) fn golden_max(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, steps: usize) -> f64 {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..steps {
        if fc >= fd {
            (b, d, fd) = (d, c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    if fc >= fd {
        c
    } else {
        d
    }
}

/// The shared SRS kernel in the iiwa's frame 0 with the shoulder as origin:
/// axes z, y, z, y, z, y, z (R₀₄ = Rz·Ry·Rz·Ry, R₄₇ = Rz·Ry·Rz), elbow at
/// d3 and wrist point at d3 + d5 along z.
fn kernel_of(d3: f64, d5: f64) -> SrsKernel {
    let (z, y) = (Vector3::z(), Vector3::y());
    SrsKernel::new(&[z, y, z, y, z, y, z], &Vector3::zeros(), &(z * d3), &(z * (d3 + d5)))
}

/// Refuses a configuration label that is not 3 bits.
fn check_config(config: u8) -> Result<()> {
    if config > 7 {
        return Err(Error::Input(InputError::OutOfRange {
            what: "config".into(),
            value: f64::from(config),
            expected: "a 3-bit value, 0 to 7".into(),
        }));
    }
    Ok(())
}

/// The error for a self-motion of no samples.
pub(crate) fn no_steps() -> Error {
    Error::Input(InputError::TooFew { what: "steps".into(), got: 0, min: 1, of: "samples".into() })
}

fn invalid(robot: &Robot, reason: String) -> Error {
    Error::UnsupportedStructure { solver: "iiwa".into(), robot: robot.name().into(), reason }
}

/// The configuration bits of a joint vector (see the module documentation).
fn bits(q: &[f64]) -> u8 {
    let mut c = 0;
    if q[1] < 0.0 {
        c |= SHOULDER;
    }
    if q[3] < 0.0 {
        c |= ELBOW;
    }
    if q[5] < 0.0 {
        c |= WRIST;
    }
    c
}

/// The labels `shoulder±/elbow±/wrist±`, indexed by configuration bits, then
/// the same with the fixed-q3 shoulder side `/front` (indices 8–15) and
/// `/back` (16–23).
const LABELS: [&str; 24] = [
    "shoulder+/elbow+/wrist+",
    "shoulder-/elbow+/wrist+",
    "shoulder+/elbow-/wrist+",
    "shoulder-/elbow-/wrist+",
    "shoulder+/elbow+/wrist-",
    "shoulder-/elbow+/wrist-",
    "shoulder+/elbow-/wrist-",
    "shoulder-/elbow-/wrist-",
    "shoulder+/elbow+/wrist+/front",
    "shoulder-/elbow+/wrist+/front",
    "shoulder+/elbow-/wrist+/front",
    "shoulder-/elbow-/wrist+/front",
    "shoulder+/elbow+/wrist-/front",
    "shoulder-/elbow+/wrist-/front",
    "shoulder+/elbow-/wrist-/front",
    "shoulder-/elbow-/wrist-/front",
    "shoulder+/elbow+/wrist+/back",
    "shoulder-/elbow+/wrist+/back",
    "shoulder+/elbow-/wrist+/back",
    "shoulder-/elbow-/wrist+/back",
    "shoulder+/elbow+/wrist-/back",
    "shoulder-/elbow+/wrist-/back",
    "shoulder+/elbow-/wrist-/back",
    "shoulder-/elbow-/wrist-/back",
];

/// The label `shoulder±/elbow±/wrist±` of configuration bits (higher bits ignored).
pub fn config_label(config: u8) -> &'static str {
    LABELS[usize::from(config & 7)]
}

impl IiwaIk {
    /// A solver for `robot`, which must be a 7R arm of the iiwa's shape
    /// (see the module documentation); otherwise [`Error::UnsupportedStructure`]
    /// says what does not fit. The default q3 of [`IkSolver::solve`](crate::ik::IkSolver::solve) is 0.
    pub fn new(robot: &Robot) -> Result<Self> {
        const TWIST: [f64; 7] = [-FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, FRAC_PI_2, 0.0];
        if robot.dof() != 7 {
            return Err(invalid(
                robot,
                format!("`{}` has {} joints; the iiwa solver needs a 7-joint arm", robot.name(), robot.dof()),
            ));
        }
        let mut d = [0.0; 7];
        for (i, j) in robot.joints().iter().enumerate() {
            let n = i + 1;
            if j.kind != JointType::Revolute {
                return Err(invalid(robot, format!("joint {n} of `{}` is not revolute", robot.name())));
            }
            let LinkGeometry::Dh { convention: DhConvention::Standard, d: di, a, alpha, .. } = j.geometry else {
                return Err(invalid(robot, format!(
                    "joint {n} of `{}` is not described by a standard DH row; the iiwa solver reads a standard DH table",
                    robot.name()
                )));
            };
            if a.abs() > 1e-12 {
                return Err(invalid(robot, format!("joint {n}: link length a = {a} m, the iiwa shape needs a = 0")));
            }
            if wrap_angle(alpha - TWIST[i]).abs() > 1e-9 {
                return Err(invalid(
                    robot,
                    format!(
                        "joint {n}: twist α = {:.4}°, the iiwa shape needs {:.0}° (−90, 90, −90, 90, −90, 90, 0)",
                        alpha.to_degrees(),
                        TWIST[i].to_degrees()
                    ),
                ));
            }
            if j.offset.abs() > 1e-12 {
                return Err(invalid(robot, format!("joint {n}: offset {} rad, the iiwa shape needs 0", j.offset)));
            }
            if i % 2 == 1 && di.abs() > 1e-12 {
                return Err(invalid(robot, format!("joint {n}: d = {di} m, the iiwa shape needs d2 = d4 = d6 = 0")));
            }
            d[i] = di;
        }
        if !(d[2] > 0.0 && d[4] > 0.0) {
            return Err(invalid(
                robot,
                format!(
                    "d3 = {} m and d5 = {} m must be positive (shoulder–elbow and elbow–wrist lengths)",
                    d[2], d[4]
                ),
            ));
        }
        Ok(IiwaIk {
            robot: robot.clone(),
            d1: d[0],
            d3: d[2],
            d5: d[4],
            d7: d[6],
            base_inv: robot.base().inverse(),
            tool_inv: robot.tool().inverse(),
            q3: 0.0,
            kernel: kernel_of(d[2], d[4]),
        })
    }

    /// The same solver with another q3 \[rad\] for [`IkSolver::solve`](crate::ik::IkSolver::solve).
    pub fn with_q3(mut self, q3: f64) -> Self {
        self.q3 = q3;
        self
    }

    /// The q3 \[rad\] that [`IkSolver::solve`](crate::ik::IkSolver::solve) uses.
    pub fn q3(&self) -> f64 {
        self.q3
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The lengths (d1, d3, d5, d7) \[m\] read from the model.
    pub fn lengths(&self) -> [f64; 4] {
        [self.d1, self.d3, self.d5, self.d7]
    }

    fn unreachable(&self, by: f64, boundary: String) -> Error {
        Error::Unreachable { solver: "iiwa".into(), reason: Unreachable::OutsideReach { by, boundary }, closest: None }
    }

    /// Strips base and tool: the flange rotation and wrist point (relative to the shoulder) in frame 0.
    fn arm_target(&self, target: &Pose) -> Result<ArmTarget> {
        check_target(target)?;
        let t = self.base_inv.mul(target).mul(&self.tool_inv);
        let w = t.pos - t.rot.column(2) * self.d7 - Vector3::new(0.0, 0.0, self.d1);
        Ok(ArmTarget { r07: t.rot, w })
    }

    /// The reach error (seed 004 eq. 4) when no elbow angle gives a shoulder–wrist distance `r` \[m\].
    fn elbow(&self, r: f64) -> Result<()> {
        // Seed 004 eq. 4 gives q4 = π ± arccos((d3² + d5² − r²)/(2·d3·d5)); its
        // "+" branch lies in [π, 2π] and must be wrapped to (−π, π] (π + x ≡ x − π)
        // to be compared with the ±120° limit of joint 4. The shared kernel
        // computes the same angle as atan2(|s4|, c4) with 1 ∓ c4 in factored
        // form, which keeps full precision near the stretched and folded arm
        // where arccos loses half the digits.
        match self.kernel.elbow(r) {
            Ok(_) => Ok(()),
            Err(miss) => Err(self.miss_error(miss, 0.0, 0.0)),
        }
    }

    /// The error for a miss of the shared kernel at q3 with sin q3 = `s3` and
    /// |sin q4| = `s4` (which size the excluded cylinder).
    fn miss_error(&self, miss: Miss, q3: f64, s4: f64) -> Error {
        let (outer, inner) = self.kernel.reach();
        match miss {
            Miss::Outer(by) => self.unreachable(
                by,
                format!("outer sphere of radius {outer:.4} m around the shoulder (reach of the wrist point)"),
            ),
            Miss::Inner(by) => self.unreachable(
                by,
                format!("inner sphere of radius {inner:.4} m around the shoulder (the wrist point cannot come closer)"),
            ),
            Miss::Arm(by) => {
                let region = format!(
                    "cylinder of radius {:.4} m around the axis of joint 1, which the wrist point cannot enter with q3 = {q3:.6} rad",
                    self.d5 * (q3.sin() * s4).abs()
                );
                Error::Unreachable {
                    solver: "iiwa".into(),
                    reason: Unreachable::InsideExcluded { by, region },
                    closest: None,
                }
            }
            Miss::Wrist(chord) => Error::Unreachable {
                solver: "iiwa".into(),
                reason: Unreachable::Orientation {
                    angle: 2.0 * (0.5 * chord).min(1.0).asin(),
                    detail: "the wrist cannot turn axis 7 to the direction asked for".into(),
                },
                closest: None,
            },
        }
    }

    /// All solutions (joint vectors, without FK evaluation) for a fixed q3,
    /// seed 004 eq. 3–11, with `q1_hint` used at the shoulder singularity.
    fn solve_q3_raw(&self, t: &ArmTarget, q3: f64, q1_hint: f64) -> Result<Candidates<7, 8>> {
        self.solve_q3_branches(t, q3, q1_hint, None)
    }

    /// As [`Self::solve_q3_raw`]; with `near`, only the shoulder and elbow
    /// branches `near` is unambiguously on (|sin q4| > 0.05 for the elbow; for
    /// the shoulder, its q1 puts the wrist on the same side by more than half
    /// the offset) — the others cannot be the continuation of a path through
    /// `near`.
    fn solve_q3_branches(
        &self,
        t: &ArmTarget,
        q3: f64,
        q1_hint: f64,
        near: Option<&[f64]>,
    ) -> Result<Candidates<7, 8>> {
        let goal = self.kernel.goal(&t.w, &t.r07);
        let near = near.and_then(|q| q.get(..7)).and_then(|q| q.try_into().ok());
        let options = Options { q1_hint, flip_singular_wrist: false, near };
        let mut out = Candidates::<7, 8>::default();
        // `/front` (shoulder root 0: the wrist point ahead of the shoulder
        // along x of DH frame 1) or `/back`; coinciding solutions (singular
        // cases) are kept once.
        let push = |q: [f64; 7], (_, shoulder, _)| {
            let side = if shoulder == 0 { 8 } else { 16 };
            out.push_unique(q, LABELS[side + usize::from(bits(&q))], 1e-12, true);
        };
        self.kernel.solve_q3(&goal, q3, &options, push).map_err(|miss| {
            let s4 = self.kernel.elbow(t.w.norm()).map_or(0.0, |(s4, _)| s4);
            self.miss_error(miss, q3, s4)
        })?;
        Ok(out)
    }

    /// All solutions for the target pose `target` (`world_from_tool`) with
    /// joint 3 fixed at `q3` \[rad\] — seed 004 eq. 3–11: up to 8 solutions,
    /// 2 elbows × 2 shoulders × 2 wrists, each labelled with its
    /// configuration bits and the fixed-q3 shoulder side
    /// (`shoulder+/elbow-/wrist+/front`, see the module documentation). Solutions outside the joint limits are included and
    /// flagged; coinciding solutions (singular cases) are returned once.
    ///
    /// Errors: a non-finite target ([`InputError::NotFinite`]); a wrist point
    /// outside the shoulder–wrist annulus \[|d3 − d5|, d3 + d5\], or inside the
    /// cylinder around the axis of joint 1 of radius d5·|sin q3·sin q4| that
    /// this q3 cannot reach ([`Error::Unreachable`] with
    /// [`Unreachable::OutsideReach`] saying by how much).
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::iiwa::IiwaIk;
    /// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
    /// let ik = IiwaIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let target = robot.fk(&q)?.world_from_tool;
    /// let sols = ik.solve_q3(&target, q[2])?;
    /// assert_eq!(sols.len(), 8);
    /// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
    /// let back = sols.iter().find(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-10)).unwrap();
    /// assert!(back.branch.starts_with("shoulder+/elbow-/wrist+/"));
    /// assert_eq!(ik.config_of(&back.q), kinema::ik::iiwa::ELBOW);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_q3(&self, target: &Pose, q3: f64) -> Result<Vec<Solution>> {
        if !q3.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "q3".into(), value: q3 }));
        }
        let t = self.arm_target(target)?;
        self.solve_q3_raw(&t, q3, 0.0)?.evaluate(&self.robot, target)
    }

    /// The closed form of [`IiwaIk::solve_q3`] alone: the joint vectors and
    /// branch labels, without the FK residual check and without allocating.
    /// Same errors.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::iiwa::IiwaIk;
    /// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
    /// let ik = IiwaIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let c = ik.solve_q3_candidates(&robot.fk(&q)?.world_from_tool, q[2])?;
    /// assert_eq!(c.len(), 8);
    /// assert!(c.qs().iter().any(|s| s.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-10)));
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_q3_candidates(&self, target: &Pose, q3: f64) -> Result<Candidates<7, 8>> {
        if !q3.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "q3".into(), value: q3 }));
        }
        let t = self.arm_target(target)?;
        self.solve_q3_raw(&t, q3, 0.0)
    }

    /// The candidates of [`IiwaIk::solve_q3_candidates`] that can continue a
    /// path through the nearby configuration `near` (a sample earlier): those
    /// on `near`'s shoulder and elbow side, both wrists (so usually 2 instead
    /// of 8; all of them where `near` is close to a shoulder or elbow
    /// singularity and its side is ambiguous). Same errors, plus a `near` that
    /// is not 7 finite values.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::iiwa::IiwaIk;
    /// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
    /// let ik = IiwaIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let next = robot.fk(&[0.301, 0.5, -0.7, -1.199, 0.4, 0.8, 0.1])?.world_from_tool;
    /// let c = ik.solve_q3_near(&next, -0.7, &q)?;
    /// assert_eq!(c.len(), 2);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_q3_near(&self, target: &Pose, q3: f64, near: &[f64]) -> Result<Candidates<7, 8>> {
        if !q3.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "q3".into(), value: q3 }));
        }
        self.robot.check_q(near)?;
        let t = self.arm_target(target)?;
        self.solve_q3_branches(&t, q3, near[0], Some(near))
    }

    /// The configuration bits of `q` ([`SHOULDER`] | [`ELBOW`] | [`WRIST`], a
    /// bit set when q2, q4, q6 respectively is negative). Values missing from a
    /// short `q` count as 0 (bit clear); NaN counts as non-negative.
    pub fn config_of(&self, q: &[f64]) -> u8 {
        let mut full = [0.0; 7];
        for (f, v) in full.iter_mut().zip(q) {
            *f = *v;
        }
        bits(&full)
    }

    /// One solution from the arm angle (no FK evaluation): the shared
    /// kernel's root with the elbow, shoulder and wrist of `config` (root 1
    /// is the one with q4, q2, q6 negative).
    fn solve_psi_raw(&self, t: &ArmTarget, psi: f64, config: u8) -> Result<[f64; 7]> {
        let goal = self.kernel.goal(&t.w, &t.r07);
        let root = |bit: u8| usize::from(config & bit != 0);
        let only = [root(ELBOW), root(SHOULDER), root(WRIST)];
        let mut solutions = Solutions::empty();
        self.kernel
            .solve_psi(&goal, psi, false, Some(only), &mut solutions)
            .map_err(|miss| self.miss_error(miss, 0.0, 0.0))?;
        Ok(solutions.q[0])
    }

    /// The solution with arm angle `psi` \[rad\] and configuration bits
    /// `config` (Shimizu et al. 2008): ψ is the right-handed rotation of the
    /// shoulder–elbow–wrist plane about the line from shoulder to wrist,
    /// measured from the plane of the arm with q3 = 0 and the same elbow
    /// angle, shoulder in front (q1° = atan2(w_y, w_x)). Errors as
    /// [`IiwaIk::solve_q3`] (the annulus only: every ψ is reachable).
    pub fn solve_psi(&self, target: &Pose, psi: f64, config: u8) -> Result<Solution> {
        if !psi.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "psi".into(), value: psi }));
        }
        check_config(config)?;
        let t = self.arm_target(target)?;
        let q = self.solve_psi_raw(&t, psi, config)?;
        Solution::evaluate(&self.robot, q.to_vec(), target, config_label(config))
    }

    /// The arm angle ψ \[rad\] in (−π, π] of a configuration `q`, the inverse of
    /// [`IiwaIk::solve_psi`]. NaN if `q` does not have 7 finite values.
    pub fn psi_of(&self, q: &[f64]) -> f64 {
        if self.robot.check_q(q).is_err() {
            return f64::NAN;
        }
        self.kernel.psi_of(q)
    }

    /// The elbow (origin of DH frame 3) in world coordinates.
    fn elbow_position(&self, q: &[f64]) -> Vector3<f64> {
        let e = rot_z(q[0]) * rot_y(q[1]) * Vector3::new(0.0, 0.0, self.d3) + Vector3::new(0.0, 0.0, self.d1);
        self.robot.base().transform_point(&e)
    }

    /// The self-motion through `q` (seed 004 §V-D, Fig. 7): `steps` samples of
    /// the arm angle, equally spaced over a full turn starting at ψ of `q`,
    /// all with the tool pose of `q` and its configuration bits. The elbow
    /// moves on a circle about the shoulder–wrist line (a point if q4 = 0).
    pub fn self_motion(&self, q: &[f64], steps: usize) -> Result<Vec<SelfMotionSample>> {
        if steps == 0 {
            return Err(no_steps());
        }
        let fk = self.robot.fk(q)?;
        let t = self.arm_target(&fk.world_from_tool)?;
        let config = bits(q);
        let psi0 = self.psi_of(q);
        (0..steps)
            .map(|k| {
                let psi = wrap_angle(psi0 + TAU * k as f64 / steps as f64);
                let qk = self.solve_psi_raw(&t, psi, config)?;
                Ok(SelfMotionSample {
                    psi,
                    q3: qk[2],
                    q: qk.to_vec(),
                    elbow: self.elbow_position(&qk),
                    within_limits: self.robot.limit_flags(&qk).is_empty(),
                })
            })
            .collect()
    }
}

impl crate::ik::ClosedForm for IiwaIk {
    const NAME: &'static str = "iiwa";

    fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The (up to 8) candidates of [`IiwaIk::solve_q3_candidates`] for q3 =
    /// [`IiwaIk::q3`] (0 unless set with [`IiwaIk::with_q3`]).
    fn kernel(&self, target: &Pose, out: &mut crate::ik::CandidateSet) -> Result<()> {
        self.solve_q3_candidates(target, self.q3)?.write_into(out);
        Ok(())
    }
}

impl crate::ik::family::Family for IiwaIk {
    fn redundancy(&self) -> Option<&dyn Redundancy> {
        Some(self)
    }
}

#[cfg(test)]
mod tests;

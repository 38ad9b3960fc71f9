//! 7R arms with a spherical shoulder, an elbow and a spherical wrist (SRS,
//! the KUKA LBR iiwa's structure), recognised from the axes alone: axes 1, 2,
//! 3 meet in the shoulder point s, axes 5, 6, 7 in the wrist centre w, and
//! axis 4 (the elbow) passes through neither.
//!
//! With joint 3 fixed the arm is a 6R with both shoulder and wrist
//! spherical. E₅E₆E₇ fix w and E₁E₂E₃ turn about s, so the target's wrist
//! centre W = G(w) (G = T·T₀⁻¹) satisfies W − s = R₁R₂R₃·(E₄(w) − s):
//!
//! * **Elbow**: |E₄(w) − s| = |W − s| fixes q₄ (*elbow* 1, 2).
//! * **Shoulder**: with x = R₃·(E₄(w) − s), rot(h₁, q₁)·rot(h₂, q₂)·x =
//!   W − s gives (q₁, q₂) (*shoulder* 1, 2).
//! * **Wrist**: M = (R₁R₂R₃R₄)ᵀ·R_G = R₅R₆R₇ gives q₅, q₆, q₇ (*wrist* 1, 2).
//!
//! The formulas are the one SRS kernel (`geo/srs_kernel.rs`, which derives
//! them), shared with `IiwaIk`: specialised to the axes once, in the frame
//! where h₁ = ẑ, with the same two-axis solve for shoulder and wrist; on
//! the iiwa's orthogonal wrist it keeps full accuracy near q₆ = 0.
//!
//! Up to 8 solutions for each q₃; the self-motion is q₃ itself, searched
//! within the limits by [`SrsIk::solve_searching`].
//!
//! **Arm angle ψ** ([`SrsIk::solve_psi`], [`SrsIk::psi_of`]): the other
//! parameter of the self-motion, with `IiwaIk`'s meaning (Shimizu et al.
//! 2008), read from the axes. Every configuration reaching W turns the
//! upper arm by a shoulder rotation R = R₁R₂R₃ with R·x₀ = W − s, where
//! x₀ = E₄(w) − s depends on q₄ alone; these rotations form the circle
//! R = Rot(d̂, ψ)·R° about the shoulder→wrist direction d̂. The reference R°
//! maps x₀ to W − s and the part of h₂ normal to x₀ onto the normal h₁ × d
//! of the plane through axis 1 and W. So ψ is the angle by which the elbow
//! point e — the point of axis 4 nearest s: fixed on the upper arm whatever
//! q₄, never s itself, and on the iiwa the elbow where axes 3 and 4 meet —
//! has turned about the shoulder→wrist line from its reference position, as
//! has everything else on the upper arm. On the iiwa, whose arm with
//! q₁ = q₂ = q₃ = 0 lies in a plane normal to axis 2, R° is the arm with
//! q₃ = 0, the same elbow angle and axis 2 along h₁ × d (the shoulder facing
//! W), and the plane (s, e, W) is turned by ψ from the plane through axis 1
//! and W: `IiwaIk`'s ψ exactly, also from a URDF or `general` description.
//! Measuring the whole upper arm rather than e keeps ψ defined with the
//! elbow stretched (e on the line from s to W). Its sense never depends on
//! the description; describing exactly one of axes 1 and 2 reversed (the
//! joint turning the other way) moves its zero by π. Where the shoulder axes
//! are not mutually perpendicular, joints 1–3 cannot take every ψ (an
//! [`Unreachable::Orientation`] error).
//!
//! **Singular cases** (conventions, never NaN): at the wrist singularity
//! (M·h₇ ∥ h₅ within 1e-12: axes 5 and 7 aligned) only a combination of q₅
//! and q₇ is determined: *wrist-1* takes q₅ = 0 and *wrist-2* q₅ = π (moved
//! into the limits when possible), q₆ and q₇ follow. At the
//! shoulder singularity (W − s on axis 1) q₁ = 0, and where W − s lies on
//! axis 2's direction q₂ = 0. Coinciding branches (a stretched or folded elbow, a target on a
//! boundary) are all returned, so the branch count stays fixed. For ψ: with
//! W on axis 1 (within 1e-12 m) the plane through axis 1 and W is undefined
//! and h₂ takes the place of its normal (`IiwaIk`'s q₁ = 0; ψ jumps there,
//! the arm-angle method's own singularity); when h₂ ∥ x₀ (never on the
//! iiwa) any normal of x₀ is used.

use std::f64::consts::{PI, TAU};

use nalgebra::Vector3;

use super::kin::{distance_to_line, intersection, parallel};
use super::srs_kernel::{Miss, Options, Solutions, SrsKernel};
use super::{label, reject, too_far, Common, GEOM_TOL, LABELS};
use crate::error::{Error, InputError, Result};
use crate::ik::family::SelfMotionParameter;
use crate::ik::iiwa::golden_max;
use crate::ik::{check_target, CandidateSet, Candidates, ClosedForm, Solution, Unreachable};
use crate::math::Pose;
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// The solver's name.
const NAME: &str = "geo-srs";

/// Samples of q₃ over its range in [`SrsIk::solve_searching`].
pub const SEARCH_SAMPLES: usize = 128;
/// Local maxima of the limit margin refined per branch by [`SrsIk::solve_searching`].
pub const SEARCH_PEAKS: usize = 2;
/// Golden-section steps per refined maximum: a bracket of two sample
/// spacings shrinks below 1e-9 rad.
pub const SEARCH_STEPS: usize = 40;

/// The limit margin and joint values of each of the 8 branches at one q₃
/// (−∞ where the branch has no solution).
type Margins = [(f64, [f64; 7]); 8];

/// The geometric solver for SRS arms (see the [module documentation](self)).
/// Name `geo-srs`. [`IkSolver::solve`](crate::ik::IkSolver::solve) is [`SrsIk::solve_q3`] at q₃ = 0.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::SrsIk};
/// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf"), None)?;
/// let ik = SrsIk::new(&robot)?;
/// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
/// let sols = ik.solve_q3(&robot.fk(&q)?.world_from_tool, q[2])?;
/// assert_eq!(sols.len(), 8);
/// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct SrsIk {
    common: Common,
    /// The shoulder point (axes 1, 2, 3 meet) \[m\].
    s: V3,
    /// The wrist centre at q = 0 (axes 5, 6, 7 meet) \[m\].
    w: V3,
    /// The closed forms (fixed q₃ and arm angle), shared with `IiwaIk`.
    arm: SrsKernel,
}

impl SrsIk {
    /// Checks the structure (tolerance [`GEOM_TOL`]) and prepares the
    /// solver: seven revolute joints; axes 1 and 2 meet and axis 3 passes
    /// through that point, not parallel to axis 2; axes 5 and 6 meet and
    /// axis 7 passes through that point, not parallel to axis 6; axis 4
    /// passes through neither point. Errors say which fails.
    pub fn new(robot: &Robot) -> Result<Self> {
        if robot.dof() != 7 {
            return reject(
                NAME,
                robot,
                format!("the {NAME} solver needs exactly 7 revolute joints; this robot has {}", robot.dof()),
            );
        }
        let common = Common::with_dof(robot, NAME, 7)?;
        let s = meeting_point(&common, 0, "shoulder")?;
        let w = meeting_point(&common, 4, "wrist")?;
        let (h4, p4) = (common.h(3), common.p(3));
        if distance_to_line(&s, &p4, &h4) <= GEOM_TOL || distance_to_line(&w, &p4, &h4) <= GEOM_TOL {
            return reject(
                NAME,
                robot,
                "axis 4 passes through the shoulder point or the wrist centre: the elbow cannot change their distance"
                    .into(),
            );
        }
        let axes = std::array::from_fn(|i| common.h(i));
        let arm = SrsKernel::new(&axes, &s, &p4, &w);
        Ok(SrsIk { common, s, w, arm })
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// The shoulder point and the wrist centre at q = 0 (world frame) \[m\].
    pub fn centres(&self) -> (V3, V3) {
        (self.s, self.w)
    }

    /// All (up to 8) solutions for the target pose `target`
    /// (`world_from_tool`) with joint 3 at `q3` \[rad\], labelled
    /// `shoulder-{1,2}/elbow-{1,2}/wrist-{1,2}`; solutions outside the limits
    /// are included and flagged.
    ///
    /// Errors: a non-finite `q3` or target ([`InputError::NotFinite`]); a
    /// wrist centre outside the shell the elbow reaches
    /// ([`Unreachable::OutsideReach`]), in the cones around axis 1 that this
    /// q3 cannot reach ([`Unreachable::InsideExcluded`]), or an orientation
    /// the wrist cannot take ([`Unreachable::Orientation`]).
    pub fn solve_q3(&self, target: &Pose, q3: f64) -> Result<Vec<Solution>> {
        self.solve_q3_candidates(target, q3)?.evaluate(self.robot(), target)
    }

    /// The closed form of [`SrsIk::solve_q3`] alone: joint vectors and branch
    /// labels without the FK check, without allocating. Same errors.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::geo::SrsIk;
    /// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf"), None)?;
    /// let ik = SrsIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let c = ik.solve_q3_candidates(&robot.fk(&q)?.world_from_tool, q[2])?;
    /// assert_eq!(c.len(), 8);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_q3_candidates(&self, target: &Pose, q3: f64) -> Result<Candidates<7, 8>> {
        if !q3.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "q3".into(), value: q3 }));
        }
        check_target(target)?;
        let mut out = Candidates::default();
        self.kernel(target, q3, &mut out).map_err(|reason| Error::Unreachable {
            solver: NAME.into(),
            reason,
            closest: None,
        })?;
        Ok(out)
    }

    /// The kernel: every candidate for a checked target and finite q₃.
    fn kernel(&self, target: &Pose, q3: f64, out: &mut Candidates<7, 8>) -> std::result::Result<(), Unreachable> {
        let g = self.common.motion(target);
        let wt = g.transform_point(&self.w);
        if let Some(u) = too_far(&wt) {
            return Err(u);
        }
        let goal = self.arm.goal(&(wt - self.s), &g.rot);
        let options = Options { flip_singular_wrist: true, ..Options::default() };
        let push = |q, (elbow, shoulder, wrist)| self.common.push(out, q, label(shoulder, elbow, wrist));
        self.arm.solve_q3(&goal, q3, &options, push).map_err(|miss| unreachable(miss, q3))?;
        if out.is_empty() {
            return Err(Unreachable::NotReached { detail: "the closed form gave no finite joint values".into() });
        }
        Ok(())
    }

    /// All (up to 8) solutions for the target pose `target`
    /// (`world_from_tool`) at the arm angle `psi` \[rad\] (see the [module
    /// documentation](self)), labelled `shoulder-{1,2}/elbow-{1,2}/wrist-{1,2}`
    /// as [`SrsIk::solve_q3`]'s; solutions outside the limits are included
    /// and flagged. Each label keeps its branch as ψ varies, away from the
    /// singularities.
    ///
    /// Errors: a non-finite `psi` or target ([`InputError::NotFinite`]); a
    /// wrist centre outside the shell the elbow reaches
    /// ([`Unreachable::OutsideReach`]); an arm angle joints 1–3 cannot turn
    /// the upper arm to, or an orientation the wrist cannot take
    /// ([`Unreachable::Orientation`]). On the iiwa, whose shoulder axes are
    /// perpendicular, every ψ is reachable.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::geo::SrsIk;
    /// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf"), None)?;
    /// let ik = SrsIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let psi = ik.psi_of(&q);
    /// let sols = ik.solve_psi(&robot.fk(&q)?.world_from_tool, psi)?;
    /// assert_eq!(sols.len(), 8);
    /// assert!(sols.iter().all(|s| s.position_error < 1e-10 && (ik.psi_of(&s.q) - psi).abs() < 1e-9));
    /// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_psi(&self, target: &Pose, psi: f64) -> Result<Vec<Solution>> {
        self.solve_psi_candidates(target, psi)?.evaluate(self.robot(), target)
    }

    /// The closed form of [`SrsIk::solve_psi`] alone: joint vectors and
    /// branch labels without the FK check, without allocating. Same errors.
    pub fn solve_psi_candidates(&self, target: &Pose, psi: f64) -> Result<Candidates<7, 8>> {
        if !psi.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "psi".into(), value: psi }));
        }
        check_target(target)?;
        let mut out = Candidates::default();
        self.psi_kernel(target, psi, &mut out).map_err(|reason| Error::Unreachable {
            solver: NAME.into(),
            reason,
            closest: None,
        })?;
        Ok(out)
    }

    /// The arm-angle kernel: every candidate for a checked target and finite ψ.
    fn psi_kernel(&self, target: &Pose, psi: f64, out: &mut Candidates<7, 8>) -> std::result::Result<(), Unreachable> {
        let g = self.common.motion(target);
        let wt = g.transform_point(&self.w);
        if let Some(u) = too_far(&wt) {
            return Err(u);
        }
        let goal = self.arm.goal(&(wt - self.s), &g.rot);
        let mut solutions = Solutions::empty();
        self.arm.solve_psi(&goal, psi, true, None, &mut solutions).map_err(|miss| match miss {
            Miss::Arm(chord) => Unreachable::Orientation {
                angle: chord_angle(chord),
                detail: format!("joints 1–3 cannot turn the upper arm to the arm angle ψ = {psi:.6} rad"),
            },
            other => unreachable(other, 0.0),
        })?;
        for (q, (elbow, shoulder, wrist)) in solutions.iter() {
            self.common.push(out, *q, label(shoulder, elbow, wrist));
        }
        if out.is_empty() {
            return Err(Unreachable::NotReached { detail: "the closed form gave no finite joint values".into() });
        }
        Ok(())
    }

    /// The arm angle ψ \[rad\] in (−π, π] of a configuration `q`, the
    /// inverse of [`SrsIk::solve_psi`]; NaN if `q` does not have 7 finite
    /// values. It depends on q₁…q₄ only.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::geo::SrsIk;
    /// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf"), None)?;
    /// let ik = SrsIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let psi = ik.psi_of(&q);
    /// assert!(psi.abs() <= std::f64::consts::PI);
    /// assert!(ik.psi_of(&[0.0; 3]).is_nan());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn psi_of(&self, q: &[f64]) -> f64 {
        if self.robot().check_q(q).is_err() {
            return f64::NAN;
        }
        self.arm.psi_of(q)
    }

    /// The solutions within the joint limits for `target`
    /// (`world_from_tool`), searching q₃ when `prefer_q3` \[rad\] has none.
    ///
    /// First [`SrsIk::solve_q3`] at `prefer_q3`: its solutions within limits,
    /// if any. Otherwise q₃ is scanned over its range (its limits, or a turn
    /// when they span more) at [`SEARCH_SAMPLES`] points; for each branch the
    /// smallest distance to a joint limit (negative outside) is maximised by
    /// golden-section refinement of its [`SEARCH_PEAKS`] highest sampled local
    /// maxima, and each branch's solution of largest margin is returned when
    /// that margin is not negative. Deterministic and bounded: at most
    /// 1 + [`SEARCH_SAMPLES`] + 8 × [`SEARCH_PEAKS`] × ([`SEARCH_STEPS`] + 3)
    /// closed-form solves. A feasible stretch of q₃ narrower than the refined
    /// brackets can be missed.
    ///
    /// Errors: those of [`SrsIk::solve_q3`] for a non-finite target or q₃,
    /// and when no q₃ of the scan gives any solution; otherwise
    /// [`Unreachable::JointLimits`] with each branch's best attempt.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::geo::SrsIk;
    /// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf"), None)?;
    /// let ik = SrsIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let sols = ik.solve_searching(&robot.fk(&q)?.world_from_tool, 0.0)?;
    /// assert!(!sols.is_empty());
    /// assert!(sols.iter().all(|s| s.within_limits() && s.position_error < 1e-10));
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_searching(&self, target: &Pose, prefer_q3: f64) -> Result<Vec<Solution>> {
        // A joint the closed form recovers on its limit may land a rounding past it.
        let settled = self.solve_q3(target, prefer_q3).map(|mut sols| {
            for s in &mut sols {
                s.out_of_limits = crate::ik::settle_on_limits(self.robot(), &mut s.q);
            }
            sols
        });
        let first = match settled {
            Ok(sols) if sols.iter().any(Solution::within_limits) => {
                return Ok(sols.into_iter().filter(Solution::within_limits).collect());
            }
            Err(e @ (Error::Input(InputError::OutOfRange { .. }) | Error::Input(InputError::NotFinite { .. }))) => {
                return Err(e)
            }
            other => other,
        };
        let mut best = self.search_q3(target);
        // The preferred q3 may lie between the samples (or outside the range).
        for (slot, m) in best.iter_mut().zip(self.margins(target, prefer_q3)) {
            if m.0 > slot.0 {
                *slot = m;
            }
        }
        if best.iter().all(|b| b.0 == f64::NEG_INFINITY) {
            // No q₃ gives a solution: the closed form's own reason.
            return first.and_then(|_| self.limits_error(&best));
        }
        if best.iter().all(|b| b.0 < 0.0) {
            return self.limits_error(&best);
        }
        (0..8)
            .filter(|&b| best[b].0 >= 0.0)
            .map(|b| Solution::evaluate(self.robot(), best[b].1.to_vec(), target, LABELS[b]))
            .collect()
    }

    /// [`Unreachable::JointLimits`] listing each branch's best attempt.
    fn limits_error<T>(&self, best: &Margins) -> Result<T> {
        let rejected = (0..8)
            .filter(|&b| best[b].0 > f64::NEG_INFINITY)
            .map(|b| {
                let joints: Vec<String> =
                    self.robot().limit_flags(&best[b].1).indices().map(|i| format!("q{}", i + 1)).collect();
                format!("{} over q3: best {:.4} rad outside ({})", LABELS[b], -best[b].0, joints.join(", "))
            })
            .collect();
        Err(Error::Unreachable { solver: NAME.into(), reason: Unreachable::JointLimits { rejected }, closest: None })
    }

    /// The range of q₃ searched: its limits, or (−π, π] when they span more
    /// than a turn (or are not finite).
    fn q3_range(&self) -> (f64, f64) {
        let lim = &self.robot().joints()[2].limits;
        if lim.min.is_finite() && lim.max.is_finite() && lim.max - lim.min <= TAU && lim.min <= lim.max {
            (lim.min, lim.max)
        } else {
            (-PI, PI)
        }
    }

    /// Each branch's best (margin, q) over the scan of q₃ and the golden-section
    /// refinement of its highest local maxima.
    fn search_q3(&self, target: &Pose) -> Margins {
        let (lo, hi) = self.q3_range();
        let n = SEARCH_SAMPLES;
        let step = (hi - lo) / (n - 1) as f64;
        let at = |k: usize| lo + step * k as f64;
        let samples: Vec<Margins> = (0..n).map(|k| self.margins(target, at(k))).collect();
        let mut best = [(f64::NEG_INFINITY, [0.0; 7]); 8];
        for (b, slot) in best.iter_mut().enumerate() {
            let m = |k: usize| samples[k][b].0;
            let mut peaks: Vec<usize> = (0..n)
                .filter(|&k| m(k) > f64::NEG_INFINITY)
                .filter(|&k| (k == 0 || m(k) >= m(k - 1)) && (k + 1 == n || m(k) >= m(k + 1)))
                .collect();
            peaks.sort_by(|&x, &y| m(y).total_cmp(&m(x)));
            peaks.truncate(SEARCH_PEAKS);
            let refined = peaks.iter().map(|&k| {
                let (a, z) = ((at(k) - step).max(lo), (at(k) + step).min(hi));
                self.margins(target, golden_max(|t| self.margins(target, t)[b].0, a, z, SEARCH_STEPS))[b]
            });
            let all = samples.iter().map(|s| s[b]).chain(refined);
            *slot = all.fold(*slot, |x, y| if y.0 > x.0 { y } else { x });
        }
        best
    }

    /// The limit margin of each branch at `q3` (−∞ where there is none).
    fn margins(&self, target: &Pose, q3: f64) -> Margins {
        let mut out = [(f64::NEG_INFINITY, [0.0; 7]); 8];
        let mut c = Candidates::<7, 8>::default();
        if self.kernel(target, q3, &mut c).is_err() {
            return out;
        }
        for (q, branch) in c.iter() {
            if let Some(b) = LABELS.iter().position(|l| *l == branch) {
                out[b] = (self.limit_margin(q), *q);
            }
        }
        out
    }

    /// The smallest distance of `q` to a joint limit ([`crate::ik::limit_margin`]).
    fn limit_margin(&self, q: &[f64; 7]) -> f64 {
        crate::ik::limit_margin(self.robot(), q)
    }
}

/// The refusal for a kernel's miss at `q3` \[rad\].
fn unreachable(miss: Miss, q3: f64) -> Unreachable {
    match miss {
        Miss::Outer(by) | Miss::Inner(by) => {
            let boundary = "spherical shell around the shoulder point that the elbow lets the wrist centre reach";
            Unreachable::OutsideReach { by, boundary: boundary.into() }
        }
        Miss::Arm(by) => {
            let region = format!("cones around axis 1 that the wrist centre cannot enter with joint 3 at {q3:.6} rad");
            Unreachable::InsideExcluded { by, region }
        }
        Miss::Wrist(chord) => Unreachable::Orientation {
            // The miss is a chord between unit vectors; as an angle:
            angle: chord_angle(chord),
            detail: "the wrist cannot turn axis 7 to the direction asked for".into(),
        },
    }
}

/// A chord between unit vectors as the angle between them \[rad\].
fn chord_angle(chord: f64) -> f64 {
    2.0 * (0.5 * chord).min(1.0).asin()
}

/// The point where axes `first`, `first + 1` meet, checked to lie on axis
/// `first + 2` too (a spherical shoulder or wrist, `what`).
fn meeting_point(c: &Common, first: usize, what: &str) -> Result<V3> {
    let (a, b, k) = (first, first + 1, first + 2);
    let robot = &c.robot;
    let Some(x) = intersection(&c.p(a), &c.h(a), &c.p(b), &c.h(b), GEOM_TOL) else {
        return reject(
            NAME,
            robot,
            format!("axes {} and {} do not meet (or are parallel): no spherical {what}", a + 1, b + 1),
        );
    };
    if parallel(&c.h(b), &c.h(k), GEOM_TOL) || distance_to_line(&x, &c.p(k), &c.h(k)) > GEOM_TOL {
        return reject(
            NAME,
            robot,
            format!(
                "axis {} does not pass through the point where axes {} and {} meet (or is parallel to axis {}): \
                 no spherical {what}",
                k + 1,
                a + 1,
                b + 1,
                b + 1
            ),
        );
    }
    Ok(x)
}

impl ClosedForm for SrsIk {
    const NAME: &'static str = NAME;

    fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// [`SrsIk::solve_q3_candidates`] at q₃ = 0.
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        self.solve_q3_candidates(target, 0.0)?.write_into(out);
        Ok(())
    }
}

impl crate::ik::family::Family for SrsIk {
    fn redundancy(&self) -> Option<&dyn crate::ik::family::Redundancy> {
        Some(self)
    }
}

/// The self-motion as joint 3 (`q3`, the first parameter, which the
/// searches and the steered paths vary) or as the arm angle (`psi`).
impl crate::ik::family::Redundancy for SrsIk {
    fn parameters(&self) -> &'static [SelfMotionParameter] {
        &[SelfMotionParameter::Q3, SelfMotionParameter::ArmAngle]
    }

    /// Up to 8 solutions at `q3` or at `psi`.
    fn solve_at(&self, target: &Pose, parameter: SelfMotionParameter, value: f64) -> Result<Vec<Solution>> {
        match parameter {
            SelfMotionParameter::ArmAngle => self.solve_psi(target, value),
            SelfMotionParameter::Q3 => self.solve_q3(target, value),
        }
    }

    fn value_of(&self, q: &[f64]) -> f64 {
        q.get(2).copied().unwrap_or(f64::NAN)
    }

    fn parameter_of(&self, q: &[f64], parameter: SelfMotionParameter) -> f64 {
        match parameter {
            SelfMotionParameter::Q3 => self.value_of(q),
            SelfMotionParameter::ArmAngle => self.psi_of(q),
        }
    }

    /// The closed form's candidates without the FK check (a path checks the one it takes).
    fn continue_at(
        &self,
        target: &Pose,
        parameter: SelfMotionParameter,
        value: f64,
        _prev: &[f64],
        out: &mut CandidateSet,
    ) -> Result<()> {
        let candidates = match parameter {
            SelfMotionParameter::ArmAngle => self.solve_psi_candidates(target, value)?,
            SelfMotionParameter::Q3 => self.solve_q3_candidates(target, value)?,
        };
        candidates.write_into(out);
        Ok(())
    }

    fn solve_near(&self, target: &Pose, q0: &[f64]) -> Result<Vec<Solution>> {
        self.solve_searching(target, self.value_of(q0))
    }

    fn solve_searching(&self, target: &Pose, prefer: f64) -> Result<Vec<Solution>> {
        SrsIk::solve_searching(self, target, prefer)
    }

    fn joint(&self) -> usize {
        2
    }

    fn choose(&self, target: &Pose, choice: &crate::ik::family::Choice) -> Result<Solution> {
        crate::ik::family::choose_on_grid(self.robot(), self, target, choice)
    }
}

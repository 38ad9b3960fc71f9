//! Any 6R arm, whatever its axes: a 2-D search over (q₁, q₂), the other
//! joints from subproblems, as IK-Geo does for a general 6R arm.
//!
//! Derivation (joints numbered 1…6, Eᵢ(θ) the turn about axis i, G the
//! motion the joints must make, so E₁…E₆ = G). Take a point y on axis 6
//! (fixed by E₆; chosen off axis 5). Then E₁…E₅(y) = G(y), and for given
//! q₁, q₂ the three joints 3, 4, 5 must carry y to
//! z = E₂⁻¹E₁⁻¹(G(y)) — a position problem of three skew axes:
//!
//! * (q₃, q₄, q₅) by **subproblem 5** ([`sp5`]): with pᵢ the point of
//!   axis i, E₃⁻¹(z) = E₄(E₅(y)) reads
//!   (p₃ − p₄) + rot(−h₃, q₃)(z − p₃) = rot(h₄, q₄)((p₅ − p₄) + rot(h₅, q₅)(y − p₅)),
//!   up to four solutions (a quartic: the *branches*).
//! * The orientation is then left with two conditions: with
//!   M = (R₁R₂R₃R₄R₅)ᵀR_G, which must equal R₆ = rot(h₆, q₆), M·h₆ = h₆. The
//!   error e(q₁, q₂) = |M·h₆ − h₆| of each branch vanishes exactly at the IK
//!   solutions (IK-Geo's alignment error).
//! * q₆ by **subproblem 1** (a vector ⊥ h₆ onto M times it).
//!
//! Finding the zeros: e is evaluated on a [`GRID`] × [`GRID`] grid over the
//! torus (−π, π]² (cell centres). A seed is a grid point whose branch has
//! an e no larger than the matching branch (nearest q₃…q₅) at its four
//! neighbours and at most `SLOPE_FACTOR` times the largest rise of e to
//! them (a minimum that is not a zero stands above its neighbours'
//! differences); at most [`MAX_SEEDS`], smallest e first, skipping seeds
//! within a grid step of a solution already found on its branch. Each seed
//! is refined by Newton's method on the branch's 2-D residual
//! (M·h₆ − h₆ on two vectors ⊥ h₆; finite-difference Jacobian, the branch
//! followed by nearest q₃…q₅, steps of at most one grid step, halved where
//! the branch ceases to exist); then q₆ by subproblem 1 and Newton's method
//! on the full pose (6 × 6 geometric Jacobian) to rounding level. Where the
//! 2-D iteration fails or finds a known solution — near the end of a
//! branch, where e is not smooth — the full-pose Newton starts from the raw
//! seed instead. Both iterations stop after [`NEWTON_ITERATIONS`] or when
//! they stop gaining. Converged configurations that reproduce the target
//! (product-of-exponentials FK, 1e-10 relative) are the solutions,
//! deduplicated to 1e-6 rad modulo 2π. The work is bounded: GRID²
//! subproblem-5 solves plus at most MAX_SEEDS refinements.
//!
//! A 6R arm has an even number of solutions unless two coincide, so an odd
//! count means one was missed — most often the partner of a solution found
//! within a grid step or two (near-singular targets, where solutions merge).
//! Then the seed search runs again on a grid [`FINE`] times finer around
//! each solution found, until the count is even.
//!
//! Missed still: two solutions close together on one branch when both are
//! missed (the count stays even), and zeros on a branch that exists only
//! between grid points. Labels `general-{1…16}` in the order found (a
//! general 6R arm has at most 16 solutions).

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use super::kin::{distance_to_line, parallel};
use super::subproblems::{rot, rotate, sp1, sp5};
use super::{candidates_with, reject, too_far, Common, GEOM_TOL};
use crate::error::Result;
use crate::ik::{wrap_angle, CandidateSet, Candidates, ClosedForm, Unreachable};
use crate::math::{rot_to_axis_angle, Pose};
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// Grid points per joint over one turn of q₁ and of q₂ (GRID² evaluations of
/// subproblem 5 per solve).
pub const GRID: usize = 48;

/// At most this many seeds are polished per solve.
pub const MAX_SEEDS: usize = 128;

/// Points per grid step of the finer search around the solutions found
/// when their count is odd, over [`NEAR_STEPS`] grid steps either side:
/// (2·FINE·NEAR_STEPS + 1)² evaluations of subproblem 5 per solution.
pub const FINE: usize = 6;

/// Grid steps either side of a solution that the finer search covers.
pub const NEAR_STEPS: usize = 2;

/// A seed's e may be at most this many times the largest rise of e to a
/// neighbouring grid point.
const SLOPE_FACTOR: f64 = 2.0;

/// Newton iterations per seed.
pub const NEWTON_ITERATIONS: usize = 24;

/// Largest step of the 2-D Newton iteration on (q₁, q₂) \[rad\]: one grid
/// step, so that it stays near its seed.
const MAX_STEP: f64 = std::f64::consts::TAU / GRID as f64;

const LABELS: [&str; 16] = [
    "general-1",
    "general-2",
    "general-3",
    "general-4",
    "general-5",
    "general-6",
    "general-7",
    "general-8",
    "general-9",
    "general-10",
    "general-11",
    "general-12",
    "general-13",
    "general-14",
    "general-15",
    "general-16",
];

/// The 2-D search solver for any 6R arm (see the [module documentation](self)).
/// Name `geo-general`.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::GeneralIk};
/// // A 6R arm with no intersecting or parallel axes.
/// let rows = [(0.3, 0.05, 80.0), (0.04, 0.4, 10.0), (0.06, 0.03, 95.0),
///             (0.35, 0.02, -85.0), (0.03, 0.04, 70.0), (0.1, 0.01, 0.0)];
/// let mut toml = String::from("name = \"skew6\"\nsource = \"made up\"\nconvention = \"standard\"\n[units]\nlength = \"m\"\nangle = \"deg\"\n");
/// for (i, (d, a, alpha)) in rows.iter().enumerate() {
///     toml += &format!("[[joint]]\nname = \"j{i}\"\nd = {d}\na = {a}\nalpha = {alpha}\nmin = -180\nmax = 180\n");
/// }
/// toml += "[poses]\nhome = [0, 0, 0, 0, 0, 0]\n";
/// let robot = kinema::Robot::from_toml_str(&toml, "skew6.toml")?;
/// let ik = GeneralIk::new(&robot)?;
/// let q = [0.3, 0.6, -2.5, 0.4, 0.7, -0.2];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?;
/// assert!(sols.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9));
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct GeneralIk {
    common: Common,
    /// The point on axis 6 carried by joints 1–5 \[m\].
    y: V3,
    /// A unit vector ⊥ h₆, for q₆.
    u6: V3,
    /// h₆ × u₆.
    w6: V3,
    /// A length of the arm \[m\], to weigh position against rotation.
    size: f64,
}

/// One grid point's branches: (e, q₃, q₄, q₅) each, e = ∞ where absent.
type Cell = [[f64; 4]; 4];

impl GeneralIk {
    /// Checks for six revolute joints whose consecutive axes never coincide
    /// (tolerance [`GEOM_TOL`]); any other structure is accepted, so this
    /// family comes after the closed forms in the registry.
    pub fn new(robot: &Robot) -> Result<Self> {
        let common = Common::new(robot, "geo-general")?;
        let (h, p) = (|i| common.h(i), |i| common.p(i));
        for i in 0..5 {
            if parallel(&h(i), &h(i + 1), GEOM_TOL) && distance_to_line(&p(i + 1), &p(i), &h(i)) <= GEOM_TOL {
                return reject("geo-general", robot, format!("axes {} and {} coincide", i + 1, i + 2));
            }
        }
        let mut size = 0.0f64;
        for i in 0..6 {
            size = size.max((p(i) - p(0)).norm()).max((common.kin.tool.pos - p(i)).norm());
        }
        let size = size.max(1e-3);
        // Any point of axis 6 will do; off axis 5, so that joint 5 moves it.
        let mut y = p(5);
        if distance_to_line(&y, &p(4), &h(4)) < 1e-3 * size {
            y += h(5) * size;
        }
        let h6 = h(5);
        let seed = if h6.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let u6 = (seed - h6 * h6.dot(&seed)).normalize();
        Ok(GeneralIk { common, y, u6, w6: h6.cross(&u6), size })
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// The branches at (q₁, q₂): up to four (q₃, q₄, q₅) by subproblem 5 and
    /// their e; `gy` = G(y), `gh` = R_G·h₆.
    fn cell(&self, gy: &V3, gh: &V3, q1: f64, q2: f64) -> Cell {
        let c = &self.common;
        let (h, p) = (|i| c.h(i), |i| c.p(i));
        let u = p(0) + rotate(&h(0), -q1, &(gy - p(0)));
        let z = p(1) + rotate(&h(1), -q2, &(u - p(1)));
        let s = sp5(&(p(2) - p(3)), &(-h(2)), &(z - p(2)), &h(3), &(p(4) - p(3)), &h(4), &(self.y - p(4)));
        let mut out = [[f64::INFINITY; 4]; 4];
        // M·h₆ = R₅ᵀR₄ᵀR₃ᵀR₂ᵀR₁ᵀ·R_G·h₆, turned one joint at a time.
        let v12 = rotate(&h(1), -q2, &rotate(&h(0), -q1, gh));
        for (k, t) in s.as_slice().iter().enumerate() {
            let v = rotate(&h(4), -t[2], &rotate(&h(3), -t[1], &rotate(&h(2), -t[0], &v12)));
            out[k] = [(v - h(5)).norm(), t[0], t[1], t[2]];
        }
        out
    }

    /// M = (R₁…R₅)ᵀ·R_G for R₁R₂ = `r12` and (q₃, q₄, q₅) = `t`.
    fn m(&self, g: &Pose, r12: &Matrix3<f64>, t: &[f64; 3]) -> Matrix3<f64> {
        let h = |i| self.common.h(i);
        (r12 * rot(&h(2), t[0]) * rot(&h(3), t[1]) * rot(&h(4), t[2])).transpose() * g.rot
    }

    /// The branch at (q₁, q₂) nearest to `near` (q₃, q₄, q₅), as the 2-D
    /// residual: M·h₆ − h₆ on two unit vectors ⊥ h₆.
    fn branch_near(&self, gy: &V3, gh: &V3, q1: f64, q2: f64, near: &[f64; 4]) -> Option<([f64; 2], [f64; 4])> {
        let cell = self.cell(gy, gh, q1, q2);
        let br = cell.iter().filter(|x| x[0].is_finite()).min_by(|x, y| dist3(x, near).total_cmp(&dist3(y, near)))?;
        let (h, w) = (|i| self.common.h(i), self.w6);
        // Recompute M·h₆ for the branch (the cell keeps only its norm).
        let v12 = rotate(&h(1), -q2, &rotate(&h(0), -q1, gh));
        let v = rotate(&h(4), -br[3], &rotate(&h(3), -br[2], &rotate(&h(2), -br[1], &v12)));
        Some(([self.u6.dot(&v), w.dot(&v)], *br))
    }

    /// Newton's method on the 2-D residual of one branch from a grid seed
    /// (finite-difference Jacobian, steps of at most [`MAX_STEP`]); the
    /// refined (q₁, q₂) and branch.
    fn refine(&self, gy: &V3, gh: &V3, q1: f64, q2: f64, br: [f64; 4]) -> ([f64; 2], [f64; 4]) {
        let (mut x, mut br) = ([q1, q2], br);
        let Some((mut f, _)) = self.branch_near(gy, gh, x[0], x[1], &br) else { return (x, br) };
        let mut stalled = 0;
        for _ in 0..NEWTON_ITERATIONS {
            let size = f[0].abs() + f[1].abs();
            if size <= 1e-13 {
                break;
            }
            const D: f64 = 1e-7;
            let Some((fa, _)) = self.branch_near(gy, gh, x[0] + D, x[1], &br) else { break };
            let Some((fb, _)) = self.branch_near(gy, gh, x[0], x[1] + D, &br) else { break };
            let j =
                nalgebra::Matrix2::new((fa[0] - f[0]) / D, (fb[0] - f[0]) / D, (fa[1] - f[1]) / D, (fb[1] - f[1]) / D);
            let Some(step) = j.lu().solve(&-nalgebra::Vector2::new(f[0], f[1])) else { break };
            // Where the branch exists only on a thin strip, halve the step
            // until it stays on it.
            let mut scale = (MAX_STEP / step.amax()).min(1.0);
            let mut landed = None;
            for _ in 0..8 {
                let next = [x[0] + scale * step[0], x[1] + scale * step[1]];
                if let Some(r) = self.branch_near(gy, gh, next[0], next[1], &br) {
                    landed = Some((next, r));
                    break;
                }
                scale *= 0.5;
            }
            let Some((next, (fn_, bn))) = landed else { break };
            // A minimum of e that is not a zero: Newton stops gaining.
            stalled = if fn_[0].abs() + fn_[1].abs() > 0.5 * size { stalled + 1 } else { 0 };
            (x, f, br) = (next, fn_, bn);
            if stalled == 2 {
                break;
            }
        }
        (x, br)
    }

    /// Newton's method on E₁…E₆(q) = G from `q`; whether it converged.
    fn polish(&self, g: &Pose, q: &mut [f64; 6]) -> bool {
        let kin = &self.common.kin;
        let x = kin.tool.pos;
        let target = g.transform_point(&x);
        let residual = |q: &[f64; 6]| -> (Vector6<f64>, f64) {
            let f = kin.fk(q) * self.common.tool0_inv;
            let dp = target - f.transform_point(&x);
            let dw = rot_to_axis_angle(&(g.rot * f.rot.transpose()));
            let r = Vector6::new(dp.x, dp.y, dp.z, dw.x, dw.y, dw.z);
            (r, dp.norm() / self.size + dw.norm())
        };
        let (mut r, mut err) = residual(q);
        let mut stalled = 0;
        for _ in 0..NEWTON_ITERATIONS {
            if err <= 1e-14 {
                return true;
            }
            // Far from a solution Newton wanders: give up when it stops gaining.
            if stalled == 5 {
                return false;
            }
            // Geometric Jacobian of the point x and the rotation, base frame.
            let mut jac = Matrix6::zeros();
            let mut t = Pose::IDENTITY;
            let mut frames = [(V3::zeros(), V3::zeros()); 6];
            for (i, frame) in frames.iter_mut().enumerate() {
                *frame = (t.rot * kin.h[i], t.transform_point(&kin.p[i]));
                t = t * kin.joint_motion(i, q[i]);
            }
            let fx = t.transform_point(&x);
            for (i, (w, o)) in frames.iter().enumerate() {
                let v = w.cross(&(fx - o));
                jac.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
                jac.fixed_view_mut::<3, 1>(3, i).copy_from(w);
            }
            let Some(step) = jac.lu().solve(&r) else { return false };
            let mut scale = 1.0;
            let mut improved = false;
            for _ in 0..4 {
                let mut next = *q;
                for i in 0..6 {
                    next[i] = wrap_angle(q[i] + scale * step[i]);
                }
                let (r2, e2) = residual(&next);
                if e2 < err {
                    stalled = if e2 > 0.5 * err { stalled + 1 } else { 0 };
                    (*q, r, err, improved) = (next, r2, e2, true);
                    break;
                }
                scale *= 0.5;
            }
            if !improved {
                return err <= 1e-12;
            }
        }
        err <= 1e-12
    }

    /// The kernel: every solution found (joint values and label) for
    /// `target`, FK-checked, or why there is none. Allocates one grid
    /// buffer (GRID² cells) per call.
    pub fn solve_candidates(&self, target: &Pose, out: &mut Candidates<6, 16>) -> std::result::Result<(), Unreachable> {
        let c = &self.common;
        let h = |i| c.h(i);
        let g = c.motion(target);
        let gy = g.transform_point(&self.y);
        if let Some(u) = too_far(&gy) {
            return Err(u);
        }
        let n = GRID;
        let step = std::f64::consts::TAU / n as f64;
        let at = |i: usize| -std::f64::consts::PI + (i as f64 + 0.5) * step;
        let gh = g.rot * h(5);
        let mut grid: Vec<Cell> = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                grid.push(self.cell(&gy, &gh, at(i), at(j)));
            }
        }
        // Seeds ([`is_seed`]) against the four neighbours on the torus.
        let mut seeds: Vec<(f64, usize, usize, usize)> = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let neighbours =
                    [(n - 1, 0), (1, 0), (0, n - 1), (0, 1)].map(|(di, dj)| &grid[(i + di) % n * n + (j + dj) % n]);
                for (b, br) in grid[i * n + j].iter().enumerate() {
                    if br[0].is_finite() && is_seed(br, neighbours) {
                        seeds.push((br[0], i, j, b));
                    }
                }
            }
        }
        seeds.sort_by(|a, b| a.0.total_cmp(&b.0));
        seeds.truncate(MAX_SEEDS);
        let scale = 1.0 + g.pos.norm();
        for &(_, i, j, b) in &seeds {
            if out.len() == 16 {
                break;
            }
            let raw = grid[i * n + j][b];
            // A seed within a grid step of a solution already found, on its
            // branch, would only find it again.
            let near = |q: &[f64; 6]| {
                wrap_angle(q[0] - at(i)).abs() < step
                    && wrap_angle(q[1] - at(j)).abs() < step
                    && (2..5).map(|k| wrap_angle(q[k] - raw[k - 1]).abs()).sum::<f64>() < 3.0 * step
            };
            if out.qs().iter().any(near) {
                continue;
            }
            // The 2-D iteration first; where it fails or meets a solution
            // already found (near the end of a branch of subproblem 5, where
            // e is not smooth), Newton on the full pose from the raw seed.
            let ([q1, q2], br) = self.refine(&gy, &gh, at(i), at(j), raw);
            if !self.finish(&g, scale, [q1, q2], &br, out) {
                self.finish(&g, scale, [at(i), at(j)], &raw, out);
            }
        }
        // A 6R arm has an even number of solutions unless two coincide, so an
        // odd count means one was missed: most often the partner of a
        // solution less than a grid step from it (a near-singular target).
        if out.len() % 2 == 1 {
            self.search_near_solutions(&g, &gy, &gh, scale, step, out);
        }
        if out.is_empty() {
            // The smallest alignment error of axis 6 over the grid is not a distance: no figure.
            return Err(Unreachable::NotReached {
                detail: "a search over (q1, q2) finds no configuration of the arm that meets it".into(),
            });
        }
        Ok(())
    }
}

impl GeneralIk {
    /// The seed search again around each solution found, on a grid
    /// [`FINE`] times finer over [`NEAR_STEPS`] grid steps either side of its
    /// (q₁, q₂), until the count is even (or 16).
    fn search_near_solutions(&self, g: &Pose, gy: &V3, gh: &V3, scale: f64, step: f64, out: &mut Candidates<6, 16>) {
        let half = FINE * NEAR_STEPS;
        let m = 2 * half + 1;
        let at = |k: usize| (k as f64 - half as f64) * step / FINE as f64;
        let found: Vec<[f64; 6]> = out.qs().to_vec();
        for q in found {
            let cells: Vec<Cell> = (0..m * m).map(|k| self.cell(gy, gh, q[0] + at(k / m), q[1] + at(k % m))).collect();
            for i in 1..m - 1 {
                for j in 1..m - 1 {
                    let neighbours = [(i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1)].map(|(a, b)| &cells[a * m + b]);
                    let (q1, q2) = (q[0] + at(i), q[1] + at(j));
                    for br in &cells[i * m + j] {
                        if !(br[0].is_finite() && is_seed(br, neighbours)) {
                            continue;
                        }
                        let (x, refined) = self.refine(gy, gh, q1, q2, *br);
                        if !self.finish(g, scale, x, &refined, out) {
                            self.finish(g, scale, [q1, q2], br, out);
                        }
                        if out.len() % 2 == 0 || out.len() == 16 {
                            return;
                        }
                    }
                }
            }
        }
    }

    /// The solution from (q₁, q₂) and branch `br`: q₆ by subproblem 1, Newton
    /// on the full pose, the FK check; pushes it if new. Whether it did.
    fn finish(&self, g: &Pose, scale: f64, q12: [f64; 2], br: &[f64; 4], out: &mut Candidates<6, 16>) -> bool {
        let c = &self.common;
        let h = |i| c.h(i);
        let t = [br[1], br[2], br[3]];
        let r12 = rot(&h(0), q12[0]) * rot(&h(1), q12[1]);
        let m = self.m(g, &r12, &t);
        let q6 = sp1(&h(5), &self.u6, &(m * self.u6)).first();
        let mut q = [q12[0], q12[1], t[0], t[1], t[2], q6];
        if !self.polish(g, &mut q) {
            return false;
        }
        let f = c.kin.fk(&q) * c.tool0_inv;
        if ((f.pos - g.pos).norm() / scale).max((f.rot - g.rot).norm()) > 1e-10 {
            return false;
        }
        let mut v = [0.0; 6];
        for (k, x) in v.iter_mut().enumerate() {
            *x = c.joint_value(k, q[k]);
        }
        if out.len() == 16 || out.qs().iter().any(|a| a.iter().zip(&v).all(|(x, y)| wrap_angle(x - y).abs() < 1e-6)) {
            return false;
        }
        out.push_unique(v, LABELS[out.len()], -1.0, false)
    }
}

/// Angular distance between the (q₃, q₄, q₅) of two branches.
/// Whether branch `br` of a grid point seeds a refinement: no larger than
/// the matching branch (nearest q₃…q₅) of each neighbour, and small against
/// how fast e changes there (at a zero e is about |∇e|·step; a minimum that
/// is not a zero stands above its neighbours' differences).
fn is_seed(br: &[f64; 4], neighbours: [&Cell; 4]) -> bool {
    let mut slope = 0.0f64;
    for nb in neighbours {
        let matched = nb.iter().filter(|x| x[0].is_finite()).min_by(|x, y| dist3(x, br).total_cmp(&dist3(y, br)));
        match matched {
            Some(m) if m[0] < br[0] => return false,
            Some(m) => slope = slope.max(m[0] - br[0]),
            // The branch ends next to this point: e may change steeply there.
            None => slope = f64::INFINITY,
        }
    }
    br[0] <= SLOPE_FACTOR * slope
}

fn dist3(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    (1..4).map(|k| wrap_angle(a[k] - b[k]).abs()).sum()
}

impl ClosedForm for GeneralIk {
    const NAME: &'static str = "geo-general";

    fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// Every solution the search finds (see the [module documentation](self)).
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        candidates_with(Self::NAME, target, out, |t, c| self.solve_candidates(t, c))
    }
}

impl crate::ik::family::Family for GeneralIk {}

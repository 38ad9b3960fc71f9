//! The static check: every statement once, loop bodies once, before anything runs.

use std::collections::HashMap;
use std::f64::consts::PI;

use kinema::ik;
use kinema::ik::family::SelfMotionParameter;
use kinema::traj::SelfMotion;

use crate::ast::{Expr, MotionKind, MotionOpts, Name, Stmt, StmtKind, Target};
use crate::diag::Diagnostic;
use crate::lexer::Span;
use crate::units::{Dim, Quantity};

use super::eval::{coerce, eval, joint_dim};
use super::scara::Scara;
use super::text::{joint_example, keyword_of, parse_profile};
use super::Compiler;

/// Names visible during the static check.
#[derive(Debug, Clone, Default)]
pub(super) struct Scope {
    /// POS names declared so far: joint (true) or Cartesian (false).
    positions: HashMap<String, bool>,
    /// FOR counters in scope.
    counters: Vec<String>,
    /// What each POS replaced (name, previous value), to undo a block's POS at its END
    /// without copying the scope for every block.
    undo: Vec<(String, Option<bool>)>,
}

impl Scope {
    fn declare(&mut self, key: &str, joint: bool) {
        let before = self.positions.insert(key.to_string(), joint);
        self.undo.push((key.to_string(), before));
    }

    /// Forgets the POS declared since `mark` (a length of `undo`).
    fn undo_to(&mut self, mark: usize) {
        while self.undo.len() > mark {
            let (key, before) = self.undo.pop().expect("longer than mark");
            match before {
                Some(j) => self.positions.insert(key, j),
                None => self.positions.remove(&key),
            };
        }
    }
}

/// Known positions named in the hint of an unknown one.
const KNOWN_LISTED: usize = 20;

/// Largest FOR bound: beyond 2⁵³ adding 1 to an `f64` may leave it unchanged.
const MAX_EXACT: f64 = 9_007_199_254_740_992.0;

/// How many passes `FOR i = a TO b` makes (0 when b < a).
pub(super) fn for_passes(a: f64, b: f64) -> f64 {
    if b < a {
        0.0
    } else {
        b - a + 1.0
    }
}

/// A value known at check time (FOR counters are NaN there) that fails `ok`.
pub(super) fn known_bad(v: f64, ok: impl Fn(f64) -> bool) -> bool {
    !v.is_nan() && !ok(v)
}

impl Compiler<'_> {
    pub(super) fn static_block(&mut self, stmts: &[Stmt], scope: &mut Scope) {
        for s in stmts {
            self.static_stmt(s, scope);
        }
    }

    /// Checks one statement: each kind has a function of its own.
    fn static_stmt(&mut self, s: &Stmt, scope: &mut Scope) {
        match &s.kind {
            StmtKind::Pos { name, value } => self.static_pos(name, value, scope),
            StmtKind::Motion { kind, relative, target, opts } => {
                self.static_motion(s, *kind, *relative, target, opts, scope)
            }
            StmtKind::Circ { aux, target, opts } => {
                self.static_target(aux, scope);
                self.static_target(target, scope);
                self.static_opts(opts, false, scope);
                self.static_cartesian_capable(s);
            }
            StmtKind::Speed(e) => self.static_speed(e, scope),
            StmtKind::Vel(e) | StmtKind::Acc(e) | StmtKind::JVel(e) | StmtKind::JAcc(e) => {
                self.static_limit(&s.kind, e, scope)
            }
            StmtKind::Profile(name) => self.static_profile(name),
            StmtKind::Redundancy { mode, value } => self.static_redundancy(mode, value.as_ref(), scope),
            StmtKind::Tool(t) | StmtKind::Base(t) => self.static_frame(t, scope),
            StmtKind::Wait(e) => self.static_wait(e, scope),
            StmtKind::Home(e) => {
                if let Some(e) = e {
                    self.static_time(e, scope);
                }
            }
            StmtKind::Loop { count, body } => self.static_loop(s, count, body, scope),
            StmtKind::For { var, from, to, body } => self.static_for(s, var, from, to, body, scope),
            StmtKind::MoveZ { dz, time } | StmtKind::MoveTita { dtheta: dz, time } => {
                self.static_scara(s);
                let (dim, scale) = if matches!(s.kind, StmtKind::MoveZ { .. }) {
                    (Dim::Length, 1e-3)
                } else {
                    (Dim::Angle, PI / 180.0)
                };
                self.static_expect(dz, dim, Some(scale), scope);
                self.static_time(time, scope);
            }
            StmtKind::MoveXy { dx, dy, time } => {
                self.static_scara(s);
                self.static_expect(dx, Dim::Length, Some(1e-3), scope);
                self.static_expect(dy, Dim::Length, Some(1e-3), scope);
                self.static_time(time, scope);
            }
        }
    }

    /// POS name = target: declared in the scope.
    fn static_pos(&mut self, name: &Name, value: &Target, scope: &mut Scope) {
        if let Some(joint) = self.static_target(value, scope) {
            if scope.counters.contains(&name.key) {
                self.err(Diagnostic::error(name.span.clone(), format!("`{}` is a FOR counter here", name.text)));
            }
            scope.declare(&name.key, joint);
        }
    }

    /// PTP and LIN, absolute or REL.
    fn static_motion(
        &mut self,
        s: &Stmt,
        kind: MotionKind,
        relative: bool,
        target: &Target,
        opts: &MotionOpts,
        scope: &Scope,
    ) {
        if relative {
            if let Target::Named(nm) = target {
                self.err(
                    Diagnostic::error(nm.span.clone(), "REL needs an offset written out, not a named position")
                        .with_hint("write e.g. LIN REL CART(0mm, 0mm, -50mm)"),
                );
            }
            if kind == MotionKind::Lin && matches!(target, Target::Joint(..)) {
                self.err(Diagnostic::error(target.span(), "LIN REL takes a Cartesian offset CART(...)"));
            }
        }
        self.static_target(target, scope);
        self.static_opts(opts, kind == MotionKind::Ptp, scope);
        if kind == MotionKind::Lin {
            self.static_cartesian_capable(s);
        }
    }

    fn static_speed(&mut self, e: &Expr, scope: &Scope) {
        if let Some(v) = self.static_expect(e, Dim::Percent, None, scope) {
            if known_bad(v, |v| v > 0.0 && v <= 1.0) {
                self.err(Diagnostic::error(e.span(), format!("SPEED must be in (0 %, 100 %], not {} %", v * 100.0)));
            }
        }
    }

    /// VEL, ACC, JVEL, JACC: a velocity or an acceleration (ACC also a percentage).
    // Range checks read better inside their match arm than folded into its guard.
    #[allow(clippy::collapsible_match)]
    fn static_limit(&mut self, kind: &StmtKind, e: &Expr, scope: &Scope) {
        let is_vel = matches!(kind, StmtKind::Vel(_) | StmtKind::JVel(_));
        let dims = if is_vel { [Dim::LinVel, Dim::AngVel] } else { [Dim::LinAcc, Dim::AngAcc] };
        let percent_ok = matches!(kind, StmtKind::Acc(_));
        match self.static_eval(e, scope) {
            Some(q) if percent_ok && q.dim == Dim::Percent => {
                if known_bad(q.value, |v| v > 0.0 && v <= 1.0) {
                    self.err(Diagnostic::error(
                        e.span(),
                        format!("ACC must be in (0 %, 100 %], not {} %", q.value * 100.0),
                    ));
                }
            }
            Some(q) if dims.contains(&q.dim) => {
                if known_bad(q.value, |v| v > 0.0) {
                    self.err(Diagnostic::error(e.span(), "must be positive"));
                }
            }
            Some(q) => self.err(Diagnostic::error(
                e.span(),
                format!(
                    "expected {} or {}{}, found {}",
                    dims[0],
                    dims[1],
                    if percent_ok { " or a percentage (%)" } else { "" },
                    q.dim
                ),
            )),
            None => {}
        }
    }

    fn static_profile(&mut self, name: &Name) {
        if parse_profile(&name.key).is_none() {
            self.err(
                Diagnostic::error(name.span.clone(), format!("unknown profile `{}`", name.text))
                    .with_hint("profiles: trapezoid, scurve, quintic, cubic"),
            );
        }
    }

    fn static_redundancy(&mut self, mode: &Name, value: Option<&Expr>, scope: &Scope) {
        match value {
            None => {
                if mode.key.parse::<f64>().is_ok()
                    || SelfMotion::parse(SelfMotionParameter::Q3, &mode.key, 1.0).is_err()
                {
                    self.err(
                        Diagnostic::error(mode.span.clone(), format!("unknown self-motion policy `{}`", mode.text))
                            .with_hint(
                            "policies: hold, track, manipulability, avoid-limits, auto; or q3 = 30deg, psi = 0.5rad",
                        ),
                    );
                }
            }
            Some(e) => {
                if mode.key.parse::<SelfMotionParameter>().is_err() {
                    self.err(
                        Diagnostic::error(mode.span.clone(), format!("`{}` is not a self-motion parameter", mode.text))
                            .with_hint("a value is given for q3 or psi: REDUNDANCY q3 = 30deg"),
                    );
                }
                self.static_expect(e, Dim::Angle, None, scope);
            }
        }
    }

    /// TOOL and BASE: a Cartesian frame.
    fn static_frame(&mut self, t: &Target, scope: &Scope) {
        if !matches!(t, Target::Cart(..)) && !matches!(t, Target::Named(_)) {
            self.err(Diagnostic::error(t.span(), "a frame is written CART(x, y, z, roll, pitch, yaw)"));
        }
        if let Some(true) = self.static_target(t, scope) {
            self.err(Diagnostic::error(t.span(), "a frame must be a Cartesian position, not joint values"));
        }
    }

    fn static_wait(&mut self, e: &Expr, scope: &Scope) {
        if let Some(v) = self.static_expect(e, Dim::Time, Some(1.0), scope) {
            if v < 0.0 {
                self.err(Diagnostic::error(e.span(), "a wait cannot be negative"));
            }
        }
    }

    /// LOOP: the count, then the body once (its POS forgotten at END).
    fn static_loop(&mut self, s: &Stmt, count: &Expr, body: &[Stmt], scope: &mut Scope) {
        if let Some(v) = self.static_expect(count, Dim::None, None, scope) {
            if self.check_count(v, count.span()) && !v.is_nan() {
                self.check_passes(s, v, 0);
            }
        }
        let mark = scope.undo.len();
        self.static_block(body, scope);
        scope.undo_to(mark);
    }

    /// FOR: the bounds, then the body once with the counter in scope.
    fn static_for(&mut self, s: &Stmt, var: &Name, from: &Expr, to: &Expr, body: &[Stmt], scope: &mut Scope) {
        let mut bounds = [None, None];
        for (k, e) in [from, to].into_iter().enumerate() {
            if let Some(v) = self.static_expect(e, Dim::None, None, scope) {
                if self.check_bound(v, e.span()) && !v.is_nan() {
                    bounds[k] = Some(v);
                }
            }
        }
        if let [Some(a), Some(b)] = bounds {
            if self.check_passes(s, for_passes(a, b), 0) {
                self.check_exact(s, a, b);
            }
        }
        let mark = scope.undo.len();
        scope.counters.push(var.key.clone());
        self.static_block(body, scope);
        scope.counters.pop();
        scope.undo_to(mark);
    }

    /// Whether a LOOP count is fine (or unknown); the error if not.
    pub(super) fn check_count(&mut self, v: f64, span: Span) -> bool {
        if known_bad(v, |v| v >= 1.0 && v.fract() == 0.0) {
            self.err(
                Diagnostic::error(span, format!("a loop count must be a positive whole number, not {v}"))
                    .with_hint("LOOP 3 repeats its body three times"),
            );
            return false;
        }
        true
    }

    /// Whether a FOR bound is fine (or unknown): a whole number.
    pub(super) fn check_bound(&mut self, v: f64, span: Span) -> bool {
        if known_bad(v, |v| v.fract() == 0.0) {
            self.err(Diagnostic::error(span, format!("FOR bounds are whole numbers, not {v}")));
            return false;
        }
        true
    }

    /// Whether FOR bounds (known, whole, and few passes apart) are small enough that
    /// counting up by one from the first is exact.
    pub(super) fn check_exact(&mut self, s: &Stmt, a: f64, b: f64) -> bool {
        if a.abs() <= MAX_EXACT && b.abs() <= MAX_EXACT {
            return true;
        }
        self.err(Diagnostic::error(
            s.keyword.clone(),
            format!("FOR bounds must lie within ±{MAX_EXACT} (where whole numbers are exact), not {a} and {b}"),
        ));
        false
    }

    /// Refuses loop `s` when its `passes` alone exceed the steps left after `used`
    /// (each pass costs one step): it could never finish.
    pub(super) fn check_passes(&mut self, s: &Stmt, passes: f64, used: usize) -> bool {
        let left = self.opts.max_steps.saturating_sub(used);
        if passes <= left as f64 {
            return true;
        }
        let kw = keyword_of(&s.kind);
        let left_text = if used == 0 { String::new() } else { format!(" ({left} left at this point)") };
        self.err(
            Diagnostic::error(
                s.keyword.clone(),
                format!(
                    "this {kw} makes {passes} passes, more than the step limit of {} allows{left_text}; it is not run",
                    self.opts.max_steps
                ),
            )
            .with_hint("every statement run and every pass of a loop, empty or not, counts one step"),
        );
        self.stopped = true;
        false
    }

    fn static_time(&mut self, e: &Expr, scope: &Scope) {
        if let Some(v) = self.static_expect(e, Dim::Time, Some(1.0), scope) {
            if known_bad(v, |v| v > 0.0) {
                self.err(Diagnostic::error(e.span(), format!("a duration must be positive, not {v} s")));
            }
        }
    }

    fn static_scara(&mut self, s: &Stmt) {
        if matches!(self.scara, Scara::No) {
            self.err(
                Diagnostic::error(
                    s.keyword.clone(),
                    format!(
                        "{} is an instruction of the SCARA on a rail (seed 003); `{}` is not one",
                        keyword_of(&s.kind),
                        self.robot.name()
                    ),
                )
                .with_hint("run it with --robot scara5, or use PTP/LIN with CART(...) targets"),
            );
        }
    }

    fn static_cartesian_capable(&mut self, s: &Stmt) {
        if self.robot.dof() < 6 && ik::analytic_solver(self.robot).is_none() {
            self.err(Diagnostic::error(
                s.keyword.clone(),
                format!(
                    "`{}` has {} joints and no closed-form solver: it cannot follow a Cartesian line in position and orientation",
                    self.robot.name(),
                    self.robot.dof()
                ),
            ));
        }
    }

    #[allow(clippy::collapsible_match)]
    fn static_opts(&mut self, o: &MotionOpts, ptp: bool, scope: &Scope) {
        if let Some(d) = &o.duration {
            self.static_time(d, scope);
        }
        if let Some(at) = &o.avoid {
            if !ptp {
                self.err(
                    Diagnostic::error(at.clone(), "AVOID applies to PTP only")
                        .with_hint("a LIN or CIRC keeps its tool path; plan around obstacles with `PTP … AVOID`"),
                );
            } else if o.duration.is_some() {
                self.err(
                    Diagnostic::error(at.clone(), "AVOID cannot be combined with IN")
                        .with_hint("a path around obstacles is timed under the joint limits (JVEL, JACC, SPEED)"),
                );
            }
        }
        if let Some(b) = &o.blend {
            match self.static_eval(b, scope) {
                Some(q) if q.dim == Dim::Length || q.dim == Dim::Time => {
                    if known_bad(q.value, |v| v >= 0.0) {
                        self.err(Diagnostic::error(b.span(), "a blend cannot be negative"));
                    }
                }
                Some(q) => self.err(
                    Diagnostic::error(b.span(), format!("BLEND takes a length or a time, found {}", q.dim))
                        .with_hint("BLEND 20mm starts the next motion when 20 mm of this one are left; BLEND 0.2s, 0.2 s before its end"),
                ),
                None => {}
            }
        }
    }

    /// Checks a target; `Some(true)` for joint values, `Some(false)` for a pose.
    fn static_target(&mut self, t: &Target, scope: &Scope) -> Option<bool> {
        let n = self.robot.dof();
        match t {
            Target::Named(name) => {
                if let Some(j) = scope.positions.get(&name.key) {
                    return Some(*j);
                }
                if self.robot.pose(&name.key).is_ok() {
                    return Some(true);
                }
                // At most a few names (a program of thousands of positions and typos
                // would otherwise list them all at each typo).
                let total = scope.positions.len() + self.robot.poses().len();
                let mut known: Vec<String> = scope
                    .positions
                    .keys()
                    .cloned()
                    .chain(self.robot.poses().iter().map(|p| p.name.clone()))
                    .take(KNOWN_LISTED)
                    .collect();
                if total > KNOWN_LISTED {
                    known.push(format!("and {} more", total - KNOWN_LISTED));
                }
                let hint = if known.is_empty() {
                    "declare it first: POS name = CART(...) or JOINT(...)".to_string()
                } else {
                    format!("known positions: {}; declare new ones with POS name = ...", known.join(", "))
                };
                self.err(
                    Diagnostic::error(name.span.clone(), format!("unknown position `{}`", name.text)).with_hint(hint),
                );
                None
            }
            Target::Joint(items, span) => {
                if items.len() != n {
                    self.err(
                        Diagnostic::error(
                            span.clone(),
                            format!("JOINT has {} values; `{}` has {n} joints", items.len(), self.robot.name()),
                        )
                        .with_hint(format!("write {n} values, e.g. JOINT({})", joint_example(self.robot))),
                    );
                }
                for (i, e) in items.iter().enumerate() {
                    let dim = joint_dim(self.robot, i);
                    self.static_expect(e, dim, None, scope);
                }
                Some(true)
            }
            Target::Cart(items, span) => {
                if items.len() != 3 && items.len() != 6 {
                    self.err(
                        Diagnostic::error(
                            span.clone(),
                            format!("CART has {} values; it takes x, y, z or x, y, z, roll, pitch, yaw", items.len()),
                        )
                        .with_hint("e.g. CART(500mm, 0mm, 400mm, 0deg, 180deg, 0deg)"),
                    );
                }
                for (i, e) in items.iter().enumerate() {
                    let dim = if i < 3 { Dim::Length } else { Dim::Angle };
                    self.static_expect(e, dim, None, scope);
                }
                Some(false)
            }
        }
    }

    /// Evaluates with FOR counters unknown (NaN); reports unknown names and
    /// unit errors.
    fn static_eval(&mut self, e: &Expr, scope: &Scope) -> Option<Quantity> {
        let counters: HashMap<String, f64> = scope.counters.iter().map(|c| (c.clone(), f64::NAN)).collect();
        match eval(e, &counters) {
            Ok(q) => Some(q),
            Err(d) => {
                self.err(d);
                None
            }
        }
    }

    /// The value in SI of an expression of dimension `dim`; a plain number
    /// takes `default_scale` (the seed's mm, degrees and seconds) or, without
    /// one, is only accepted when it is 0.
    fn static_expect(&mut self, e: &Expr, dim: Dim, default_scale: Option<f64>, scope: &Scope) -> Option<f64> {
        let q = self.static_eval(e, scope)?;
        match coerce(q, dim, default_scale, e) {
            Ok(v) => Some(v),
            Err(d) => {
                self.err(d);
                None
            }
        }
    }
}

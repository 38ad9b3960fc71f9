//! Execution: statements in order, loops unrolled, each step counted.

use crate::ast::{Expr, MotionKind, Name, Program, Stmt, StmtKind, Target};
use crate::diag::Diagnostic;
use crate::stop::StopReason;
use crate::units::Dim;

use super::check::for_passes;
use super::eval::{coerce, eval};
use super::Compiler;

impl Compiler<'_> {
    pub(super) fn run(&mut self, program: &Program) {
        self.block(&program.stmts);
        self.flush_chain();
        if self.errors.is_empty() {
            self.check_trajectory();
        }
    }

    fn block(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            if !self.step(s) {
                return;
            }
            self.stmt(s);
        }
    }

    /// Counts one step at `s` (a statement, or a pass of the loop `s`) and looks at the
    /// stop; false, with the one error that says why, when the run must end here.
    fn step(&mut self, s: &Stmt) -> bool {
        if self.stopped {
            return false;
        }
        self.steps += 1;
        if let Some(why) = self.opts.stop.reason() {
            self.stop_here(s, why);
            return false;
        }
        if self.steps > self.opts.max_steps {
            self.err(
                Diagnostic::error(
                    s.keyword.clone(),
                    format!(
                        "the program executes more than {} statements (the step limit; loop passes counted); it is cut here",
                        self.opts.max_steps
                    ),
                )
                .with_hint("every statement run and every pass of a loop, empty or not, counts one step"),
            );
            self.stopped = true;
            return false;
        }
        true
    }

    fn stop_here(&mut self, s: &Stmt, why: StopReason) {
        self.err(Diagnostic::error(s.keyword.clone(), format!("stopped here: {why}")));
        self.stopped = true;
    }

    pub(super) fn value(&mut self, e: &Expr, dim: Dim, default_scale: Option<f64>) -> Option<f64> {
        match eval(e, &self.counters).and_then(|q| coerce(q, dim, default_scale, e)) {
            Ok(v) => Some(v),
            Err(d) => {
                self.err(d);
                None
            }
        }
    }

    /// Runs one statement: each kind has a function of its own.
    fn stmt(&mut self, s: &Stmt) {
        // A statement that is not a blended Cartesian motion ends the chain.
        let continues_chain = matches!(s.kind, StmtKind::Motion { kind: MotionKind::Lin, .. } | StmtKind::Circ { .. })
            || matches!(
                s.kind,
                StmtKind::Pos { .. }
                    | StmtKind::Speed(_)
                    | StmtKind::Vel(_)
                    | StmtKind::Acc(_)
                    | StmtKind::JVel(_)
                    | StmtKind::JAcc(_)
            );
        if !continues_chain {
            self.flush_chain();
        }
        match &s.kind {
            StmtKind::Pos { name, value } => self.declare_pos(name, value),
            StmtKind::Motion { kind: MotionKind::Ptp, relative, target, opts } => self.ptp(s, *relative, target, opts),
            StmtKind::Motion { kind: MotionKind::Lin, relative, target, opts } => self.lin(s, *relative, target, opts),
            StmtKind::Circ { aux, target, opts } => self.circ(s, aux, target, opts),
            StmtKind::Speed(e) => self.set_speed(e),
            StmtKind::Vel(e) | StmtKind::Acc(e) | StmtKind::JVel(e) | StmtKind::JAcc(e) => self.set_limit(&s.kind, e),
            StmtKind::Profile(name) => self.set_profile(name),
            StmtKind::Redundancy { mode, value } => self.set_redundancy(mode, value.as_ref()),
            StmtKind::Tool(t) => self.set_tool(t),
            StmtKind::Base(t) => self.set_base(t),
            StmtKind::Wait(e) => self.wait(s, e),
            StmtKind::Home(e) => self.home(s, e.as_ref()),
            StmtKind::Loop { count, body } => self.run_loop(s, count, body),
            StmtKind::For { var, from, to, body } => self.run_for(s, var, from, to, body),
            StmtKind::MoveZ { dz, time } => self.move_z(s, dz, time),
            StmtKind::MoveTita { dtheta, time } => self.move_tita(s, dtheta, time),
            StmtKind::MoveXy { dx, dy, time } => self.move_xy(s, dx, dy, time),
        }
    }

    /// POS name = target.
    fn declare_pos(&mut self, name: &Name, value: &Target) {
        if let Some(v) = self.resolve(value) {
            self.positions.insert(name.key.clone(), v);
        }
    }

    /// WAIT t: the robot stands still.
    fn wait(&mut self, s: &Stmt, e: &Expr) {
        if let Some(t) = self.value(e, Dim::Time, Some(1.0)) {
            if t < 0.0 {
                self.err(Diagnostic::error(e.span(), format!("a wait cannot be negative ({t} s)")));
            } else {
                self.hold(s, t, "WAIT");
            }
        }
    }

    /// LOOP n … END.
    fn run_loop(&mut self, s: &Stmt, count: &Expr, body: &[Stmt]) {
        let Some(n) = self.value(count, Dim::None, None) else { return };
        let counted = self.check_count(n, count.span()) && !n.is_nan();
        if !(counted && self.check_passes(s, n, self.steps)) {
            return;
        }
        // Each pass is a step, so an empty body ends at the step limit too.
        for _ in 0..(n as u64) {
            if !self.step(s) {
                return;
            }
            self.block(body);
        }
    }

    /// FOR var = from TO to … END.
    fn run_for(&mut self, s: &Stmt, var: &Name, from: &Expr, to: &Expr, body: &[Stmt]) {
        let (Some(a), Some(b)) = (self.value(from, Dim::None, None), self.value(to, Dim::None, None)) else {
            return;
        };
        let whole = self.check_bound(a, from.span()) && self.check_bound(b, to.span());
        if !(whole && self.check_passes(s, for_passes(a, b), self.steps) && self.check_exact(s, a, b)) {
            return;
        }
        let saved = self.counters.get(&var.key).copied();
        // Both bounds are whole and within ±2⁵³, so i takes every value exactly.
        let mut i = a;
        while i <= b && self.step(s) {
            self.counters.insert(var.key.clone(), i);
            self.block(body);
            i += 1.0;
        }
        match saved {
            Some(v) => self.counters.insert(var.key.clone(), v),
            None => self.counters.remove(&var.key),
        };
    }
}

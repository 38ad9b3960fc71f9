//! The syntax tree of a program (see `docs/language.md` for the grammar).

use crate::lexer::Span;

/// A whole program: its statements in order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Program {
    /// Top-level statements.
    pub stmts: Vec<Stmt>,
}

/// A name as written, with its place. Names compare in lower case.
#[derive(Debug, Clone, PartialEq)]
pub struct Name {
    /// The name in lower case.
    pub key: String,
    /// As written.
    pub text: String,
    /// Where.
    pub span: Span,
}

/// A statement and its place (from its keyword to its last token).
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    /// What it says.
    pub kind: StmtKind,
    /// Where.
    pub span: Span,
    /// The keyword's place.
    pub keyword: Span,
}

/// PTP (joint-space) or LIN (straight line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// Point to point in joint space.
    Ptp,
    /// Straight line in Cartesian space.
    Lin,
}

/// Options after a motion's target.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MotionOpts {
    /// `BLEND d` (a length: blend when this much path is left; or a time).
    pub blend: Option<Expr>,
    /// `IN t`: the motion lasts exactly t.
    pub duration: Option<Expr>,
    /// `AVOID` (PTP only): where it is written. With a collision check, a
    /// straight motion that collides is replaced by a planned path around
    /// the obstacles.
    pub avoid: Option<Span>,
}

/// Every kind of statement.
#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    /// `POS name = target`: a named position.
    Pos {
        /// Its name.
        name: Name,
        /// Its value.
        value: Target,
    },
    /// `PTP|LIN [REL] target [BLEND d] [IN t]`.
    Motion {
        /// PTP or LIN.
        kind: MotionKind,
        /// `REL`: the target is an offset from where the robot is.
        relative: bool,
        /// Where to.
        target: Target,
        /// BLEND, IN.
        opts: MotionOpts,
    },
    /// `CIRC aux, target [BLEND d] [IN t]`: an arc through `aux` to `target`.
    Circ {
        /// A point on the arc (only its position is used).
        aux: Target,
        /// The end of the arc.
        target: Target,
        /// BLEND, IN.
        opts: MotionOpts,
    },
    /// `SPEED p%`: velocity override of every later motion.
    Speed(Expr),
    /// `VEL v`: Cartesian speed, linear (m/s, mm/s) or angular (deg/s, rad/s).
    Vel(Expr),
    /// `ACC a`: Cartesian acceleration, linear (m/s², mm/s²) or angular; or
    /// `ACC p%`, an acceleration override of every later motion.
    Acc(Expr),
    /// `JVEL v`: joint speed for PTP, angular (revolute joints) or linear
    /// (prismatic joints), capped by the robot's own limits.
    JVel(Expr),
    /// `JACC a`: joint acceleration for PTP, as `JVEL`.
    JAcc(Expr),
    /// `PROFILE name`: the time law of later motions.
    Profile(Name),
    /// `REDUNDANCY policy` (`hold`, `track`, `manipulability`,
    /// `avoid-limits`, `auto`) or `REDUNDANCY q3 = angle` / `psi = angle`:
    /// the self-motion of a redundant arm in later LIN and CIRC motions.
    Redundancy {
        /// The policy, or the parameter a value is given for.
        mode: Name,
        /// The value, after `=`.
        value: Option<Expr>,
    },
    /// `TOOL target`: the tool frame (flange → tool point) of later motions.
    Tool(Target),
    /// `BASE target`: the frame later Cartesian targets are written in.
    Base(Target),
    /// `WAIT t` or `PAUSE t`: stand still.
    Wait(Expr),
    /// `HOME [t]`: PTP to the robot's home pose (in t when given).
    Home(Option<Expr>),
    /// `LOOP n … END`.
    Loop {
        /// How many times.
        count: Expr,
        /// What is repeated.
        body: Vec<Stmt>,
    },
    /// `FOR i = a TO b … END` (i takes a, a+1, …, b).
    For {
        /// The counter, usable in expressions inside.
        var: Name,
        /// First value.
        from: Expr,
        /// Last value.
        to: Expr,
        /// What is repeated.
        body: Vec<Stmt>,
    },
    /// Seed 003: `MOVEZ dz, t` (mm by default).
    MoveZ {
        /// Vertical offset.
        dz: Expr,
        /// Duration (s by default).
        time: Expr,
    },
    /// Seed 003: `MOVETITA dθ, t` (degrees by default).
    MoveTita {
        /// Turn of the tool about the vertical.
        dtheta: Expr,
        /// Duration.
        time: Expr,
    },
    /// Seed 003: `MOVEXY dx, dy, t` (mm by default).
    MoveXy {
        /// Offset along x.
        dx: Expr,
        /// Offset along y.
        dy: Expr,
        /// Duration.
        time: Expr,
    },
}

/// A position: by name, joint values, or a Cartesian pose.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A name declared with POS (or a named pose of the robot such as `home`).
    Named(Name),
    /// `JOINT(q1, …, qn)`.
    Joint(Vec<Expr>, Span),
    /// `CART(x, y, z [, roll, pitch, yaw])`.
    Cart(Vec<Expr>, Span),
}

impl Target {
    /// Where it is written.
    pub fn span(&self) -> Span {
        match self {
            Target::Named(n) => n.span.clone(),
            Target::Joint(_, s) | Target::Cart(_, s) => s.clone(),
        }
    }
}

/// Arithmetic operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// +
    Add,
    /// −
    Sub,
    /// ×
    Mul,
    /// ÷
    Div,
}

/// An expression: numbers with units, loop counters, arithmetic.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A literal with its unit as written (lower case).
    Num {
        /// The number as written.
        value: f64,
        /// Its unit.
        unit: Option<String>,
        /// Where.
        span: Span,
    },
    /// A FOR counter.
    Var(Name),
    /// −e
    Neg(Box<Expr>, Span),
    /// a op b
    Bin {
        /// Which.
        op: BinOp,
        /// Left side.
        lhs: Box<Expr>,
        /// Right side.
        rhs: Box<Expr>,
        /// Where (both sides).
        span: Span,
    },
}

impl Expr {
    /// Where it is written.
    pub fn span(&self) -> Span {
        match self {
            Expr::Num { span, .. } | Expr::Neg(_, span) | Expr::Bin { span, .. } => span.clone(),
            Expr::Var(n) => n.span.clone(),
        }
    }
}

//! Joint-space curves from expressions of time (seed 001 §4.2:
//! θ1 = 3·sin(4π·t²/2)).
//!
//! The expression language: numbers (`2`, `0.5`, `1e-3`), the variable `t`
//! \[s\], the constants `pi` and `e`, `+ - * /`, powers `^` or `**` (right
//! associative, binding tighter than a leading minus: `-t^2` = −(t²)),
//! parentheses, and the functions `sin cos tan asin acos atan sinh cosh tanh
//! exp ln log10 sqrt abs floor ceil` of one argument and `atan2 min max pow`
//! of two. Names are case-insensitive. Velocities and accelerations are
//! computed by differentiating the parsed expression symbolically.

use std::fmt;

use super::{sample_times, JointTrajectory};
use crate::error::{Error, InputError, Result};
use crate::robot::Robot;

/// A parsed expression of `t`.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    node: Node,
    text: String,
}

#[derive(Debug, Clone, PartialEq)]
enum Node {
    Num(f64),
    T,
    Neg(Box<Node>),
    Add(Box<Node>, Box<Node>),
    Sub(Box<Node>, Box<Node>),
    Mul(Box<Node>, Box<Node>),
    Div(Box<Node>, Box<Node>),
    Pow(Box<Node>, Box<Node>),
    Call(Func, Vec<Node>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Ln,
    Log10,
    Sqrt,
    Abs,
    Floor,
    Ceil,
    Atan2,
    Min,
    Max,
}

const FUNCS: [(&str, Func, usize); 20] = [
    ("sin", Func::Sin, 1),
    ("cos", Func::Cos, 1),
    ("tan", Func::Tan, 1),
    ("asin", Func::Asin, 1),
    ("acos", Func::Acos, 1),
    ("atan", Func::Atan, 1),
    ("sinh", Func::Sinh, 1),
    ("cosh", Func::Cosh, 1),
    ("tanh", Func::Tanh, 1),
    ("exp", Func::Exp, 1),
    ("ln", Func::Ln, 1),
    ("log", Func::Ln, 1),
    ("log10", Func::Log10, 1),
    ("sqrt", Func::Sqrt, 1),
    ("abs", Func::Abs, 1),
    ("floor", Func::Floor, 1),
    ("ceil", Func::Ceil, 1),
    ("atan2", Func::Atan2, 2),
    ("min", Func::Min, 2),
    ("max", Func::Max, 2),
];

/// A syntax error at byte `col` of `text`: the 1-based column (in
/// characters) and what was expected.
fn syntax(text: &str, col: usize, message: String) -> Error {
    let column = text.get(..col.min(text.len())).map_or(col, |s| s.chars().count()) + 1;
    Error::Input(InputError::Syntax { what: "expression".into(), text: text.into(), column, expected: message })
}

struct Parser<'a> {
    text: &'a str,
    bytes: &'a [u8],
    pos: usize,
    depth: usize,
}

impl Parser<'_> {
    fn skip(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip();
        self.bytes.get(self.pos).copied()
    }

    fn err(&self, message: impl Into<String>) -> Error {
        syntax(self.text, self.pos, message.into())
    }

    fn expr(&mut self) -> Result<Node> {
        self.depth += 1;
        if self.depth > 200 {
            return Err(self.err("the expression is nested too deeply"));
        }
        let mut left = self.term()?;
        while let Some(c @ (b'+' | b'-')) = self.peek() {
            self.pos += 1;
            let right = self.term()?;
            left = if c == b'+' { Node::Add(left.into(), right.into()) } else { Node::Sub(left.into(), right.into()) };
        }
        self.depth -= 1;
        Ok(left)
    }

    fn term(&mut self) -> Result<Node> {
        let mut left = self.unary()?;
        loop {
            match self.peek() {
                Some(b'*') if self.bytes.get(self.pos + 1) != Some(&b'*') => {
                    self.pos += 1;
                    left = Node::Mul(left.into(), self.unary()?.into());
                }
                Some(b'/') => {
                    self.pos += 1;
                    left = Node::Div(left.into(), self.unary()?.into());
                }
                _ => return Ok(left),
            }
        }
    }

    fn unary(&mut self) -> Result<Node> {
        self.depth += 1;
        if self.depth > 200 {
            return Err(self.err("the expression is nested too deeply"));
        }
        let n = match self.peek() {
            Some(b'-') => {
                self.pos += 1;
                Node::Neg(self.unary()?.into())
            }
            Some(b'+') => {
                self.pos += 1;
                self.unary()?
            }
            _ => self.power()?,
        };
        self.depth -= 1;
        Ok(n)
    }

    fn power(&mut self) -> Result<Node> {
        let base = self.atom()?;
        match self.peek() {
            Some(b'^') => {
                self.pos += 1;
                Ok(Node::Pow(base.into(), self.unary()?.into()))
            }
            Some(b'*') if self.bytes.get(self.pos + 1) == Some(&b'*') => {
                self.pos += 2;
                Ok(Node::Pow(base.into(), self.unary()?.into()))
            }
            _ => Ok(base),
        }
    }

    fn atom(&mut self) -> Result<Node> {
        match self.peek() {
            None => Err(self.err("the expression ends here; expected a number, `t`, a function or `(`")),
            Some(b'(') => {
                self.pos += 1;
                let e = self.expr()?;
                if self.peek() != Some(b')') {
                    return Err(self.err("expected `)`"));
                }
                self.pos += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                let start = self.pos;
                while self.pos < self.bytes.len()
                    && (self.bytes[self.pos].is_ascii_digit() || self.bytes[self.pos] == b'.')
                {
                    self.pos += 1;
                }
                if self.pos < self.bytes.len() && matches!(self.bytes[self.pos], b'e' | b'E') {
                    let save = self.pos;
                    self.pos += 1;
                    if self.pos < self.bytes.len() && matches!(self.bytes[self.pos], b'+' | b'-') {
                        self.pos += 1;
                    }
                    if self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_digit() {
                        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_digit() {
                            self.pos += 1;
                        }
                    } else {
                        self.pos = save; // `2e`: not an exponent; the `e` is reported as unexpected.
                    }
                }
                let s = &self.text[start..self.pos];
                s.parse::<f64>().map(Node::Num).map_err(|_| syntax(self.text, start, format!("`{s}` is not a number")))
            }
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let start = self.pos;
                while self.pos < self.bytes.len()
                    && (self.bytes[self.pos].is_ascii_alphanumeric() || self.bytes[self.pos] == b'_')
                {
                    self.pos += 1;
                }
                let name = self.text[start..self.pos].to_ascii_lowercase();
                match name.as_str() {
                    "t" => return Ok(Node::T),
                    "pi" => return Ok(Node::Num(std::f64::consts::PI)),
                    "e" => return Ok(Node::Num(std::f64::consts::E)),
                    _ => {}
                }
                let Some(&(_, f, arity)) = FUNCS.iter().find(|(n, _, _)| *n == name) else {
                    return Err(syntax(
                        self.text,
                        start,
                        format!(
                            "unknown name `{name}`; the variable is `t`, the constants `pi` and `e`, the functions {}",
                            {
                                let names: Vec<&str> = FUNCS.iter().map(|f| f.0).collect();
                                names.join(" ")
                            }
                        ),
                    ));
                };
                if self.peek() != Some(b'(') {
                    return Err(self.err(format!("expected `(` after the function `{name}`")));
                }
                self.pos += 1;
                let mut args = vec![self.expr()?];
                while self.peek() == Some(b',') {
                    self.pos += 1;
                    args.push(self.expr()?);
                }
                if self.peek() != Some(b')') {
                    return Err(self.err("expected `,` or `)`"));
                }
                self.pos += 1;
                if args.len() != arity {
                    return Err(syntax(
                        self.text,
                        start,
                        format!("`{name}` takes {arity} argument(s), {} given", args.len()),
                    ));
                }
                Ok(Node::Call(f, args))
            }
            Some(_) => {
                let c = self.text[self.pos..].chars().next().unwrap_or('?');
                Err(self.err(format!("unexpected `{c}`; expected a number, `t`, a function or `(`")))
            }
        }
    }
}

fn num(v: f64) -> Node {
    Node::Num(v)
}

fn b(n: Node) -> Box<Node> {
    Box::new(n)
}

impl Node {
    fn eval(&self, t: f64) -> f64 {
        match self {
            Node::Num(v) => *v,
            Node::T => t,
            Node::Neg(a) => -a.eval(t),
            Node::Add(a, c) => a.eval(t) + c.eval(t),
            Node::Sub(a, c) => a.eval(t) - c.eval(t),
            Node::Mul(a, c) => a.eval(t) * c.eval(t),
            Node::Div(a, c) => a.eval(t) / c.eval(t),
            Node::Pow(a, c) => a.eval(t).powf(c.eval(t)),
            Node::Call(f, args) => {
                let x = args[0].eval(t);
                let y = args.get(1).map_or(0.0, |a| a.eval(t));
                match f {
                    Func::Sin => x.sin(),
                    Func::Cos => x.cos(),
                    Func::Tan => x.tan(),
                    Func::Asin => x.asin(),
                    Func::Acos => x.acos(),
                    Func::Atan => x.atan(),
                    Func::Sinh => x.sinh(),
                    Func::Cosh => x.cosh(),
                    Func::Tanh => x.tanh(),
                    Func::Exp => x.exp(),
                    Func::Ln => x.ln(),
                    Func::Log10 => x.log10(),
                    Func::Sqrt => x.sqrt(),
                    Func::Abs => x.abs(),
                    Func::Floor => x.floor(),
                    Func::Ceil => x.ceil(),
                    Func::Atan2 => x.atan2(y),
                    Func::Min => x.min(y),
                    Func::Max => x.max(y),
                }
            }
        }
    }

    fn has_t(&self) -> bool {
        match self {
            Node::Num(_) => false,
            Node::T => true,
            Node::Neg(a) => a.has_t(),
            Node::Add(a, c) | Node::Sub(a, c) | Node::Mul(a, c) | Node::Div(a, c) | Node::Pow(a, c) => {
                a.has_t() || c.has_t()
            }
            Node::Call(_, args) => args.iter().any(Node::has_t),
        }
    }

    /// d/dt, symbolically (piecewise functions use the derivative of the active piece).
    fn deriv(&self) -> Node {
        if !self.has_t() {
            return num(0.0);
        }
        match self {
            Node::Num(_) => num(0.0),
            Node::T => num(1.0),
            Node::Neg(a) => Node::Neg(b(a.deriv())),
            Node::Add(a, c) => Node::Add(b(a.deriv()), b(c.deriv())),
            Node::Sub(a, c) => Node::Sub(b(a.deriv()), b(c.deriv())),
            Node::Mul(a, c) => Node::Add(b(Node::Mul(b(a.deriv()), c.clone())), b(Node::Mul(a.clone(), b(c.deriv())))),
            Node::Div(a, c) => Node::Div(
                b(Node::Sub(b(Node::Mul(b(a.deriv()), c.clone())), b(Node::Mul(a.clone(), b(c.deriv()))))),
                b(Node::Mul(c.clone(), c.clone())),
            ),
            Node::Pow(a, c) if !c.has_t() => {
                // (a^c)' = c·a^(c−1)·a'
                Node::Mul(
                    b(Node::Mul(c.clone(), b(Node::Pow(a.clone(), b(Node::Sub(c.clone(), b(num(1.0)))))))),
                    b(a.deriv()),
                )
            }
            Node::Pow(a, c) => {
                // (a^c)' = a^c·(c'·ln a + c·a'/a)
                let ln_a = Node::Call(Func::Ln, vec![(**a).clone()]);
                Node::Mul(
                    b(self.clone()),
                    b(Node::Add(
                        b(Node::Mul(b(c.deriv()), b(ln_a))),
                        b(Node::Div(b(Node::Mul(c.clone(), b(a.deriv()))), a.clone())),
                    )),
                )
            }
            Node::Call(f, args) => {
                let x = &args[0];
                let dx = x.deriv();
                let call = |g: Func, n: Node| Node::Call(g, vec![n]);
                let outer = match f {
                    Func::Sin => call(Func::Cos, x.clone()),
                    Func::Cos => Node::Neg(b(call(Func::Sin, x.clone()))),
                    Func::Tan => Node::Div(b(num(1.0)), b(Node::Pow(b(call(Func::Cos, x.clone())), b(num(2.0))))),
                    Func::Asin => Node::Div(
                        b(num(1.0)),
                        b(call(Func::Sqrt, Node::Sub(b(num(1.0)), b(Node::Mul(b(x.clone()), b(x.clone())))))),
                    ),
                    Func::Acos => Node::Neg(b(Node::Div(
                        b(num(1.0)),
                        b(call(Func::Sqrt, Node::Sub(b(num(1.0)), b(Node::Mul(b(x.clone()), b(x.clone())))))),
                    ))),
                    Func::Atan => {
                        Node::Div(b(num(1.0)), b(Node::Add(b(num(1.0)), b(Node::Mul(b(x.clone()), b(x.clone()))))))
                    }
                    Func::Sinh => call(Func::Cosh, x.clone()),
                    Func::Cosh => call(Func::Sinh, x.clone()),
                    Func::Tanh => Node::Sub(b(num(1.0)), b(Node::Pow(b(call(Func::Tanh, x.clone())), b(num(2.0))))),
                    Func::Exp => call(Func::Exp, x.clone()),
                    Func::Ln => Node::Div(b(num(1.0)), b(x.clone())),
                    Func::Log10 => Node::Div(b(num(1.0 / std::f64::consts::LN_10)), b(x.clone())),
                    Func::Sqrt => Node::Div(b(num(0.5)), b(call(Func::Sqrt, x.clone()))),
                    // sign(x) = x/|x| (0/0 at x = 0, where |x| has no derivative).
                    Func::Abs => Node::Div(b(x.clone()), b(call(Func::Abs, x.clone()))),
                    Func::Floor | Func::Ceil => num(0.0),
                    Func::Atan2 | Func::Min | Func::Max => return self.two_arg_deriv(*f, args),
                };
                Node::Mul(b(outer), b(dx))
            }
        }
    }

    fn two_arg_deriv(&self, f: Func, args: &[Node]) -> Node {
        let (y, x) = (&args[0], &args[1]);
        match f {
            // d atan2(y, x) = (x·y' − y·x')/(x² + y²)
            Func::Atan2 => Node::Div(
                b(Node::Sub(b(Node::Mul(b(x.clone()), b(y.deriv()))), b(Node::Mul(b(y.clone()), b(x.deriv()))))),
                b(Node::Add(b(Node::Mul(b(x.clone()), b(x.clone()))), b(Node::Mul(b(y.clone()), b(y.clone()))))),
            ),
            // The derivative of the active argument: (a' + b')/2 + sign(a − b)·(a' − b')/2 (± for max/min).
            _ => {
                let diff = Node::Sub(b(y.clone()), b(x.clone()));
                let sign = Node::Div(b(diff.clone()), b(Node::Call(Func::Abs, vec![diff])));
                let half_sum = Node::Mul(b(num(0.5)), b(Node::Add(b(y.deriv()), b(x.deriv()))));
                let half_diff = Node::Mul(b(num(0.5)), b(Node::Sub(b(y.deriv()), b(x.deriv()))));
                let signed = Node::Mul(b(sign), b(half_diff));
                if f == Func::Max {
                    Node::Add(b(half_sum), b(signed))
                } else {
                    Node::Sub(b(half_sum), b(signed))
                }
            }
        }
    }
}

impl Expr {
    /// Parses `text`. Errors name the column and what was expected.
    ///
    /// # Examples
    /// ```
    /// use kinema::traj::Expr;
    /// let e = Expr::parse("3*sin(4*pi*t^2/2)")?; // seed 001 §4.2
    /// assert!((e.eval(0.25) - 3.0 * (std::f64::consts::PI / 8.0).sin()).abs() < 1e-15);
    /// assert!(Expr::parse("3*sin(4*pi*t^2/2").unwrap_err().to_string().contains("column"));
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn parse(text: &str) -> Result<Expr> {
        if text.len() > 10_000 {
            return Err(syntax(text, 0, "the expression is longer than 10 000 characters".into()));
        }
        let mut p = Parser { text, bytes: text.as_bytes(), pos: 0, depth: 0 };
        let node = p.expr()?;
        if p.peek().is_some() {
            let c = text[p.pos..].chars().next().unwrap_or('?');
            return Err(p.err(format!("unexpected `{c}` after a complete expression")));
        }
        Ok(Expr { node, text: text.to_string() })
    }

    /// The value at `t`.
    pub fn eval(&self, t: f64) -> f64 {
        self.node.eval(t)
    }

    /// The derivative d/dt as an expression.
    pub fn derivative(&self) -> Expr {
        Expr { node: self.node.deriv(), text: format!("d/dt ({})", self.text) }
    }

    /// The text it was parsed from.
    pub fn text(&self) -> &str {
        &self.text
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// A joint trajectory whose joints follow expressions of t (the others hold
/// their values in `q0`), sampled every `dt` over \[0, `duration`\], with
/// velocities and accelerations from the symbolic derivatives.
///
/// Errors: `q0` wrong; a joint index out of range (1-based in messages);
/// a non-finite value at some sample (its time and joint).
pub fn expression_trajectory(
    robot: &Robot,
    q0: &[f64],
    exprs: &[(usize, Expr)],
    duration: f64,
    dt: f64,
) -> Result<JointTrajectory> {
    robot.check_q(q0)?;
    if !(duration.is_finite() && duration > 0.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "duration".into(),
            value: duration,
            expected: "a positive, finite time [s]".into(),
        }));
    }
    let n = robot.dof();
    let mut compiled = Vec::with_capacity(exprs.len());
    for (j, e) in exprs {
        if *j >= n {
            return Err(Error::Input(InputError::OutOfRange {
                what: "joint".into(),
                value: (j + 1) as f64,
                expected: format!("a joint of `{}`, 1 to {n}", robot.name()),
            }));
        }
        let d1 = e.derivative();
        let d2 = d1.derivative();
        compiled.push((*j, e.clone(), d1, d2));
    }
    let times = sample_times(duration, dt)?;
    let mut traj = JointTrajectory::reserved(n, times.len())?;
    let (mut q, mut qd, mut qdd) = (q0.to_vec(), vec![0.0; n], vec![0.0; n]);
    for t in times {
        for (j, e, d1, d2) in &compiled {
            (q[*j], qd[*j], qdd[*j]) = (e.eval(t), d1.eval(t), d2.eval(t));
            for (what, v) in [("value", q[*j]), ("velocity", qd[*j]), ("acceleration", qdd[*j])] {
                if !v.is_finite() {
                    return Err(Error::Infeasible {
                        what: "expression".into(),
                        reason: format!(
                            "`{e}` for joint {}: the {what} at t = {t:.4} s is {v}; it must stay finite",
                            j + 1
                        ),
                    });
                }
            }
        }
        traj.push(t, &q, &qd, &qdd)?;
    }
    Ok(traj)
}

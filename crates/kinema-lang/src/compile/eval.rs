//! Expressions evaluated to SI values with their dimension.

use std::collections::HashMap;

use kinema::Robot;

use crate::ast::{BinOp, Expr};
use crate::diag::Diagnostic;
use crate::units::{unit, Dim, Quantity};

/// Evaluates an expression to SI with its dimension.
pub(crate) fn eval(e: &Expr, counters: &HashMap<String, f64>) -> Result<Quantity, Diagnostic> {
    match e {
        Expr::Num { value, unit: None, .. } => Ok(Quantity { value: *value, dim: Dim::None }),
        Expr::Num { value, unit: Some(u), span } => match unit(u) {
            Some((scale, dim)) => Ok(Quantity { value: value * scale, dim }),
            None => Err(Diagnostic::error(span.clone(), format!("unknown unit `{u}`"))),
        },
        Expr::Var(name) => match counters.get(&name.key) {
            Some(v) => Ok(Quantity { value: *v, dim: Dim::None }),
            None => Err(Diagnostic::error(name.span.clone(), format!("unknown name `{}` in an expression", name.text))
                .with_hint("only FOR counters can be used in expressions; numbers need their unit, e.g. 50mm")),
        },
        Expr::Neg(inner, _) => {
            let q = eval(inner, counters)?;
            Ok(Quantity { value: -q.value, dim: q.dim })
        }
        Expr::Bin { op, lhs, rhs, span } => {
            let (a, b) = (eval(lhs, counters)?, eval(rhs, counters)?);
            let mismatch =
                |what: &str| Diagnostic::error(span.clone(), format!("cannot {what} {} and {}", a.dim, b.dim));
            match op {
                BinOp::Add | BinOp::Sub => {
                    if a.dim != b.dim {
                        return Err(mismatch(if *op == BinOp::Add { "add" } else { "subtract" })
                            .with_hint("both sides need the same kind of unit, e.g. 50mm + 2cm"));
                    }
                    let value = if *op == BinOp::Add { a.value + b.value } else { a.value - b.value };
                    Ok(Quantity { value, dim: a.dim })
                }
                BinOp::Mul => match (a.dim, b.dim) {
                    (Dim::None, d) | (d, Dim::None) => Ok(Quantity { value: a.value * b.value, dim: d }),
                    _ => Err(mismatch("multiply").with_hint("one side of * must be a plain number")),
                },
                BinOp::Div => {
                    if b.value == 0.0 {
                        return Err(Diagnostic::error(span.clone(), "division by zero"));
                    }
                    match (a.dim, b.dim) {
                        (d, Dim::None) => Ok(Quantity { value: a.value / b.value, dim: d }),
                        (x, y) if x == y => Ok(Quantity { value: a.value / b.value, dim: Dim::None }),
                        _ => Err(mismatch("divide")),
                    }
                }
            }
        }
    }
}

/// A quantity as a value of dimension `dim` (see [`Compiler::static_expect`]).
pub(super) fn coerce(q: Quantity, dim: Dim, default_scale: Option<f64>, e: &Expr) -> Result<f64, Diagnostic> {
    if q.dim == dim {
        return Ok(q.value);
    }
    if q.dim == Dim::None {
        if let Some(scale) = default_scale {
            return Ok(q.value * scale);
        }
        if dim == Dim::None || q.value == 0.0 {
            return Ok(q.value);
        }
        let example = match dim {
            Dim::Length => "50mm or 0.05m",
            Dim::Angle => "30deg or 0.5rad",
            Dim::Time => "2s",
            Dim::Percent => "50%",
            Dim::LinVel => "250mm/s",
            Dim::AngVel => "90deg/s",
            Dim::LinAcc => "1m/s^2",
            Dim::AngAcc => "180deg/s^2",
            Dim::None => "",
        };
        return Err(Diagnostic::error(e.span(), format!("missing unit: expected {dim}"))
            .with_hint(format!("write e.g. {example}")));
    }
    Err(Diagnostic::error(e.span(), format!("expected {dim}, found {}", q.dim)))
}

/// The dimension of joint `i`'s values: a length for a prismatic joint, else an angle.
pub(super) fn joint_dim(robot: &Robot, i: usize) -> Dim {
    match robot.joints().get(i).map(|j| j.kind) {
        Some(kinema::JointType::Prismatic) => Dim::Length,
        _ => Dim::Angle,
    }
}

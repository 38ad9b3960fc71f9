//! Joint curves from expressions of t (seed 001 §4.2).

use std::f64::consts::PI;

use kinema::traj::{check, expression_trajectory, CheckOptions, Expr};
use kinema::Robot;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn seed_001_curve_and_its_derivatives() {
    // θ1 = 3·sin(4π·t²/2): θ̇ = 12π·t·cos(2π·t²), θ̈ = 12π·cos(2πt²) − 48π²·t²·sin(2πt²).
    let e = Expr::parse("3*sin(4*pi*t^2/2)").unwrap();
    let (d1, d2) = (e.derivative(), e.derivative().derivative());
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..5000 {
        let t: f64 = rng.random_range(-3.0..3.0);
        let u = 2.0 * PI * t * t;
        assert!((e.eval(t) - 3.0 * u.sin()).abs() < 1e-12);
        assert!((d1.eval(t) - 12.0 * PI * t * u.cos()).abs() < 1e-10 * (1.0 + t.abs()));
        let want = 12.0 * PI * u.cos() - 48.0 * PI * PI * t * t * u.sin();
        assert!((d2.eval(t) - want).abs() < 1e-9 * (1.0 + want.abs()), "{t}: {} vs {want}", d2.eval(t));
    }
}

/// A random expression as text, with an independent evaluator.
type Gen = (String, Box<dyn Fn(f64) -> f64>);

fn random_expr(rng: &mut ChaCha8Rng, depth: usize) -> Gen {
    if depth == 0 || rng.random_bool(0.25) {
        return if rng.random_bool(0.5) {
            ("t".into(), Box::new(|t| t))
        } else {
            let c: f64 = (rng.random_range(-30..30) as f64) / 10.0;
            (format!("({c})"), Box::new(move |_| c))
        };
    }
    let (a, fa) = random_expr(rng, depth - 1);
    match rng.random_range(0..9) {
        0 => {
            let (c, fc) = random_expr(rng, depth - 1);
            (format!("({a} + {c})"), Box::new(move |t| fa(t) + fc(t)))
        }
        1 => {
            let (c, fc) = random_expr(rng, depth - 1);
            (format!("({a} - {c})"), Box::new(move |t| fa(t) - fc(t)))
        }
        2 => {
            let (c, fc) = random_expr(rng, depth - 1);
            (format!("({a})*({c})"), Box::new(move |t| fa(t) * fc(t)))
        }
        3 => {
            let (c, fc) = random_expr(rng, depth - 1);
            (format!("({a}) / (2 + ({c})^2)"), Box::new(move |t| fa(t) / (2.0 + fc(t).powi(2))))
        }
        4 => (format!("SIN({a})"), Box::new(move |t| fa(t).sin())),
        5 => (format!("cos({a})"), Box::new(move |t| fa(t).cos())),
        6 => (format!("exp(-({a})^2)"), Box::new(move |t| (-(fa(t).powi(2))).exp())),
        7 => (format!("atan({a})"), Box::new(move |t| fa(t).atan())),
        _ => (format!("sqrt(1 + ({a})**2)"), Box::new(move |t| (1.0 + fa(t).powi(2)).sqrt())),
    }
}

#[test]
fn random_expressions_evaluate_and_differentiate_correctly() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..2000 {
        let (text, f) = random_expr(&mut rng, 4);
        let e = Expr::parse(&text).unwrap_or_else(|err| panic!("{text}: {err}"));
        let d = e.derivative();
        for _ in 0..5 {
            let t: f64 = rng.random_range(-2.0..2.0);
            let (got, want) = (e.eval(t), f(t));
            assert!((got - want).abs() <= 1e-12 * (1.0 + want.abs()), "{text} at {t}: {got} vs {want}");
            // Central difference (h = 1e-5): error ~ h²·f‴, far below the tolerance.
            let h = 1e-5;
            let fd = (f(t + h) - f(t - h)) / (2.0 * h);
            let dv = d.eval(t);
            assert!((dv - fd).abs() <= 1e-5 * (1.0 + fd.abs()), "{text} at {t}: d/dt {dv} vs {fd}");
        }
    }
}

#[test]
fn precedence_and_associativity() {
    let v = |s: &str| Expr::parse(s).unwrap().eval(2.0);
    assert_eq!(v("-t^2"), -4.0);
    assert_eq!(v("2^3^2"), 512.0);
    assert_eq!(v("2**3**2"), 512.0);
    assert_eq!(v("1 - 2 - 3"), -4.0);
    assert_eq!(v("12 / 2 / 3"), 2.0);
    assert_eq!(v("2 * t + 1"), 5.0);
    assert_eq!(v("1e-3 * 1E3"), 1.0);
    assert_eq!(v("max(t, 3) + min(t, 3) + atan2(0, 1)"), 5.0);
    assert_eq!(v(" ( ( t ) ) "), 2.0);
    assert!((v("e") - std::f64::consts::E).abs() < 1e-15 && (v("PI") - PI).abs() < 1e-15);
}

#[test]
fn syntax_errors_name_the_column_and_never_panic() {
    for (text, col, what) in [
        ("3*sin(4*pi*t^2/2", 17, "`)`"),
        ("3 + * t", 5, "unexpected `*`"),
        ("foo(t)", 1, "unknown name `foo`"),
        ("sin t", 5, "expected `(`"),
        ("atan2(t)", 1, "takes 2 argument"),
        ("t t", 3, "after a complete expression"),
        ("", 1, "ends here"),
        ("2e", 2, "unexpected `e`"),
    ] {
        let e = Expr::parse(text).unwrap_err().to_string();
        assert!(e.contains(&format!("column {col}")) && e.contains(what), "{text}: {e}");
    }
    let deep = format!("{}t{}", "(".repeat(4000), ")".repeat(4000));
    assert!(Expr::parse(&deep).unwrap_err().to_string().contains("nested too deeply"));
    assert!(Expr::parse(&"-".repeat(5000)).is_err());
    assert!(Expr::parse(&"t+".repeat(6000)).unwrap_err().to_string().contains("longer"));
    // Random bytes and random token soups: an error or an expression, never a panic.
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let tokens =
        ["t", "(", ")", "+", "-", "*", "/", "^", "**", ",", "sin", "atan2", "pi", "1.5", "e", "2e", " ", "é", "max"];
    for _ in 0..20_000 {
        let s: String = if rng.random_bool(0.5) {
            let bytes: Vec<u8> = (0..rng.random_range(0..30)).map(|_| rng.random()).collect();
            String::from_utf8_lossy(&bytes).into_owned()
        } else {
            (0..rng.random_range(0..20)).map(|_| tokens[rng.random_range(0..tokens.len())]).collect()
        };
        if let Ok(e) = Expr::parse(&s) {
            let _ = (e.eval(0.3), e.derivative().eval(0.3));
        }
    }
}

#[test]
fn rommel_joint_curve_from_the_seed() {
    let robot = Robot::builtin("rommel").unwrap();
    let e = Expr::parse("3*sin(4*pi*t^2/2)").unwrap();
    let traj = expression_trajectory(&robot, robot.home(), &[(0, e.clone())], 2.0, 0.001).unwrap();
    assert_eq!(traj.len(), 2001);
    for k in (0..traj.len()).step_by(97) {
        let t = traj.times()[k];
        assert!((traj.q(k)[0] - e.eval(t)).abs() < 1e-15);
        assert_eq!(&traj.q(k)[1..], &robot.home()[1..]);
        assert!(traj.qd(k)[1..].iter().all(|v| *v == 0.0));
    }
    // Velocity and acceleration columns against differences of the samples.
    for k in 1..traj.len() - 1 {
        let (a, b) = (traj.q(k - 1)[0], traj.q(k + 1)[0]);
        let fd = (b - a) / 0.002;
        assert!((traj.qd(k)[0] - fd).abs() < 2e-3 * (1.0 + fd.abs()), "{k}");
    }
    // An amplitude of 3 rad breaks ROMMEL's joint-1 limit: the check says when.
    let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
    let lim = robot.joints()[0].limits;
    if lim.max < 3.0 {
        assert!(report.violations.iter().any(|v| v.joint == Some(0)), "expected a joint-1 violation");
    }
    let e = expression_trajectory(&robot, robot.home(), &[(7, Expr::parse("t").unwrap())], 1.0, 0.1).unwrap_err();
    assert!(
        matches!(&e, kinema::Error::Input(kinema::InputError::OutOfRange { what, value: 8.0, .. }) if what == "joint"),
        "{e:?}"
    );
    assert!(e.to_string().contains("expected a joint of `rommel`, 1 to 5"), "{e}");
    let e =
        expression_trajectory(&robot, robot.home(), &[(0, Expr::parse("ln(t - 0.5)").unwrap())], 1.0, 0.1).unwrap_err();
    assert!(e.to_string().contains("t = 0.0000"), "{e}");
}

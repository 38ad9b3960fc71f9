//! Shared by the `core-peers` binary and the `core_peers` benchmark: the robots as kinema and `k`
//! load them from one URDF, the states and Pinocchio's results written by `pinocchio_bench`, and
//! a URDF writer for kinema's built-in DH robots so that all three peers read the same model.

#[cfg(feature = "ik-geo")]
pub mod ikgeo;

use std::fmt::Write as _;
use std::path::Path;

use kinema::nalgebra::{Rotation3, Vector3};
use kinema::{DhConvention, Inertial, JointType, LinkGeometry, Pose, Robot};

/// One robot as each Rust peer holds it.
pub struct Peers {
    /// kinema's model of the chain from the URDF's root to the tip link.
    pub robot: Robot,
    /// `k`'s chain from the URDF's root to the tip link.
    pub k: k::SerialChain<f64>,
}

/// Loads `urdf` up to the link `tip` in kinema and in `k`.
pub fn load(urdf: &Path, tip: &str) -> Result<Peers, String> {
    let robot = Robot::from_file(urdf, Some(tip)).map_err(|e| format!("kinema: {e}"))?;
    let chain = k::Chain::<f64>::from_urdf_file(urdf).map_err(|e| format!("k: {e}"))?;
    let end = chain.find_link(tip).ok_or_else(|| format!("k: no link `{tip}`"))?;
    let k = k::SerialChain::from_end(end);
    if k.dof() != robot.dof() {
        return Err(format!("k has {} joints to `{tip}`, kinema {}", k.dof(), robot.dof()));
    }
    Ok(Peers { robot, k })
}

/// One row of `pinocchio_bench states`: a state and Pinocchio's results at it.
#[derive(Debug, Clone)]
pub struct State {
    /// Joint positions, velocities, accelerations.
    pub q: Vec<f64>,
    /// Joint velocities.
    pub qd: Vec<f64>,
    /// Joint accelerations.
    pub qdd: Vec<f64>,
    /// Tool pose: rotation row-major, then position.
    pub pose: [f64; 12],
    /// Tool Jacobian, 6 × n row-major, rows \[v; ω\] in world axes.
    pub jacobian: Vec<f64>,
    /// RNEA torques with gravity (0, 0, −9.81).
    pub tau: Vec<f64>,
    /// Mass matrix, n × n row-major, both triangles.
    pub m: Vec<f64>,
}

/// Reads the states of an `n`-joint robot from `pinocchio_bench states`' CSV.
pub fn read_states(path: &Path, n: usize) -> Result<Vec<State>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    text.lines()
        .enumerate()
        .map(|(i, line)| {
            let v: Vec<f64> = line
                .split(',')
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|e| format!("line {}: {e}", i + 1))?;
            if v.len() != 3 * n + 12 + 6 * n + n + n * n {
                return Err(format!("line {}: {} values for {n} joints", i + 1, v.len()));
            }
            let mut at = 0;
            let mut take = |k: usize| {
                at += k;
                v[at - k..at].to_vec()
            };
            Ok(State {
                q: take(n),
                qd: take(n),
                qdd: take(n),
                pose: take(12).try_into().expect("12 values"),
                jacobian: take(6 * n),
                tau: take(n),
                m: take(n * n),
            })
        })
        .collect()
}

/// Mass properties for a link the description gives none: a 2 kg body 5 cm along z of its
/// frame. For timing only (every peer gets the same), not a model of any arm.
pub const PLACEHOLDER: Inertial = Inertial {
    mass: 2.0,
    com: Vector3::new(0.0, 0.0, 0.05),
    inertia: kinema::nalgebra::Matrix3::new(0.02, 0.0, 0.0, 0.0, 0.02, 0.0, 0.0, 0.0, 0.01),
};

fn origin(p: &Pose) -> String {
    let (r, pi, y) = Rotation3::from_matrix_unchecked(p.rot).euler_angles();
    format!(r#"<origin xyz="{:.17e} {:.17e} {:.17e}" rpy="{r:.17e} {pi:.17e} {y:.17e}"/>"#, p.pos.x, p.pos.y, p.pos.z)
}

fn link(out: &mut String, name: &str, body: Option<&Inertial>) {
    match body {
        None => writeln!(out, r#"  <link name="{name}"/>"#).unwrap(),
        Some(b) => {
            let i = &b.inertia;
            writeln!(
                out,
                r#"  <link name="{name}"><inertial>{}<mass value="{:.17e}"/><inertia ixx="{:.17e}" iyy="{:.17e}" izz="{:.17e}" ixy="{:.17e}" ixz="{:.17e}" iyz="{:.17e}"/></inertial></link>"#,
                origin(&Pose::translation(b.com.x, b.com.y, b.com.z)),
                b.mass,
                i[(0, 0)],
                i[(1, 1)],
                i[(2, 2)],
                i[(0, 1)],
                i[(0, 2)],
                i[(1, 2)]
            )
            .unwrap()
        }
    }
}

fn fixed(out: &mut String, name: &str, parent: &str, child: &str, at: &Pose) {
    writeln!(
        out,
        r#"  <joint name="{name}" type="fixed"><parent link="{parent}"/><child link="{child}"/>{}</joint>"#,
        origin(at)
    )
    .unwrap();
}

/// `robot` as a URDF: links `link0` (the base frame) … `link{n}` carrying the mass properties
/// (or [`PLACEHOLDER`] where there are none) in the model's link frames, and `tool`. A standard
/// DH row becomes the joint about z of frame i−1 and a fixed joint Tz(d)·Tx(a)·Rx(α) to link i;
/// a modified DH row and a general joint become one joint whose origin carries the fixed part.
/// Joint offsets go into the origins (URDF has none), so q means the same in every reader.
pub fn urdf_of(robot: &Robot) -> String {
    let mut out = format!(
        "<?xml version=\"1.0\"?>\n<!-- {} written by kinema-core-peers from kinema's model -->\n<robot name=\"{}\">\n",
        robot.name(),
        robot.name()
    );
    link(&mut out, "world", None);
    link(&mut out, "link0", None);
    fixed(&mut out, "base", "world", "link0", robot.base());
    for (i, j) in robot.joints().iter().enumerate() {
        let body = robot.inertials()[i].unwrap_or(PLACEHOLDER);
        let prismatic = j.kind == JointType::Prismatic;
        let (at, axis, after) = match j.geometry {
            LinkGeometry::Dh { convention, d, a, alpha, theta } => {
                // The constant θ and d (the joint's value adds to one of them); motion about or
                // along z commutes with the constant part about or along z.
                let (th, dd) = if prismatic { (theta, j.offset) } else { (j.offset, d) };
                let z = Pose::rot_z(th) * Pose::translation(0.0, 0.0, dd);
                let x = Pose::translation(a, 0.0, 0.0) * Pose::rot_x(alpha);
                match convention {
                    DhConvention::Standard => (z, Vector3::z(), Some(x)),
                    DhConvention::Modified => {
                        (Pose::rot_x(alpha) * Pose::translation(a, 0.0, 0.0) * z, Vector3::z(), None)
                    }
                }
            }
            LinkGeometry::General { origin, axis } => {
                let off = if prismatic {
                    Pose::translation(axis.x * j.offset, axis.y * j.offset, axis.z * j.offset)
                } else {
                    let r = Rotation3::from_axis_angle(&kinema::nalgebra::Unit::new_normalize(axis), j.offset);
                    Pose::new(*r.matrix(), Vector3::zeros())
                };
                (origin * off, axis, None)
            }
        };
        let child = if after.is_some() { format!("moving{}", i + 1) } else { format!("link{}", i + 1) };
        let (lo, hi) = (j.limits.min, j.limits.max);
        writeln!(
            out,
            r#"  <joint name="{}" type="{}"><parent link="link{i}"/><child link="{child}"/>{}<axis xyz="{:.17e} {:.17e} {:.17e}"/><limit lower="{lo:.17e}" upper="{hi:.17e}" effort="100" velocity="{}"/></joint>"#,
            j.name,
            if prismatic { "prismatic" } else { "revolute" },
            origin(&at),
            axis.x,
            axis.y,
            axis.z,
            j.limits.vel.unwrap_or(1.0)
        )
        .unwrap();
        if let Some(after) = after {
            link(&mut out, &child, None);
            fixed(&mut out, &format!("dh{}", i + 1), &child, &format!("link{}", i + 1), &after);
        }
        link(&mut out, &format!("link{}", i + 1), Some(&body));
    }
    link(&mut out, "tool", None);
    fixed(&mut out, "flange", &format!("link{}", robot.dof()), "tool", robot.tool());
    out.push_str("</robot>\n");
    out
}

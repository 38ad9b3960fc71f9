//! Shared by the benchmarks: seeded configurations and the same chains built
//! for the `k` crate from kinema's model (checked equal before timing).
#![allow(dead_code)]

use k::nalgebra as kna;
use kinema::nalgebra::Matrix6xX;
use kinema::{DhConvention, Frame, JointType, LinkGeometry, Pose, Robot};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Number of configurations cycled through in every benchmark (a power of two).
pub const N_CONFIGS: usize = 1024;
/// Configurations used to cross-check the k chain against kinema.
pub const N_CHECK: usize = 100;
/// Tolerance of the cross-check.
pub const TOL: f64 = 1e-9;

pub type Iso = kna::Isometry3<f64>;

/// `N_CONFIGS` seeded random configurations (within the limits, each checked
/// valid), taken in turn so that branch predictors cannot learn one input.
pub struct Cycle {
    qs: Vec<f64>,
    n: usize,
}

impl Cycle {
    pub fn new(robot: &Robot, seed: u64) -> Self {
        let n = robot.dof();
        let qs = configs(robot, seed, N_CONFIGS);
        for q in qs.chunks_exact(n) {
            robot.check_q(q).expect("random configurations are valid");
        }
        Cycle { qs, n }
    }

    /// The i-th configuration, i taken modulo `N_CONFIGS`.
    #[inline(always)]
    pub fn at(&self, i: usize) -> &[f64] {
        let i = i & (N_CONFIGS - 1);
        &self.qs[i * self.n..(i + 1) * self.n]
    }
}

/// Criterion's settings for the per-call benchmarks (`kinematics`, `cold`):
/// calls of tens of nanoseconds need no long measurement.
pub fn per_call_criterion() -> criterion::Criterion {
    criterion::Criterion::default()
        .sample_size(50)
        .warm_up_time(std::time::Duration::from_secs(1))
        .measurement_time(std::time::Duration::from_secs(2))
}

/// `N_CONFIGS` random configurations, one after another (`N_CONFIGS × dof`).
pub fn configs(robot: &Robot, seed: u64, count: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut qs = Vec::with_capacity(count * robot.dof());
    for _ in 0..count {
        qs.extend(robot.random_q(&mut rng));
    }
    qs
}

// ---------------------------------------------------------------------------
// Building a k chain from kinema's model description.
// ---------------------------------------------------------------------------

pub fn k_trans(x: f64, y: f64, z: f64) -> Iso {
    Iso::translation(x, y, z)
}

pub fn k_rot(axis: kna::Unit<kna::Vector3<f64>>, angle: f64) -> Iso {
    Iso::from_parts(kna::Translation3::identity(), kna::UnitQuaternion::from_axis_angle(&axis, angle))
}

pub fn k_rot_x(angle: f64) -> Iso {
    k_rot(kna::Vector3::x_axis(), angle)
}

pub fn k_rot_z(angle: f64) -> Iso {
    k_rot(kna::Vector3::z_axis(), angle)
}

/// A kinema pose (nalgebra 0.34) as a k isometry (nalgebra 0.30).
pub fn k_iso(p: &Pose) -> Iso {
    let r = &p.rot;
    let m = kna::Matrix3::new(
        r[(0, 0)],
        r[(0, 1)],
        r[(0, 2)],
        r[(1, 0)],
        r[(1, 1)],
        r[(1, 2)],
        r[(2, 0)],
        r[(2, 1)],
        r[(2, 2)],
    );
    let rot = kna::Rotation3::from_matrix_unchecked(m);
    Iso::from_parts(kna::Translation3::new(p.pos.x, p.pos.y, p.pos.z), kna::UnitQuaternion::from_rotation_matrix(&rot))
}

/// One joint of the chain in URDF form: `link_i = pre · J_axis(q) · post`.
pub struct KJoint {
    name: String,
    pre: Iso,
    joint_type: k::JointType<f64>,
    post: Iso,
}

/// Derives the URDF-style description of a kinema joint directly from the
/// model's DH row / general description (independently of kinema's compiled
/// chain, which is private).
pub fn k_joint(j: &kinema::Joint) -> KJoint {
    let prismatic = j.kind == JointType::Prismatic;
    match j.geometry {
        LinkGeometry::Dh { convention, d, a, alpha, theta } => {
            let joint_type = if prismatic {
                k::JointType::Linear { axis: kna::Vector3::z_axis() }
            } else {
                k::JointType::Rotational { axis: kna::Vector3::z_axis() }
            };
            // The constant parts of θ and d (the joint value adds to one of them).
            let (th0, d0) = if prismatic { (theta, j.offset) } else { (j.offset, d) };
            match convention {
                // Rz(θ)·Tz(d)·Tx(a)·Rx(α): the motion about/along z comes first
                // (it commutes with Rz(θ0)·Tz(d0)); the rest is fixed and belongs
                // to the next node's origin.
                DhConvention::Standard => KJoint {
                    name: j.name.clone(),
                    pre: Iso::identity(),
                    joint_type,
                    post: k_rot_z(th0) * k_trans(0.0, 0.0, d0) * k_trans(a, 0.0, 0.0) * k_rot_x(alpha),
                },
                // Rx(α)·Tx(a)·Rz(θ)·Tz(d): fixed part first, motion last.
                DhConvention::Modified => KJoint {
                    name: j.name.clone(),
                    pre: k_rot_x(alpha) * k_trans(a, 0.0, 0.0) * k_rot_z(th0) * k_trans(0.0, 0.0, d0),
                    joint_type,
                    post: Iso::identity(),
                },
            }
        }
        LinkGeometry::General { origin, axis } => {
            let axis = kna::Unit::new_normalize(kna::Vector3::new(axis.x, axis.y, axis.z));
            // Motion by q + offset about/along `axis` = motion by offset, then by q.
            let (off, joint_type) = if prismatic {
                (
                    Iso::from_parts(
                        kna::Translation3::from(axis.into_inner() * j.offset),
                        kna::UnitQuaternion::identity(),
                    ),
                    k::JointType::Linear { axis },
                )
            } else {
                (k_rot(axis, j.offset), k::JointType::Rotational { axis })
            };
            KJoint { name: j.name.clone(), pre: k_iso(&origin) * off, joint_type, post: Iso::identity() }
        }
    }
}

/// k chain equivalent to `robot`: one node per joint (the base in the first
/// origin, each joint's trailing fixed part in the next origin) and a final
/// fixed `tool` node. Returns the serial chain (from root to the tool node).
pub fn k_chain(robot: &Robot) -> k::SerialChain<f64> {
    let joints: Vec<KJoint> = robot.joints().iter().map(k_joint).collect();
    // k links a child to its parent weakly (parents own their children), so
    // every node is kept alive here until the chain holds them all.
    let mut nodes: Vec<k::Node<f64>> = Vec::with_capacity(joints.len() + 1);
    let mut prev_post = k_iso(robot.base());
    for kj in joints {
        let node =
            k::NodeBuilder::new().name(&kj.name).joint_type(kj.joint_type).origin(prev_post * kj.pre).into_node();
        if let Some(p) = nodes.last() {
            node.set_parent(p);
        }
        prev_post = kj.post;
        nodes.push(node);
    }
    let tool = k::NodeBuilder::new()
        .name("tool")
        .joint_type(k::JointType::Fixed)
        .origin(prev_post * k_iso(robot.tool()))
        .into_node();
    tool.set_parent(nodes.last().expect("a robot has at least one joint"));
    let chain = k::SerialChain::from_end(&tool);
    assert_eq!(chain.iter().count(), nodes.len() + 1, "{}: k chain lost nodes", robot.name());
    chain
}

/// The k chain's tool pose at `q` via `update_transforms`.
pub fn k_fk(chain: &k::SerialChain<f64>, q: &[f64]) -> Iso {
    chain.set_joint_positions_unchecked(q);
    let all = chain.update_transforms();
    *all.last().expect("non-empty chain")
}

/// Asserts that the k chain reproduces kinema's FK and base-frame Jacobian.
pub fn cross_check(robot: &Robot, chain: &k::SerialChain<f64>) {
    let name = robot.name();
    assert_eq!(chain.dof(), robot.dof(), "{name}: k chain dof");
    let n = robot.dof();
    let qs = configs(robot, 0xC0FFEE, N_CHECK);
    let mut jac = Matrix6xX::zeros(n);
    let tool_node = chain.iter().last().expect("non-empty chain").clone();
    for q in qs.chunks_exact(n) {
        let want = robot.fk(q).expect("valid q").world_from_tool;
        let got = k_fk(chain, q);
        // The last node's cached world transform is the same pose.
        let cached = tool_node.world_transform().expect("updated");
        assert!((cached.to_homogeneous() - got.to_homogeneous()).norm() == 0.0);
        let got_r = got.rotation.to_rotation_matrix().into_inner();
        let got_p = got.translation.vector;
        let mut err: f64 = 0.0;
        for r in 0..3 {
            err = err.max((got_p[r] - want.pos[r]).abs());
            for c in 0..3 {
                err = err.max((got_r[(r, c)] - want.rot[(r, c)]).abs());
            }
        }
        assert!(
            err <= TOL,
            "{name}: k FK differs from kinema FK by {err:e} at q = {q:?}\nkinema: {want:?}\nk: {got:?}"
        );
        // `end_transform` (used by fk/k-end) agrees as well.
        let end = chain.end_transform();
        assert!(
            (end.to_homogeneous() - got.to_homogeneous()).amax() <= TOL,
            "{name}: k end_transform differs from update_transforms at q = {q:?}"
        );

        kinema::kin::jacobian_into(robot, q, Frame::Base, &mut jac).expect("valid q");
        let kj = k::jacobian(chain);
        assert_eq!((kj.nrows(), kj.ncols()), (6, n));
        let mut jerr: f64 = 0.0;
        for r in 0..6 {
            for c in 0..n {
                jerr = jerr.max((kj[(r, c)] - jac[(r, c)]).abs());
            }
        }
        assert!(jerr <= TOL, "{name}: k Jacobian differs from kinema's by {jerr:e} at q = {q:?}");
    }
}

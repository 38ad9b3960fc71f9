//! A closed-form family added from outside the library in one file plus one
//! registry line: a planar two-link arm, fitted from its joint axes at q = 0,
//! whose kernel alone (through [`ClosedForm`]) makes it an IK solver that the
//! request layer and the contract take as they take the built-in families.

use kinema::ik::family::Family;
use kinema::ik::geo::Kinematics;
use kinema::ik::registry::{self, boxed, Entry, FAMILIES};
use kinema::ik::{solve_target_with, CandidateSet, ClosedForm, IkRequest, IkTarget, SolverChoice};
use kinema::nalgebra::Vector3;
use kinema::{Error, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Two revolute joints with parallel axes, the tool in their plane.
struct Planar2R {
    robot: Robot,
    /// Link lengths \[m\]: axis 1 to axis 2, axis 2 to the tool point.
    l1: f64,
    l2: f64,
}

impl Planar2R {
    fn new(robot: &Robot) -> kinema::Result<Self> {
        let refuse = |reason: &str| Error::UnsupportedStructure {
            solver: "planar-2r".into(),
            robot: robot.name().into(),
            reason: reason.into(),
        };
        if robot.dof() != 2 {
            return Err(refuse("it needs two revolute joints"));
        }
        let kin = Kinematics::new(robot)?;
        if kin.h[0].cross(&kin.h[1]).norm() > 1e-9 || kin.h[0].cross(&Vector3::z()).norm() > 1e-9 {
            return Err(refuse("its axes must both be the base's z axis"));
        }
        let (p1, p2, tool) = (kin.p[0], kin.p[1], kin.tool.pos);
        if (tool.z - p1.z).abs() > 1e-9 {
            return Err(refuse("the tool must lie in the plane of motion"));
        }
        let planar = |v: Vector3<f64>| v.xy().norm();
        Ok(Planar2R { robot: robot.clone(), l1: planar(p2 - p1), l2: planar(tool - p2) })
    }
}

impl ClosedForm for Planar2R {
    const NAME: &'static str = "planar-2r";

    fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Both elbows for the target's position; its orientation is left to the
    /// contract, which keeps the elbow whose tool turn matches.
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> kinema::Result<()> {
        let (x, y) = (target.pos.x, target.pos.y);
        let c2 = (x * x + y * y - self.l1 * self.l1 - self.l2 * self.l2) / (2.0 * self.l1 * self.l2);
        if !(-1.0..=1.0).contains(&c2) {
            return Err(Error::Unreachable {
                solver: Self::NAME.into(),
                reason: kinema::ik::Unreachable::NotReached { detail: "outside the annulus the links reach".into() },
                closest: None,
            });
        }
        out.clear();
        for (sign, branch) in [(1.0, "elbow-1"), (-1.0, "elbow-2")] {
            let q2 = sign * c2.acos();
            let q1 = y.atan2(x) - (self.l2 * q2.sin()).atan2(self.l1 + self.l2 * q2.cos());
            let q1 = q1.sin().atan2(q1.cos());
            out.push(&[q1, q2], branch);
        }
        Ok(())
    }
}

impl Family for Planar2R {}

const ARM: &str = r#"name = "toy-planar"
source = "tests/all/ik_toy_family.rs"
convention = "standard"
[units]
length = "m"
angle = "rad"
[[joint]]
name = "shoulder"
d = 0
a = 0.4
alpha = 0
min = -3.1
max = 3.1
[[joint]]
name = "elbow"
d = 0
a = 0.3
alpha = 0
min = -3.1
max = 3.1
[poses]
home = [0, 0]
"#;

#[test]
fn a_family_in_one_file_and_one_registry_line_solves_through_the_contract() {
    let robot = Robot::from_toml_str(ARM, "toy.toml").unwrap();
    assert!(registry::fit(&robot).is_none(), "no built-in family takes the toy arm");
    let registry: Vec<Entry> = FAMILIES
        .iter()
        .copied()
        .chain([Entry { name: "planar-2r", typed: &[], fit: |r| boxed(Planar2R::new(r)) }])
        .collect();
    let fitted = registry::fit_in(&registry, &robot).expect("the toy family fits its arm");
    assert_eq!(fitted.name(), "planar-2r");
    let mut rng = ChaCha8Rng::seed_from_u64(0x2e);
    for _ in 0..200 {
        let q = [rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0)];
        let target = IkTarget::Pose(robot.fk(&q).unwrap().world_from_tool);
        let request = IkRequest { solver: SolverChoice::Analytic, all: true, ..Default::default() };
        let answer = solve_target_with(&robot, Some(fitted.as_ref()), &target, &request).unwrap();
        assert_eq!(answer.solver, "planar-2r");
        // The other elbow turns the tool differently: the contract measured and dropped it.
        assert!(answer.solutions.len() == 1 && answer.discarded.len() == 1 || q[1].abs() < 1e-6, "{answer:?}");
        for s in &answer.solutions {
            assert!(s.position_error < 1e-9 && s.orientation_error < 1e-9, "{s:?}");
        }
        assert!(
            answer.solutions.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)),
            "{q:?}: {:?}",
            answer.solutions
        );
    }
    // An unreachable target is the family's refusal, said through the contract.
    let far = IkTarget::Pose(Pose::translation(2.0, 0.0, 0.0));
    let request = IkRequest { solver: SolverChoice::Analytic, ..Default::default() };
    let e = solve_target_with(&robot, Some(fitted.as_ref()), &far, &request).unwrap_err().to_string();
    assert!(e.contains("planar-2r") && e.contains("annulus"), "{e}");
}

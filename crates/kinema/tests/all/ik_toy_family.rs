//! A closed-form family added from outside the library in one file plus one
//! registry line: a planar two-link arm, fitted from its joint axes at q = 0,
//! whose kernel alone (through [`ClosedForm`]) makes it an IK solver that the
//! request layer and the contract take as they take the built-in families,
//! with a typed target of its own (the tool point and the tool's heading)
//! that a door's named components select through the registry.

use kinema::ik::family::Family;
use kinema::ik::geo::Kinematics;
use kinema::ik::registry::{self, boxed, typed_target_in, Entry, FAMILIES};
use kinema::ik::{solve_target_with, CandidateSet, ClosedForm, IkRequest, IkTarget, SolverChoice};
use kinema::ik::{Component, Quantity, Solution, TypedKind, TypedTarget};
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

/// The toy's typed target: the tool point with the heading of link 2
/// (q1 + q2) in the plane, which picks one elbow.
static HEADING: TypedKind = TypedKind {
    name: "heading",
    components: &[Component { name: "heading", quantity: Quantity::Angle }],
    summary: "planar 2R: position and heading",
};

static TOY_KINDS: [&TypedKind; 1] = [&HEADING];

/// The angle between two headings \[rad\], in [0, π].
fn turn(a: f64, b: f64) -> f64 {
    let d = a - b;
    d.sin().atan2(d.cos()).abs()
}

impl Family for Planar2R {
    /// Registered outside [`FAMILIES`]: it says itself which kinds it owns.
    fn owns(&self, kind: &TypedKind) -> bool {
        *kind == HEADING
    }

    /// Both elbows for the point; the contract keeps the one whose heading
    /// [`Family::typed_orientation_error`] finds on target.
    fn solve_typed(&self, target: &TypedTarget, _q0: Option<&[f64]>) -> kinema::Result<Vec<Solution>> {
        let [x, y, z] = target.position;
        let mut out = CandidateSet::new();
        self.kernel(&Pose::translation(x, y, z), &mut out)?;
        Ok(out.unmeasured())
    }

    fn typed_orientation_error(&self, target: &TypedTarget, reached: &Pose) -> f64 {
        turn(target.angle("heading"), reached.rot[(1, 0)].atan2(reached.rot[(0, 0)]))
    }
}

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

/// The built-in families and the toy: its one registry line.
fn with_toy() -> Vec<Entry> {
    FAMILIES
        .iter()
        .copied()
        .chain([Entry { name: "planar-2r", typed: &TOY_KINDS, fit: |r| boxed(Planar2R::new(r)) }])
        .collect()
}

#[test]
fn the_toy_familys_typed_target_is_read_by_name_and_solved_through_the_contract() {
    let robot = Robot::from_toml_str(ARM, "toy.toml").unwrap();
    let registry = with_toy();
    let fitted = registry::fit_in(&registry, &robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x2f);
    for _ in 0..200 {
        let q = [rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0)];
        let p = robot.fk(&q).unwrap().world_from_tool.pos;
        let heading = [q[0] + q[1]];
        // As a door reads it: named components, the registry says which kind they make.
        let typed = typed_target_in(&registry, [p.x, p.y, p.z], &[("heading", &heading)]).unwrap().unwrap();
        assert_eq!(typed.kind.name, "heading");
        let request = IkRequest { all: true, ..Default::default() };
        let answer = solve_target_with(&robot, Some(fitted.as_ref()), &IkTarget::Typed(typed), &request).unwrap();
        assert_eq!(answer.solver, "planar-2r");
        assert!(!answer.solutions.is_empty());
        for s in &answer.solutions {
            assert!(s.position_error < 1e-9 && s.orientation_error < 1e-9, "{s:?}");
            assert!(turn(s.q[0], q[0]) < 1e-9 && turn(s.q[1], q[1]) < 1e-9, "{q:?}: {s:?}");
        }
    }
    // The built-in registry does not know the toy's component, and says which ones it knows.
    let e = registry::typed_target([0.5, 0.0, 0.0], &[("heading", Some(&[0.0]))]).unwrap_err().to_string();
    assert!(e.contains("heading") && e.contains("pitch-roll"), "{e}");
}

#[test]
fn a_family_in_one_file_and_one_registry_line_solves_through_the_contract() {
    let robot = Robot::from_toml_str(ARM, "toy.toml").unwrap();
    assert!(registry::fit(&robot).is_none(), "no built-in family takes the toy arm");
    let registry = with_toy();
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

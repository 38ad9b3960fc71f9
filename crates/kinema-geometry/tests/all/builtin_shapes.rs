//! The link shapes of the built-in robots (`[[shape]]` in `robots/*.toml`):
//! free of self-collision at every named pose, enclosing each link's DH
//! centre line, and colliding when the arm is folded onto itself.

use kinema::nalgebra::{Point3, Vector3};
use kinema::{DhConvention, JointType, LinkGeometry, Pose, Robot};
use kinema_geometry::{
    collides, load_robot_geometry, pair_distance, CollisionPairs, LinkShape, Placement, RobotGeometry, Shape,
};

fn load(name: &str) -> (Robot, RobotGeometry) {
    load_robot_geometry(name, &Default::default()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn every_builtin_has_shapes_and_named_poses_are_free() {
    for name in kinema::builtin_names() {
        let (robot, geometry) = load(name);
        assert!(geometry.len() >= robot.dof() - 2, "{name}: {} shapes", geometry.len());
        let pairs = CollisionPairs::self_collision(&geometry);
        assert!(!pairs.is_empty(), "{name}");
        let zero = vec![0.0; robot.dof()];
        let poses = robot.poses().iter().map(|p| (p.name.as_str(), p.q.clone()));
        for (pose, q) in poses.chain([("zeros", zero)]) {
            let placement = Placement::of(&robot, &geometry, &q).unwrap();
            if let Some((a, b)) = collides(&geometry, &placement, &pairs, 0.0).unwrap() {
                let (sa, sb) = (geometry.shapes()[a].name(), geometry.shapes()[b].name());
                panic!("{name} at `{pose}`: {sa} and {sb} collide");
            }
        }
    }
}

/// Points along link i's DH centre line, in link i's frame: standard DH from
/// joint i's axis point (frame i−1's origin) along d, then a, to frame i's
/// origin; modified DH from d below frame i along its z axis, then a of the
/// next row along x. Variable (prismatic) lengths are left out.
fn centre_line(robot: &Robot, i: usize) -> Vec<Vector3<f64>> {
    let dh = |k: usize| match robot.joints()[k].geometry {
        LinkGeometry::Dh { convention, d, a, alpha, .. } => (convention, d, a, alpha),
        _ => panic!("{}: not a DH robot", robot.name()),
    };
    let (convention, d, a, alpha) = dh(i - 1);
    let d = if robot.joints()[i - 1].kind == JointType::Prismatic { 0.0 } else { d };
    let corners = match convention {
        DhConvention::Standard => {
            [Vector3::new(-a, -d * alpha.sin(), -d * alpha.cos()), Vector3::new(-a, 0.0, 0.0), Vector3::zeros()]
        }
        DhConvention::Modified => {
            let next_a = if i < robot.dof() { dh(i).2 } else { 0.0 };
            [Vector3::new(0.0, 0.0, -d), Vector3::zeros(), Vector3::new(next_a, 0.0, 0.0)]
        }
    };
    let mut points = Vec::new();
    for w in corners.windows(2) {
        for k in 0..=10 {
            points.push(w[0] + (w[1] - w[0]) * (k as f64 / 10.0));
        }
    }
    points
}

#[test]
fn shapes_enclose_each_links_centre_line() {
    // A point is enclosed when a probe ball of 1 µm there overlaps a shape of
    // its link or of a neighbour (the housings of short links cover the joints).
    for name in kinema::builtin_names() {
        let (robot, geometry) = load(name);
        let q = robot.home().to_vec();
        for link in 1..=robot.dof() {
            for (k, p) in centre_line(&robot, link).into_iter().enumerate() {
                let probe =
                    LinkShape::new("probe", link, Pose::translation(p.x, p.y, p.z), Shape::Sphere { radius: 1e-6 })
                        .unwrap();
                let mut shapes = geometry.shapes().to_vec();
                shapes.push(probe);
                let probed = RobotGeometry::new(&robot, shapes).unwrap();
                let placement = Placement::of(&robot, &probed, &q).unwrap();
                let at = probed.len() - 1;
                let inside = (0..geometry.len())
                    .filter(|&s| geometry.shapes()[s].link().abs_diff(link) <= 1)
                    .any(|s| pair_distance(&probed, &placement, s, at).unwrap().distance <= 0.0);
                let world = Point3::from(placement.frames()[link].transform_point(&p));
                assert!(inside, "{name}: link {link}, centre-line point {k} at {world:?} is in no shape");
            }
        }
    }
}

#[test]
fn folded_arms_collide() {
    // The elbow or the shoulder at (or near) its limit, folding the arm onto
    // itself; each names the pair of links that must meet. The PUMA 560 and
    // the SCARA have no such configuration within their limits: their
    // offsets keep the forearm beside the upper arm and column.
    let deg = std::f64::consts::PI / 180.0;
    let cases: [(&str, &[f64], (usize, usize)); 5] = [
        ("ur5", &[0.0, -90.0, -180.0, -90.0, -90.0, 0.0], (2, 4)),
        ("lbr-iiwa-14-r820", &[0.0, -120.0, 0.0, 0.0, 0.0, 0.0, 0.0], (1, 3)),
        ("panda", &[0.0, 33.8, 0.0, -171.9, 0.0, 114.6, 45.0], (1, 7)),
        ("rommel", &[0.0, 0.0, -150.0, 0.0, 0.0], (2, 4)),
        ("scorbot-er-v-plus", &[0.0, -35.0, -90.0, -90.0, 0.0], (1, 5)),
    ];
    for (name, q_deg, links) in cases {
        let (robot, geometry) = load(name);
        let q: Vec<f64> = q_deg.iter().map(|v| v * deg).collect();
        assert!(robot.fk(&q).unwrap().within_limits(), "{name}: {q_deg:?} is outside the limits");
        let placement = Placement::of(&robot, &geometry, &q).unwrap();
        let pairs = CollisionPairs::self_collision(&geometry);
        let touching = kinema_geometry::contacts(&geometry, &placement, &pairs, 0.0).unwrap();
        let link_pairs: Vec<(usize, usize)> =
            touching.iter().map(|c| (geometry.shapes()[c.a].link(), geometry.shapes()[c.b].link())).collect();
        assert!(
            link_pairs.iter().any(|&(a, b)| (a.min(b), a.max(b)) == links),
            "{name} at {q_deg:?}: links {links:?} should touch; touching {link_pairs:?}"
        );
    }
}

#[test]
fn shape_tables_are_checked_with_file_and_line() {
    let base = kinema::builtin_source("ur5").unwrap();
    let robot = Robot::from_toml_str(base, "ur5.toml").unwrap();
    let dir = std::path::Path::new(".");
    let error = |text: String| kinema_geometry::toml_geometry(&robot, &text, "bad.toml", dir).unwrap_err().to_string();
    let line_of = |text: &str, needle: &str| text[..text.find(needle).unwrap()].matches('\n').count() + 1;

    let unknown = base.replacen("capsule = { radius = 0.06, length = 0.425 }", "capsul = { radius = 0.06 }", 1);
    let e = error(unknown.clone());
    assert!(e.starts_with(&format!("bad.toml:{}:", line_of(&unknown, "capsul ="))), "{e}");
    assert!(e.contains("capsul") && e.contains("shape[1]"), "{e}");

    let two =
        base.replacen("capsule = { radius = 0.06, length = 0.425 }", "sphere = { radius = 1 }\nbox = [1, 1, 1]", 1);
    let e = error(two);
    assert!(e.contains("sphere and box") && e.contains("exactly one of"), "{e}");

    let negative = base.replacen("radius = 0.06, length = 0.425", "radius = -0.06, length = 0.425", 1);
    let e = error(negative);
    assert!(e.contains("shape[1]") && e.contains("radius is -0.06"), "{e}");

    let no_link = base.replacen("link = 2\n", "link = 9\n", 1);
    let e = error(no_link);
    assert!(e.contains("shape[1].link") && e.contains("expected 0 (base) to 6"), "{e}");

    let mm = base.replacen("length = \"m\"", "length = \"mm\"", 1).replacen(
        "radius = 0.06, length = 0.425",
        "radius = \"60mm\", length = 425",
        1,
    );
    let mm_robot = Robot::from_toml_str(&mm, "mm.toml").unwrap();
    let g = kinema_geometry::toml_geometry(&mm_robot, &mm, "mm.toml", dir).unwrap();
    assert_eq!(g.shapes()[1].shape(), &Shape::Capsule { radius: 0.06, length: 0.425 });
}

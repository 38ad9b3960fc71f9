//! Scene files: obstacles against a built-in robot, a `kinema cell` file read
//! as a scene, and errors that name the key or file.

use std::path::Path;

use kinema_geometry::{collides, load_robot_geometry, min_distance, CollisionPairs, Placement, Scene};

fn scene(text: &str) -> kinema_geometry::Result<Scene> {
    Scene::from_toml(text, "lab.toml", Path::new("."))
}

#[test]
fn an_obstacle_on_the_arm_collides_and_one_beside_it_does_not() {
    let (robot, geometry) = load_robot_geometry("ur5", &Default::default()).unwrap();
    let home = robot.home().to_vec();
    let wrist = robot.link_frames(&home).unwrap()[4].pos;
    let ball = |up: f64| {
        format!(
            "[[obstacle]]\nname = \"ball\"\nsphere = {{ radius = 0.05 }}\npose = [{}, {}, {}, 0, 0, 0]\n",
            wrist.x,
            wrist.y,
            wrist.z + up
        )
    };
    let pairs = CollisionPairs::self_collision(&geometry);
    for (up, hit) in [(0.0, true), (1.0, false)] {
        let s = scene(&ball(up)).unwrap();
        let (all, all_pairs) = s.with_robot(&robot, &geometry, &pairs).unwrap();
        assert_eq!(all.len(), geometry.len() + 1);
        assert_eq!(all_pairs.len(), pairs.len() + geometry.len());
        let placement = Placement::of(&robot, &all, &home).unwrap();
        let first = collides(&all, &placement, &all_pairs, 0.0).unwrap();
        assert_eq!(first.is_some(), hit, "ball {up} m above the wrist");
        if let Some((a, b)) = first {
            assert_eq!(all.shapes()[b].link_name(), "ball");
            assert!(all.shapes()[a].link() >= 3, "{}", all.shapes()[a].name());
        } else {
            // The ball's centre is 1 m above the wrist centre, the arm's highest point at home: the
            // nearest link is 0.5–1 m away, and the closest pair of all is no farther.
            let ball = all.len() - 1;
            let to_ball = (0..geometry.len())
                .filter(|&s| all_pairs.contains(s, ball))
                .map(|s| kinema_geometry::pair_distance(&all, &placement, s, ball).unwrap().distance)
                .fold(f64::INFINITY, f64::min);
            assert!(to_ball > 0.5 && to_ball < 1.0, "{to_ball}");
            let d = min_distance(&all, &placement, &all_pairs).unwrap().unwrap();
            assert!(d.distance <= to_ball, "{d:?}");
        }
    }
}

#[test]
fn units_rpy_and_a_cell_file_as_a_scene() {
    let s = scene(
        "rpy = \"zyx\"\n[[obstacle]]\nname = \"wall\"\nbox = [\"20mm\", 1, 1]\npose = [\"1000mm\", 0, 0.5, 0, 0, \"90deg\"]\n",
    )
    .unwrap();
    let w = &s.obstacles[0];
    assert!((w.world_from_shape.pos.x - 1.0).abs() < 1e-15);
    assert!((w.world_from_shape.rot[(1, 0)] - 1.0).abs() < 1e-15, "yaw 90°: x → y");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cells");
    let cell = Scene::load(dir.join("seed004_two_iiwa.toml")).unwrap();
    assert_eq!(cell.robots.len(), 2);
    assert!(cell.obstacles.is_empty());
    assert_eq!(cell.robots[1].robot, "lbr-iiwa-14-r820");
    assert!((cell.robots[1].world_from_base.pos.x - 1.2).abs() < 1e-12);
    assert!((cell.robots[1].world_from_base.rot[(0, 0)] + 1.0).abs() < 1e-12, "turned 180°");
}

#[test]
fn errors_name_the_key_and_what_is_expected() {
    let e = scene("[[obstacle]]\nname = \"b\"\nbox = [1, 1, 1]\ncolour = \"red\"\n").unwrap_err().to_string();
    assert!(e.starts_with("lab.toml:4:") && e.contains("colour") && e.contains("expected one of"), "{e}");
    let e = scene("[[obstacle]]\nname = \"b\"\nbox = [1, 1, 1]\nsphere = { radius = 1 }\n").unwrap_err().to_string();
    assert!(e.contains("box and sphere") || e.contains("sphere and box"), "{e}");
    let e = scene("[[obstacle]]\nname = \"b\"\nmesh = \"no/such.stl\"\n").unwrap_err().to_string();
    assert!(e.starts_with("lab.toml:3:") && e.contains("no/such.stl") && e.contains("not found"), "{e}");
    let e = scene("[[obstacle]]\nname = \"b\"\nbox = [1, -1, 1]\n").unwrap_err().to_string();
    assert!(e.contains("obstacle[0]") && e.contains("box size along y is -1"), "{e}");
    let e = scene("[[obstacle]]\nname = \"b\"\nlink = 2\nbox = [1, 1, 1]\n").unwrap_err().to_string();
    assert!(e.contains("fixed in the world"), "{e}");
    let e = scene("[[obstacle]]\nname = \"b\"\nbox = [1, 1, 1]\npose = [0, 0, \"1 parsec\", 0, 0, 0]\n").unwrap_err();
    assert!(e.to_string().contains("unknown unit `parsec`"), "{e}");
    let e = scene("wind = 3\n").unwrap_err().to_string();
    assert!(e.contains("wind") && e.contains("obstacle"), "{e}");
}

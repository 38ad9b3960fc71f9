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

/// examples/scenes/two-iiwas.toml: seed 004's two iiwas facing each other
/// 1.2 m apart, the drawer robot standing with its arm stretched towards the
/// holder.
fn two_iiwas_path() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/two-iiwas.toml")
}

fn two_iiwas_text() -> String {
    std::fs::read_to_string(two_iiwas_path()).unwrap()
}

#[test]
fn a_scene_robot_stands_at_its_start_as_an_obstacle() {
    use kinema_geometry::CollisionCheck;
    use std::f64::consts::FRAC_PI_2;
    let options = kinema_geometry::CheckOptions { scene: Some(two_iiwas_path()), ..Default::default() };
    let scene = Scene::load(two_iiwas_path()).unwrap();
    // Each obstacle of the drawer robot sits where the core's FK of the placed robot puts its link.
    let standing = scene.standing(Some("holder"), &Default::default()).unwrap();
    let drawer = scene.member("drawer").unwrap();
    let (placed, geometry) = drawer.load(&Default::default()).unwrap();
    let frames = placed.link_frames(&drawer.standing_q(&placed).unwrap()).unwrap();
    assert_eq!(standing.obstacles.len(), geometry.len());
    for (o, s) in standing.obstacles.iter().zip(geometry.shapes()) {
        let expected = frames[s.link()] * *s.link_from_shape();
        assert!((o.world_from_shape.pos - expected.pos).norm() < 1e-12, "{}", o.name);
        assert!((o.world_from_shape.rot - expected.rot).norm() < 1e-12, "{}", o.name);
        assert_eq!(o.body, format!("drawer/{}", s.link_name()));
    }
    // The holder, named as in the scene, reaching towards the drawer's arm hits it; turned away it is free.
    let check = CollisionCheck::load("holder", &options).unwrap();
    let reach = [0.0, FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0];
    let (_, b) = check.first_collision(&reach).unwrap().expect("the two arms overlap");
    assert!(check.body(b).starts_with("drawer/link"), "{}", check.body(b));
    assert_eq!(check.first_collision(&[FRAC_PI_2, FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap(), None);
    // It is not its own obstacle: at home it is free. The same arm not named as a member
    // stands at the origin too, inside the holder standing there.
    assert_eq!(check.first_collision(&[0.0; 7]).unwrap(), None);
    let stranger = CollisionCheck::load("lbr-iiwa-14-r820", &options).unwrap();
    let (_, b) = stranger.first_collision(&[0.0; 7]).unwrap().expect("inside the holder");
    assert!(stranger.body(b).starts_with("holder/"), "{}", stranger.body(b));
}

#[test]
fn a_bad_start_or_member_name_is_an_error_naming_it() {
    let text = two_iiwas_text().replace("start = \"0, 1.5707963267948966", "start = \"0, x");
    let s = scene(&text).unwrap();
    let e = s.standing(None, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("drawer") && e.contains("start") && e.contains("`x`"), "{e}");
    let e = scene(&two_iiwas_text()).unwrap().standing(Some("nobody"), &Default::default()).unwrap_err().to_string();
    assert!(e.contains("nobody") && e.contains("holder, drawer"), "{e}");
    let e = scene(&two_iiwas_text().replace("start = \"0, 1.57", "start = \"qq")).unwrap();
    let e = e.standing(None, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("drawer") && e.contains("qq"), "{e}");
}

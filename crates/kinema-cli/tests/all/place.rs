//! `kinema place`: the ranked CSV holds every candidate base once, best
//! first, with the scores the core gives for the same grid; bad tasks and
//! regions are refused.

use kinema::ik::IkRequest;
use kinema::reach::place::{base_candidates, place_scores, Region};
use kinema::{Pose, Robot, RpyConvention};

use super::cli::{fails, tempdir};
use crate::common::kinema;

const TASK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/tasks/table-pick.csv");

/// The example task's poses, read independently of the CLI's parser.
fn task_poses() -> Vec<Pose> {
    std::fs::read_to_string(TASK)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
            Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], RpyConvention::Zyx)
        })
        .collect()
}

#[test]
fn place_ranks_every_base_with_the_cores_scores() {
    let dir = tempdir("place");
    let out = dir.join("ranks.csv").display().to_string();
    let r = kinema(&[
        "place",
        "--robot",
        "puma560",
        "--task",
        TASK,
        "--region",
        "0.5:1.5,-0.5:0.5",
        "--resolution",
        "0.25",
        "--yaw-steps",
        "2",
        "--out",
        &out,
    ]);
    assert!(r.ok, "{}", r.stderr);
    let robot = Robot::builtin("puma560").unwrap();
    let region = Region { x: (0.5, 1.5), y: (-0.5, 0.5), z: None };
    let bases = base_candidates(&robot, &region, 0.25, 2).unwrap();
    let task = task_poses();
    let scores = place_scores(&robot, &bases, &task, &IkRequest::default(), &|| {}, &|| false).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("rank,x,y,z,yaw,reached,fraction"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), bases.len());
    let mut seen = vec![false; bases.len()];
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[0] as usize, k + 1);
        let i = bases
            .iter()
            .position(|b| {
                let yaw = (b.rot[(1, 0)]).atan2(b.rot[(0, 0)]).rem_euclid(std::f64::consts::TAU);
                (b.pos.x - row[1]).abs() < 1e-6 && (b.pos.y - row[2]).abs() < 1e-6 && (yaw - row[4]).abs() < 1e-5
            })
            .unwrap_or_else(|| panic!("row {row:?} is no candidate"));
        assert!(!seen[i], "base {i} listed twice");
        seen[i] = true;
        assert_eq!(row[5] as u32, scores[i], "{row:?}");
        assert!((row[6] - scores[i] as f64 / task.len() as f64).abs() < 1e-6);
        if k > 0 {
            assert!(rows[k - 1][5] >= row[5], "not ranked: {row:?}");
        }
    }
    assert!(rows[0][6] > rows[rows.len() - 1][6], "every base scores the same");
}

#[test]
fn place_refuses_positions_and_bad_regions() {
    let dir = tempdir("place-bad");
    let positions = dir.join("positions.csv");
    std::fs::write(&positions, "0.5,0,0.5\n").unwrap();
    let out = dir.join("ranks.csv").display().to_string();
    let e = fails(&["place", "--robot", "puma560", "--task", positions.to_str().unwrap(), "--out", &out]);
    assert!(e.contains("full poses"), "{e}");
    for region in ["1:0", "0:1,0", "a:1,0:1", "0:1,0:1,0,0"] {
        fails(&["place", "--robot", "puma560", "--task", TASK, "--region", region, "--out", &out]);
    }
    assert!(!std::path::Path::new(&out).exists(), "a refused run wrote its output");
}

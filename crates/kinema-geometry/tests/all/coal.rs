//! The differential test against Pinocchio + coal (ignored: it needs their
//! CSV, written by `benchmarks/coal_peers.py`; run by
//! `benchmarks/run_coal_peers.sh`). On example-robot-data's Panda and UR5
//! collision meshes, with the pairs their SRDFs leave: the same pair set, the
//! same verdict per pair (except pairs within `BAND` of touching, counted),
//! and the same distance between separated pairs within `BAND` — compared
//! only for pairs coal finds closer than `NEAR`: parry's mesh–mesh distance
//! costs milliseconds a pair, and distances far from touching do not decide
//! any verdict.

use std::collections::HashMap;
use std::path::PathBuf;

use kinema_geometry::{
    collides, collides_fast, load_urdf, pair_distance, CollisionPairs, Placement, Spheres, Srdf, UrdfOptions, UrdfRobot,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::fast_paths::{assert_same_closest, first_closer};

/// How close to touching a pair may be for the two libraries to differ on
/// its verdict, and how far their distances may differ \[m\].
const BAND: f64 = 1e-6;

/// Pairs at least this far apart by coal's distance get their verdict
/// compared but not their distance \[m\].
const NEAR: f64 = 0.02;

struct Robot {
    urdf: UrdfRobot,
    pairs: Vec<(usize, usize)>,
}

fn robot(header: &[&str]) -> Robot {
    let (urdf, srdf, share, tip) = (header[2], header[3], header[4], header[5]);
    let options = UrdfOptions { tip: Some(tip.into()), package_paths: vec![PathBuf::from(share)], skip_visual: true };
    let urdf = load_urdf(urdf, &options).unwrap();
    let g = &urdf.collision;
    let mut checked = CollisionPairs::all(g);
    Srdf::load(srdf).unwrap().apply(g, &urdf.links, &mut checked).unwrap();
    // coal's pair order, by name; kinema must check exactly the same pairs.
    let pairs: Vec<(usize, usize)> = header[6..]
        .iter()
        .map(|p| {
            let (a, b) = p.split_once('|').unwrap();
            let (a, b) = (g.find(a).unwrap_or_else(|| panic!("no shape {a}")), g.find(b).unwrap());
            assert!(checked.contains(a, b), "{}: coal checks {p}, kinema does not", header[1]);
            (a, b)
        })
        .collect();
    assert_eq!(pairs.len(), checked.len(), "{}: kinema checks pairs coal does not", header[1]);
    Robot { urdf, pairs }
}

#[derive(Default)]
struct Tally {
    configurations: usize,
    pair_checks: usize,
    collisions: usize,
    verdicts_in_band: usize,
    verdicts_differ: usize,
    distances: usize,
    max_distance_difference: f64,
    distances_beyond: usize,
}

#[test]
#[ignore = "needs KINEMA_COAL_CSV from benchmarks/coal_peers.py (benchmarks/run_coal_peers.sh)"]
fn matches_coal() {
    let path = std::env::var("KINEMA_COAL_CSV").expect("KINEMA_COAL_CSV: the CSV of benchmarks/coal_peers.py");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut robots: HashMap<String, Robot> = HashMap::new();
    let mut tally: HashMap<String, Tally> = HashMap::new();
    let mut worst: Vec<String> = Vec::new();
    for line in text.lines() {
        let cells: Vec<&str> = line.split(',').collect();
        if cells[0] == "#robot" {
            robots.insert(cells[1].to_string(), robot(&cells));
            continue;
        }
        let r = &robots[cells[0]];
        let (kin, g) = (&r.urdf.robot, &r.urdf.collision);
        let n = kin.dof();
        let q: Vec<f64> = cells[1..=n].iter().map(|c| c.parse().unwrap()).collect();
        let placement = Placement::of(kin, g, &q).unwrap();
        let t = tally.entry(cells[0].to_string()).or_default();
        t.configurations += 1;
        for (k, &(a, b)) in r.pairs.iter().enumerate() {
            let coal_hit = cells[1 + n + 2 * k] == "1";
            let coal_distance: f64 = cells[2 + n + 2 * k].parse().unwrap();
            let one = CollisionPairs::from_pairs(g, [(a, b)]).unwrap();
            let hit = collides(g, &placement, &one, 0.0).unwrap().is_some();
            if hit == coal_hit && coal_distance >= NEAR {
                t.pair_checks += 1;
                t.collisions += usize::from(coal_hit);
                continue;
            }
            let d = pair_distance(g, &placement, a, b).unwrap().distance;
            t.pair_checks += 1;
            t.collisions += usize::from(coal_hit);
            if hit != coal_hit {
                if coal_distance.abs() <= BAND || d.abs() <= BAND {
                    t.verdicts_in_band += 1;
                } else {
                    t.verdicts_differ += 1;
                    worst.push(format!(
                        "{} q {q:?} {}–{}: coal {coal_hit} ({coal_distance:e} m), kinema {hit} ({d:e} m)",
                        cells[0],
                        g.shapes()[a].name(),
                        g.shapes()[b].name()
                    ));
                }
            }
            if !hit && !coal_hit {
                t.distances += 1;
                let diff = (d - coal_distance).abs();
                t.max_distance_difference = t.max_distance_difference.max(diff);
                if diff > BAND {
                    t.distances_beyond += 1;
                    worst.push(format!(
                        "{} q {q:?} {}–{}: distance coal {coal_distance:e} m, kinema {d:e} m",
                        cells[0],
                        g.shapes()[a].name(),
                        g.shapes()[b].name()
                    ));
                }
            }
        }
    }
    assert!(!tally.is_empty(), "{path} holds no configuration");
    let mut names: Vec<&String> = tally.keys().collect();
    names.sort();
    for name in names {
        let t = &tally[name];
        println!(
            "{name}: {} configurations, {} pair checks, {} in collision (coal); verdicts: {} differ within {BAND:e} m of touching, {} beyond; distances of {} separated pairs within {NEAR} m: max difference {:.3e} m, {} beyond {BAND:e} m",
            t.configurations,
            t.pair_checks,
            t.collisions,
            t.verdicts_in_band,
            t.verdicts_differ,
            t.distances,
            t.max_distance_difference,
            t.distances_beyond
        );
    }
    for w in worst.iter().take(10) {
        println!("  {w}");
    }
    assert!(worst.is_empty(), "{} disagreements with coal outside {BAND:e} m (first ones above)", worst.len());
}

/// The fast paths on coal's Panda (example-robot-data's collision meshes, the
/// pairs its SRDF leaves): which meshes are convex, and `min_distance` and
/// `collides_fast` against their references at seeded configurations.
#[test]
#[ignore = "needs KINEMA_COAL_CSV from benchmarks/coal_peers.py (benchmarks/run_coal_peers.sh)"]
fn fast_paths_match_the_references_on_the_panda_meshes() {
    let path = std::env::var("KINEMA_COAL_CSV").expect("KINEMA_COAL_CSV: the CSV of benchmarks/coal_peers.py");
    let text = std::fs::read_to_string(&path).unwrap();
    let header: Vec<&str> = text.lines().find(|l| l.starts_with("#robot,panda,")).unwrap().split(',').collect();
    let options =
        UrdfOptions { tip: Some(header[5].into()), package_paths: vec![PathBuf::from(header[4])], skip_visual: true };
    let urdf = load_urdf(header[2], &options).unwrap();
    let (kin, g) = (&urdf.robot, &urdf.collision);
    let mut pairs = CollisionPairs::all(g);
    Srdf::load(header[3]).unwrap().apply(g, &urdf.links, &mut pairs).unwrap();
    let convex: Vec<&str> = g.shapes().iter().filter(|s| s.is_convex_mesh()).map(|s| s.name()).collect();
    println!("panda: {} of {} collision meshes convex: {convex:?}", convex.len(), g.len());
    let spheres = Spheres::fit(g, 4);
    let (mut sp, mut scratch) = (spheres.placement(), Placement::new(g));
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut hits = 0;
    for _ in 0..FAST_PATH_CONFIGURATIONS {
        let q = kin.random_q(&mut rng);
        let placement = Placement::of(kin, g, &q).unwrap();
        assert_same_closest(g, &placement, &pairs, &format!("panda q {q:?}"));
        let exact = first_closer(g, &placement, &pairs, 0.0);
        assert_eq!(collides(g, &placement, &pairs, 0.0).unwrap(), exact, "panda q {q:?}");
        let fast = collides_fast(kin, g, &spheres, &q, &pairs, 0.0, &mut sp, &mut scratch).unwrap();
        assert_eq!(fast, exact, "panda q {q:?}");
        hits += usize::from(exact.is_some());
    }
    println!("panda: {FAST_PATH_CONFIGURATIONS} configurations, {hits} in collision, fast paths as the references");
}

/// Seeded configurations of the fast-path test on the Panda meshes.
const FAST_PATH_CONFIGURATIONS: usize = 2000;

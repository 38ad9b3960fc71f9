//! `--shard i/n` on every batch command (`ik`, `fk` and `collide` with
//! `--input`): the shards' outputs, concatenated in order, are the unsharded
//! output byte for byte, for any number of shards, including more shards
//! than lines.

use std::path::Path;
use std::process::Command;

use kinema::Robot;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::cli::{fails, tempdir};

/// Runs `kinema` and returns its exit code and standard output, bytes as printed.
fn run(args: &[&str]) -> (Option<i32>, Vec<u8>) {
    let out = Command::new(env!("CARGO_BIN_EXE_kinema")).args(args).output().unwrap();
    (out.status.code(), out.stdout)
}

/// The unsharded output of `args` (with `{out}` standing for an output file, or stdout when
/// `args` has none) against the concatenated outputs of `n` shards, for several `n`.
fn shards_concatenate(args: &[&str], dir: &Path) {
    let output = |tag: &str| dir.join(format!("out-{tag}.csv")).display().to_string();
    let with = |out: &str, shard: Option<&str>| {
        let mut a: Vec<String> = args.iter().map(|s| s.replace("{out}", out)).collect();
        if let Some(s) = shard {
            a.extend(["--shard".to_string(), s.to_string()]);
        }
        a
    };
    let to_file = args.contains(&"{out}");
    let produce = |tag: &str, shard: Option<&str>| -> (Option<i32>, Vec<u8>) {
        let out = output(tag);
        let a = with(&out, shard);
        let (code, stdout) = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
        (code, if to_file { std::fs::read(&out).unwrap() } else { stdout })
    };
    let (code, whole) = produce("whole", None);
    assert!(!whole.is_empty());
    for n in [1, 2, 3, 7, 64] {
        let mut joined = Vec::new();
        let mut codes = Vec::new();
        for i in 1..=n {
            let (c, bytes) = produce(&format!("{i}-of-{n}"), Some(&format!("{i}/{n}")));
            joined.extend(bytes);
            codes.push(c);
        }
        assert!(
            joined == whole,
            "{args:?} in {n} shards:\n{}\n---\n{}",
            String::from_utf8_lossy(&joined),
            String::from_utf8_lossy(&whole)
        );
        // A shard fails as the whole batch does when one of its lines does.
        assert!(codes.iter().all(|c| *c == Some(0) || *c == code), "{args:?} in {n}: {codes:?} vs {code:?}");
    }
}

#[test]
fn shards_of_every_batch_command_concatenate_into_the_whole_output() {
    let dir = tempdir("shard");
    let mut rng = ChaCha8Rng::seed_from_u64(3901);
    let ur5 = Robot::builtin("ur5").unwrap();
    let mut qs = Vec::new();
    let mut targets = vec!["# targets, a few out of reach".to_string()];
    for k in 0..41 {
        let q = ur5.random_q(&mut rng);
        qs.push(q.iter().map(|v| format!("{v:?}")).collect::<Vec<_>>().join(","));
        let pose = ur5.fk(&q).unwrap().world_from_tool;
        let reach = if k % 10 == 3 { rng.random_range(2.0..4.0) } else { 1.0 };
        let p = pose.pos * reach;
        let rpy = pose.rpy(kinema::RpyConvention::Zyx);
        targets.push([p.x, p.y, p.z, rpy[0], rpy[1], rpy[2]].map(|v| format!("{v:?}")).join(","));
    }
    let configurations = dir.join("q.csv");
    std::fs::write(&configurations, qs.join("\n")).unwrap();
    let poses = dir.join("targets.csv");
    std::fs::write(&poses, targets.join("\n")).unwrap();
    let (q, t, d) = (configurations.to_str().unwrap(), poses.to_str().unwrap(), dir.as_ref());
    shards_concatenate(&["fk", "--robot", "ur5", "--input", q, "--output", "{out}"], d);
    shards_concatenate(&["ik", "--robot", "ur5", "--input", t, "--output", "{out}"], d);
    shards_concatenate(&["collide", "--robot", "ur5", "--input", q], d);
    shards_concatenate(&["collide", "--robot", "ur5", "--input", q, "--json"], d);
    // Bad shards are named, and --shard needs a batch.
    for bad in ["0/3", "4/3", "2", "x/3"] {
        let e = fails(&["fk", "--robot", "ur5", "--input", q, "--output", "-", "--shard", bad]);
        assert!(e.contains("1 ≤ i ≤ n"), "{bad}: {e}");
    }
    assert!(fails(&["fk", "--robot", "ur5", "--q", "home", "--shard", "1/2"]).contains("--input"));
}

#[test]
fn reach_maps_shard_and_a_scene_only_removes_poses() {
    let dir = tempdir("reach");
    let d = dir.as_ref();
    shards_concatenate(
        &["reach", "--robot", "puma560", "--resolution", "0.3", "--orientations", "4", "--out", "{out}"],
        d,
    );
    // The iiwa on the fume-hood bench: the bench and the hood take voxels away, none is gained.
    let map = |scene: Option<&str>| -> Vec<(String, u32)> {
        let out = dir.join("map.csv");
        let mut args = vec!["reach", "--robot", "lbr-iiwa-14-r820", "--resolution", "0.25", "--orientations", "6"];
        args.extend(scene.map(|s| ["--scene", s]).into_iter().flatten());
        let o = out.to_str().unwrap();
        args.extend(["--out", o]);
        let (code, _) = run(&args);
        assert_eq!(code, Some(0), "{args:?}");
        let text = std::fs::read_to_string(&out).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (f[..3].join(","), f[3].parse().unwrap())
            })
            .collect()
    };
    let free = map(None);
    let hood = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/scenes/fume-hood.toml");
    let in_scene = map(Some(hood));
    assert_eq!(free.len(), in_scene.len());
    let below_bench = |v: &str| v.split(',').nth(2).unwrap().parse::<f64>().unwrap() < -0.1;
    let (mut lost, mut reached) = (0, 0);
    for ((voxel, n), (same, m)) in free.iter().zip(&in_scene) {
        assert_eq!(voxel, same);
        assert!(m <= n, "{voxel}: {m} orientations in the scene, {n} without");
        assert!(!below_bench(voxel) || *m == 0, "{voxel}: reached under the bench");
        lost += n - m;
        reached += n;
    }
    assert!(lost > 0 && lost < reached, "{lost} of {reached} lost to the scene");
    for bad in [["--resolution", "0"], ["--orientations", "0"]] {
        let mut args = vec!["reach", "--robot", "puma560", "--out", "-"];
        args.extend(bad);
        let e = fails(&args);
        assert!(e.contains(&bad[0][2..]), "{bad:?}: {e}");
    }
}

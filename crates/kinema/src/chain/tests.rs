use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{Chain, Layout};
use crate::{Pose, Robot};

/// The dispatched path (AVX2+FMA where available) and the portable path
/// agree on every built-in robot and on chains made of every step kind
/// (both DH conventions, revolute and prismatic, each twist form); on a
/// CPU without FMA they are the same code.
#[test]
fn vector_and_portable_paths_agree() {
    use std::f64::consts::{FRAC_PI_2, PI};

    use crate::model::{DhConvention, Joint, JointType, Limits, LinkGeometry};

    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let check = |chain: &Chain, q: &[f64], what: &str| {
        let n = q.len();
        // Fused and separate multiply-adds round differently; the difference
        // grows with the number of joints (40 joints: ~1e-14 m over a 4 m reach).
        let tol = 1e-14 * (n as f64 / 8.0).max(1.0);
        let (mut a, mut b) = (vec![0.0; 6 * n], vec![0.0; 6 * n]);
        let (p1, p2) = (chain.fk(q).0, chain.fk_portable(q));
        assert!((p1.pos - p2.pos).norm() < tol && (p1.rot - p2.rot).norm() < tol, "{what}");
        for tool in [false, true] {
            for layout in [Layout::ColumnMajor, Layout::RowMajor] {
                // SAFETY: both write only computed values.
                chain.jacobian(q, tool, layout, unsafe { super::as_uninit(&mut a) }, None);
                // SAFETY: as above.
                chain.jacobian_portable(q, tool, layout, unsafe { super::as_uninit(&mut b) }, None);
                let diff = a.iter().zip(&b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                assert!(diff < tol, "{what} {layout:?}: {diff}");
            }
        }
    };
    for name in crate::builtin_names() {
        let r = Robot::builtin(name).unwrap();
        for _ in 0..2000 {
            check(&r.chain, &r.random_q(&mut rng), name);
        }
    }
    let mut kinds = Vec::new();
    for convention in [DhConvention::Standard, DhConvention::Modified] {
        for kind in [JointType::Revolute, JointType::Prismatic] {
            for alpha in [0.0, FRAC_PI_2, -FRAC_PI_2, PI, 0.7] {
                for theta in [0.0, 0.3] {
                    let geometry = LinkGeometry::Dh { convention, d: 0.2, a: -0.1, alpha, theta };
                    kinds.push(Joint {
                        name: "j".into(),
                        kind,
                        geometry,
                        offset: 0.1,
                        limits: Limits::position(-PI, PI),
                    });
                }
            }
        }
    }
    // Every kind after every kind, and all of them in one chain (several angle blocks).
    let base = Pose::rot_x(0.4) * Pose::translation(0.1, 0.0, 0.2);
    for (i, a) in kinds.iter().enumerate() {
        for b in &kinds {
            let chain = Chain::new(&[a.clone(), b.clone(), a.clone()], &base, &Pose::rot_z(0.2));
            check(
                &chain,
                &[rng.random_range(-PI..PI), rng.random_range(-PI..PI), rng.random_range(-PI..PI)],
                &format!("kind {i}"),
            );
        }
    }
    let all = Chain::new(&kinds, &Pose::IDENTITY, &Pose::IDENTITY);
    for _ in 0..200 {
        let q: Vec<f64> = kinds.iter().map(|_| rng.random_range(-PI..PI)).collect();
        check(&all, &q, "all kinds");
    }
    // Every length around the exact-length walks (`EXACT`), in each shape:
    // the dispatched path walks 5, 6 and 7 joints exactly, the portable
    // one the padded block.
    let exact_revolute = |convention: DhConvention| -> Vec<Joint> {
        let exact = |alpha: f64| [0.0, FRAC_PI_2, -FRAC_PI_2, PI].contains(&alpha);
        kinds
            .iter()
            .filter(|j| {
                let LinkGeometry::Dh { convention: c, alpha, .. } = j.geometry else { return false };
                j.kind == JointType::Revolute && c == convention && exact(alpha)
            })
            .cloned()
            .collect()
    };
    let pools = [
        (exact_revolute(DhConvention::Standard), Some(super::Shape::Standard)),
        (exact_revolute(DhConvention::Modified), Some(super::Shape::Modified)),
        (kinds.clone(), None),
    ];
    for len in 1..=9 {
        for (pool, shape) in &pools {
            for round in 0..20 {
                let joints: Vec<Joint> = (0..len).map(|_| pool[rng.random_range(0..pool.len())].clone()).collect();
                let chain = Chain::new(&joints, &base, &Pose::rot_z(0.2));
                if let Some(shape) = shape {
                    assert_eq!(chain.shape, *shape, "{len} joints");
                }
                for _ in 0..10 {
                    let q: Vec<f64> = (0..len).map(|_| rng.random_range(-PI..PI)).collect();
                    check(&chain, &q, &format!("{len} joints, {shape:?}, round {round}"));
                }
            }
        }
    }
}

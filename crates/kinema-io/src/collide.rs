//! A collision check as an answer: in collision or not, the colliding pairs
//! by link or obstacle name, and the closest pair with its witness points —
//! built once here for `kinema collide`, the server and Python.

use kinema_geometry::{CollisionCheck, Placement};
use serde::Serialize;

/// Two bodies, by link name (a robot's) or obstacle name (a scene's).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct CollidePair {
    /// First body.
    pub a: String,
    /// Second body.
    pub b: String,
}

/// The closest pair and how close (world frame).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DistanceAnswer {
    /// Signed distance \[m\]: > 0 apart, < 0 overlapping by that depth.
    pub distance: f64,
    /// First body (link or obstacle name).
    pub a: String,
    /// Second body.
    pub b: String,
    /// The point of `a` nearest to `b` \[m\].
    pub point_a: [f64; 3],
    /// The point of `b` nearest to `a` \[m\].
    pub point_b: [f64; 3],
}

/// `kinema collide` for one configuration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CollideAnswer {
    /// The joint values checked \[rad or m\].
    pub q: Vec<f64>,
    /// Whether any checked pair is closer than the margin.
    pub collision: bool,
    /// The safety margin \[m\].
    pub margin: f64,
    /// The pairs closer than the margin, each once, in check order.
    pub pairs: Vec<CollidePair>,
    /// The closest checked pair (absent when no pair is checked).
    pub min_distance: Option<DistanceAnswer>,
}

impl CollideAnswer {
    /// The answer of `check` at `q`, placed into `placement` (reused across
    /// calls): every colliding body pair and the closest pair.
    pub fn of(
        check: &CollisionCheck,
        q: Vec<f64>,
        placement: &mut Placement,
    ) -> kinema_geometry::Result<CollideAnswer> {
        check.place(&q, placement)?;
        let pairs: Vec<CollidePair> =
            check.colliding_bodies(placement)?.into_iter().map(|(a, b)| CollidePair { a, b }).collect();
        let closest = check.closest(placement)?.map(|p| DistanceAnswer {
            distance: p.distance,
            a: check.body(p.a).to_string(),
            b: check.body(p.b).to_string(),
            point_a: p.point_a.coords.into(),
            point_b: p.point_b.coords.into(),
        });
        Ok(CollideAnswer { q, collision: !pairs.is_empty(), margin: check.margin(), pairs, min_distance: closest })
    }
}

//! Which pairs of shapes are checked against each other.

use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;

/// The pairs of shapes (by index into a [`RobotGeometry`]) that the queries
/// check; every other pair is allowed to touch. Each pair is stored once,
/// lower index first, in a fixed order (the order `collides` reports the
/// first hit in).
///
/// [`CollisionPairs::self_collision`] is the default for one arm; an SRDF's
/// `<disable_collisions>` entries remove pairs with
/// [`CollisionPairs::disable_links`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CollisionPairs {
    shapes: usize,
    pairs: Vec<(u32, u32)>,
}

impl CollisionPairs {
    /// No pair at all.
    pub fn none(geometry: &RobotGeometry) -> CollisionPairs {
        CollisionPairs { shapes: geometry.len(), pairs: Vec::new() }
    }

    /// Every pair of shapes on different links. Shapes on one link are one
    /// rigid body and never checked against each other.
    pub fn all(geometry: &RobotGeometry) -> CollisionPairs {
        Self::filtered(geometry, |a, b| a != b)
    }

    /// Self-collision of a serial arm: every pair of shapes on different
    /// links except links next to each other on the chain (link i and link
    /// i + 1, which touch at their joint by construction).
    ///
    /// # Examples
    /// ```
    /// use kinema::{Pose, Robot};
    /// use kinema_geometry::{CollisionPairs, LinkShape, RobotGeometry, Shape};
    /// let robot = Robot::builtin("ur5")?;
    /// let ball = Shape::Sphere { radius: 0.05 };
    /// let shapes = (0..=6).map(|l| LinkShape::new(format!("s{l}"), l, Pose::IDENTITY, ball.clone()));
    /// let geometry = RobotGeometry::new(&robot, shapes.collect::<Result<_, _>>()?)?;
    /// let pairs = CollisionPairs::self_collision(&geometry);
    /// assert_eq!(pairs.len(), 21 - 6); // 7 links: 21 pairs, 6 of them adjacent
    /// assert!(!pairs.contains(2, 3) && pairs.contains(2, 4));
    /// # Ok::<(), kinema_geometry::Error>(())
    /// ```
    pub fn self_collision(geometry: &RobotGeometry) -> CollisionPairs {
        Self::filtered(geometry, |a, b| a.abs_diff(b) > 1)
    }

    /// The given pairs of shape indices (either order; repeats kept once).
    /// Errors on an index beyond the geometry's shapes or a shape paired with itself.
    pub fn from_pairs(geometry: &RobotGeometry, pairs: impl IntoIterator<Item = (usize, usize)>) -> Result<Self> {
        let mut out = CollisionPairs::none(geometry);
        for (a, b) in pairs {
            if a.max(b) >= geometry.len() || a == b {
                return Err(Error::Mismatch {
                    what: format!("pair ({a}, {b}) (two different shape indices expected)"),
                    got: a.max(b) + 1,
                    expected: geometry.len(),
                });
            }
            let p = (a.min(b) as u32, a.max(b) as u32);
            if !out.pairs.contains(&p) {
                out.pairs.push(p);
            }
        }
        Ok(out)
    }

    fn filtered(geometry: &RobotGeometry, keep: impl Fn(usize, usize) -> bool) -> CollisionPairs {
        let shapes = geometry.shapes();
        let mut pairs = Vec::new();
        for (a, sa) in shapes.iter().enumerate() {
            for (b, sb) in shapes.iter().enumerate().skip(a + 1) {
                if keep(sa.link(), sb.link()) {
                    pairs.push((a as u32, b as u32));
                }
            }
        }
        CollisionPairs { shapes: shapes.len(), pairs }
    }

    /// Stops checking shapes `a` and `b` against each other; whether they were checked.
    pub fn disable(&mut self, a: usize, b: usize) -> bool {
        let p = (a.min(b) as u32, a.max(b) as u32);
        let before = self.pairs.len();
        self.pairs.retain(|q| *q != p);
        self.pairs.len() != before
    }

    /// Stops checking every shape of the link named `a` against every shape
    /// of the link named `b` (link names as [`crate::LinkShape::link_name`]
    /// gives them, e.g. the URDF's): an SRDF `<disable_collisions>` entry.
    /// Returns how many pairs were removed.
    pub fn disable_links(&mut self, geometry: &RobotGeometry, a: &str, b: &str) -> usize {
        let shapes = geometry.shapes();
        let before = self.pairs.len();
        self.pairs.retain(|&(i, j)| {
            let (li, lj) = (shapes[i as usize].link_name(), shapes[j as usize].link_name());
            !((li == a && lj == b) || (li == b && lj == a))
        });
        before - self.pairs.len()
    }

    /// Whether shapes `a` and `b` are checked against each other.
    pub fn contains(&self, a: usize, b: usize) -> bool {
        self.pairs.contains(&(a.min(b) as u32, a.max(b) as u32))
    }

    /// The pairs, lower index first.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (usize, usize)> + '_ {
        self.pairs.iter().map(|&(a, b)| (a as usize, b as usize))
    }

    /// Pair `n` in check order (panics when `n` ≥ [`len`](Self::len)).
    pub(crate) fn get(&self, n: usize) -> (usize, usize) {
        let (a, b) = self.pairs[n];
        (a as usize, b as usize)
    }

    /// The number of pairs.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// Whether no pair is checked.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The number of shapes of the geometry it was made for.
    pub fn shape_count(&self) -> usize {
        self.shapes
    }
}

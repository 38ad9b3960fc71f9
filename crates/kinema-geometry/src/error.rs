//! The error type of `kinema-geometry`.

use std::path::PathBuf;

/// Everything that can go wrong while loading link geometry or asking it a
/// question. Each variant names what was wrong and what was expected.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// An error of the kinematic core (a URDF that cannot be read, a joint
    /// vector of the wrong length, a file that cannot be read, …).
    #[error(transparent)]
    Kinema(#[from] kinema::Error),
    /// A mesh named by a URDF that is in none of the places it may be.
    #[error(
        "{urdf}: link `{link}`: mesh `{uri}` not found; looked in: {}{}",
        list(searched),
        if uri.starts_with("package://") { " (add the directory that holds the package to the package search path)" } else { "" }
    )]
    MeshNotFound {
        /// The URDF file (or `<string>`).
        urdf: String,
        /// The link whose `<collision>` or `<visual>` names it.
        link: String,
        /// The file name as the URDF gives it.
        uri: String,
        /// Every path tried, in order.
        searched: Vec<PathBuf>,
    },
    /// A mesh file that cannot be used: unreadable format, no triangles,
    /// non-finite vertices, or a hull that encloses no volume.
    #[error("mesh `{path}`: {message}")]
    Mesh {
        /// Path as given or resolved.
        path: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A shape with a dimension that is not a positive finite length, or a
    /// pose that is not finite.
    #[error("shape `{name}`: {message}")]
    Shape {
        /// The shape's name.
        name: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A shape attached to a link the robot does not have.
    #[error("shape `{name}` rides on link {link}, but robot `{robot}` has links 0 (base) to {dof}")]
    NoSuchLink {
        /// The shape's name.
        name: String,
        /// The link index asked for.
        link: usize,
        /// Robot name.
        robot: String,
        /// The robot's joint count (its last link's index).
        dof: usize,
    },
    /// A pair of shapes the collision library has no algorithm for.
    #[error("no collision algorithm for the pair `{a}` – `{b}` ({kinds})")]
    UnsupportedPair {
        /// First shape's name.
        a: String,
        /// Second shape's name.
        b: String,
        /// The two shape kinds.
        kinds: String,
    },
    /// An SRDF that cannot be read, or that names a link the robot does not have.
    #[error("{file}: {message}")]
    Srdf {
        /// The SRDF file (or `<string>`).
        file: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A safety margin that is not a distance.
    #[error("the safety margin is {margin}; expected a finite distance ≥ 0 m")]
    Margin {
        /// The margin given \[m\].
        margin: f64,
    },
    /// A placement, or a pair list, made for another geometry.
    #[error("{what} is for {got} shapes, but the geometry has {expected}; make it from this geometry")]
    Mismatch {
        /// What was given (`the placement`, `pair (3, 9)`).
        what: String,
        /// Its shape count or index.
        got: usize,
        /// The geometry's shape count.
        expected: usize,
    },
    /// A planning request whose start or goal configuration already collides.
    #[error(
        "the {which} configuration collides: `{a}` – `{b}` are closer than the margin; a path must start and end clear"
    )]
    Blocked {
        /// `start` or `goal`.
        which: &'static str,
        /// One body of the pair (link or obstacle name).
        a: String,
        /// The other body.
        b: String,
    },
    /// A planner that used up its budget without joining start and goal.
    #[error(
        "no collision-free path found before {budget} ran out ({iterations} iteration(s), {nodes} configurations in \
         the search trees); raise it, or check that start and goal lie in one free region"
    )]
    NoPath {
        /// Which budget ran out (`the time limit of 1 s`, `the limit of 5000 iteration(s)`).
        budget: String,
        /// Iterations run.
        iterations: usize,
        /// Configurations in both trees.
        nodes: usize,
    },
    /// A planned path the final exact check refused: the fast check and the
    /// exact one disagree, which is a defect of the planner.
    #[error(
        "the planned path failed its final exact check: `{a}` – `{b}` come within the margin on it; \
         please report this with the robot, scene and seed"
    )]
    Uncertified {
        /// One body of the pair (link or obstacle name).
        a: String,
        /// The other body.
        b: String,
    },
    /// A path that no wait at its via points keeps clear of another robot
    /// moving along its own trajectory (boxed: the details are long).
    #[error("{0}")]
    Crossing(Box<crate::plan::Crossing>),
    /// A run stopped by its caller (Ctrl-C).
    #[error("planning interrupted")]
    Interrupted,
}

fn list(paths: &[PathBuf]) -> String {
    if paths.is_empty() {
        return "nowhere (no search directory applies)".into();
    }
    paths.iter().map(|p| format!("`{}`", p.display())).collect::<Vec<_>>().join(", ")
}

/// `Result` with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

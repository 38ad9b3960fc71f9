//! What the tool must reach: a full pose, a position, or a family's typed
//! target ([`IkTarget`]), and the kinds of typed target ([`TypedKind`]).

use crate::math::Pose;

/// What the tool must reach (see [`solve_target`](super::solve_target)). Positions are tool points
/// in the world frame (the frame of [`Robot::fk`](crate::Robot::fk)) \[m\]; angles \[rad\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkTarget {
    /// A full tool pose `world_from_tool`: the robot's analytic solver or the
    /// numeric one ([`solve_request`](super::solve_request)).
    Pose(Pose),
    /// The tool point alone, the orientation free: the numeric solver with
    /// the position-only task mask \[x, y, z\]. The solutions' residuals are
    /// measured against this position with the orientation of the robot's
    /// `home` pose as a placeholder, so their `orientation_error` means
    /// nothing (see [`IkTarget::orientation_free`]).
    Position([f64; 3]),
    /// Scorbot (seed 000 eq. 13): the tool point with pitch β = −(θ2 + θ3 + θ4)
    /// and roll γ = θ5; the yaw follows from the position
    /// ([`ScorbotIk::solve_xyz_pitch_roll`](crate::ik::scorbot::ScorbotIk::solve_xyz_pitch_roll), up to four solutions).
    PositionPitchRoll {
        /// Tool point \[m\].
        position: [f64; 3],
        /// Pitch β \[rad\] (positive points the approach downwards).
        pitch: f64,
        /// Roll γ \[rad\].
        roll: f64,
    },
    /// ROMMEL (seed 001): the tool point with the tool z axis along
    /// `approach` (any non-zero vector, normalised), q5 = 0
    /// ([`RommelIk::solve_position_approach`](crate::ik::rommel::RommelIk::solve_position_approach), up to four solutions).
    PositionApproach {
        /// Tool point \[m\].
        position: [f64; 3],
        /// Approach direction (tool z axis), world frame.
        approach: [f64; 3],
    },
    /// SCARA on a rail (seed 003): the tool point with the tool angle
    /// α = q2 + q3 + q5 about the vertical, the rail placed by the zone rule;
    /// elbow side and q5 follow `IkRequest::q0` when given
    /// ([`ScaraIk::solve_zone`](crate::ik::scara::ScaraIk::solve_zone), one solution).
    PositionAlpha {
        /// Tool point \[m\].
        position: [f64; 3],
        /// Tool angle α \[rad\].
        alpha: f64,
    },
}

impl IkTarget {
    /// Whether the orientation is not part of the target ([`IkTarget::Position`]):
    /// then a solution's `orientation_error` is measured against a placeholder
    /// (the `home` orientation) and says nothing about success. The typed
    /// targets measure it against the orientation they fix, so it is ~0.
    pub fn orientation_free(&self) -> bool {
        matches!(self, IkTarget::Position(_))
    }

    /// Whether this is a robot family's typed target (pitch/roll, approach, α).
    pub fn is_typed(&self) -> bool {
        !matches!(self, IkTarget::Pose(_) | IkTarget::Position(_))
    }
}

/// The kinds of typed target (a tool point plus the components a family's
/// arm controls), as [`IkTarget`] has them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TypedKind {
    /// [`IkTarget::PositionPitchRoll`].
    PitchRoll,
    /// [`IkTarget::PositionApproach`].
    Approach,
    /// [`IkTarget::PositionAlpha`].
    Alpha,
}

impl IkTarget {
    /// The typed kind of this target; `None` for a pose or a position.
    pub fn typed_kind(&self) -> Option<TypedKind> {
        match self {
            IkTarget::Pose(_) | IkTarget::Position(_) => None,
            IkTarget::PositionPitchRoll { .. } => Some(TypedKind::PitchRoll),
            IkTarget::PositionApproach { .. } => Some(TypedKind::Approach),
            IkTarget::PositionAlpha { .. } => Some(TypedKind::Alpha),
        }
    }

    /// The tool point of a position or typed target; `None` for a pose.
    pub fn position(&self) -> Option<[f64; 3]> {
        match *self {
            IkTarget::Pose(_) => None,
            IkTarget::Position(position)
            | IkTarget::PositionPitchRoll { position, .. }
            | IkTarget::PositionApproach { position, .. }
            | IkTarget::PositionAlpha { position, .. } => Some(position),
        }
    }
}

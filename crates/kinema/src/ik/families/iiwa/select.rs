//! Choosing one solution along a path: the q3 window around the previous
//! configuration, the direction of motion, and the fallback to a search.

use super::*;

impl IiwaIk {
    /// The next configuration along a path (seed 004 §V-E, q_k = f(q_{k−1}, T_k)).
    ///
    /// q3 is searched on a grid of step [`SELECT_STEP`] over
    /// q_prev\[2\] ± [`SELECT_WINDOW`] (clipped to the limits of joint 3). For
    /// each q3 the solution within limits nearest to `q_prev` is the
    /// candidate (nearest branch). Candidates that move no joint by more than
    /// [`SELECT_MAX_STEP`] are preferred; among them, elbow-up ones (elbow
    /// above the shoulder–wrist line, world z up) are preferred, or, if there
    /// is none, the one with the highest elbow is taken (moving towards
    /// elbow-up). Among the elbow-up candidates the one with the largest
    /// translational manipulability along `direction` (world frame, seed 004
    /// eq. 12, [`manipulability_along`]) wins; without a direction, the
    /// nearest to `q_prev`.
    ///
    /// At the shoulder singularity q1 is kept at q_prev\[0\].
    ///
    /// When no q3 of the window gives a solution within limits, the whole
    /// self-motion is searched as in [`IiwaIk::solve_searching`] and the solution
    /// within limits nearest to `q_prev` ([`joint_distance`]) among those the
    /// search sees is returned (a jump in q3, the window having none). Errors as
    /// [`IiwaIk::solve_q3`], or [`Unreachable::JointLimits`] if that search
    /// finds no solution within limits either.
    pub fn select(&self, q_prev: &[f64], target: &Pose, direction: Option<&Vector3<f64>>) -> Result<Solution> {
        self.select_within(q_prev, target, direction, SELECT_WINDOW, 21, &[SELECT_MAX_STEP; 7])
    }

    /// [`IiwaIk::select`] with the q3 window half-width `window` \[rad\] searched
    /// on a grid of `points` values (odd; 1 keeps q3) and per-joint preferred step limits
    /// `max_steps` \[rad\] — for path following at a sample period dt, the
    /// joints' velocity limits times dt, so that q3's drift towards better
    /// manipulability never asks a joint to move faster than it can.
    pub fn select_within(
        &self,
        q_prev: &[f64],
        target: &Pose,
        direction: Option<&Vector3<f64>>,
        window: f64,
        points: usize,
        max_steps: &[f64],
    ) -> Result<Solution> {
        // select_impl checks q_prev (a short or non-finite one gives a NaN centre first).
        let center = q_prev.get(2).copied().unwrap_or(f64::NAN);
        let along = |q: &[f64]| -> Result<f64> {
            match direction {
                Some(v) => manipulability_along(&self.robot.jacobian(q, Frame::Base)?, Axes::Translation, v),
                None => Ok(0.0),
            }
        };
        let choice = Choice {
            prev: q_prev,
            center,
            window,
            points,
            max_steps,
            score: direction.is_some().then_some(&along as &dyn Fn(&[f64]) -> Result<f64>),
            family_preference: true,
        };
        match self.select_impl(target, &choice, false) {
            // The window can miss a feasible q3 that lies further away; only the
            // whole self-motion decides that the target is out of limits.
            Err(Error::Unreachable { .. }) => self.nearest_searched(q_prev, target),
            other => other,
        }
    }

    /// The grid search of [`IiwaIk::select_within`] and [`Redundancy::choose`]
    /// over `choice`; with `continuing`, only the shoulder/elbow branches that
    /// can continue a path through `choice.prev` are solved
    /// ([`IiwaIk::solve_q3_near`]), the others would be jumps.
    pub(super) fn select_impl(&self, target: &Pose, choice: &Choice, continuing: bool) -> Result<Solution> {
        let q_prev = choice.prev;
        self.robot.check_q(q_prev)?;
        choice.check(7)?;
        let t = self.arm_target(target)?;
        let lim = self.robot.joints()[2].limits;
        let step = if choice.window > 0.0 { choice.window / (choice.points / 2) as f64 } else { 0.0 };
        // Grid index of each candidate and its joint values.
        let mut cands: Vec<(i64, [f64; 7])> = Vec::new();
        let mut last_err = None;
        let mut rejected = Vec::new();
        let solve = |q3: f64| self.solve_q3_branches(&t, q3, q_prev[0], continuing.then_some(q_prev));
        // The solution within limits nearest to q_prev, each taken by whole
        // turns to its copy within limits nearest q_prev (joints with more
        // than a turn of range) and onto a limit it passes by rounding.
        let nearest = |sols: &Candidates<7, 8>| -> Option<[f64; 7]> {
            sols.qs()
                .iter()
                .map(|q| {
                    let mut q = *q;
                    let outside = crate::ik::nearest_turns(&self.robot, &mut q, q_prev);
                    (outside, q)
                })
                .filter(|(outside, _)| outside.is_empty())
                .map(|(_, q)| (joint_distance(&self.robot, &q, q_prev), q))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, q)| q)
        };
        for (k, q3) in choice.grid(lim.min, lim.max) {
            match solve(q3) {
                Ok(sols) => match nearest(&sols) {
                    Some(q) => cands.push((k, q)),
                    None => rejected.extend(sols.qs().iter().map(|q| {
                        let joints: Vec<String> =
                            self.robot.limit_flags(q).indices().map(|i| format!("q{}", i + 1)).collect();
                        format!("{} at q3 = {q3:.4} ({})", config_label(bits(q)), joints.join(", "))
                    })),
                },
                Err(e) => last_err = Some(e),
            }
        }
        if cands.is_empty() {
            if rejected.is_empty() {
                if let Some(e) = last_err {
                    return Err(e);
                }
            }
            return Err(Error::Unreachable {
                solver: "iiwa".into(),
                reason: Unreachable::JointLimits { rejected },
                closest: None,
            });
        }
        let small = |q: &[f64; 7]| q.iter().zip(q_prev).zip(choice.max_steps).all(|((a, b), m)| (a - b).abs() <= *m);
        if cands.iter().any(|(_, q)| small(q)) {
            cands.retain(|(_, q)| small(q));
        }
        // The seed's preference: elbow up first, else the highest elbow.
        let heights: Vec<f64> = cands.iter().map(|(_, q)| self.elbow_height(q)).collect();
        let preferred = |i: usize| !choice.family_preference || heights[i] > 0.0;
        let score_of = |q: &[f64; 7]| -> Result<f64> {
            match choice.score {
                Some(f) => f(q),
                None => Ok(0.0),
            }
        };
        let mut scores = vec![f64::NEG_INFINITY; cands.len()];
        let pick = if (0..cands.len()).any(preferred) {
            let mut best = (f64::NEG_INFINITY, f64::INFINITY, 0usize);
            for (i, (_, q)) in cands.iter().enumerate() {
                if !preferred(i) {
                    continue;
                }
                let dist = joint_distance(&self.robot, q, q_prev);
                let score = score_of(q)?;
                scores[i] = score;
                if score > best.0 || (score == best.0 && dist < best.1) {
                    best = (score, dist, i);
                }
            }
            best.2
        } else {
            (0..cands.len()).max_by(|&a, &b| heights[a].total_cmp(&heights[b])).unwrap_or(0)
        };
        // Between grid points: the vertex of the parabola through the best
        // score and its two grid neighbours. Without it the choice hops between
        // neighbouring grid points when the maximum lies between them, and q3
        // chatters at the decision rate.
        let mut q = cands[pick].1;
        if choice.score.is_some() && step > 0.0 && pick > 0 && pick + 1 < cands.len() {
            let (km, k0, kp) = (cands[pick - 1].0, cands[pick].0, cands[pick + 1].0);
            let (sm, s0, sp) = (scores[pick - 1], scores[pick], scores[pick + 1]);
            let curvature = sm - 2.0 * s0 + sp;
            if km + 1 == k0 && k0 + 1 == kp && sm.is_finite() && sp.is_finite() && curvature < 0.0 {
                let delta = (0.5 * (sm - sp) / curvature).clamp(-0.5, 0.5);
                let q3 = choice.center + (k0 as f64 + delta) * step;
                if let Some(refined) = solve(q3).ok().as_ref().and_then(nearest) {
                    let keeps_preference = !choice.family_preference || self.elbow_height(&refined) > 0.0;
                    if small(&refined) && keeps_preference && score_of(&refined)? >= s0 {
                        q = refined;
                    }
                }
            }
        }
        Solution::evaluate(&self.robot, q.to_vec(), target, config_label(bits(&q)))
    }

    /// Height of the elbow above the shoulder–wrist line, along world z \[m\].
    pub(super) fn elbow_height(&self, q: &[f64]) -> f64 {
        let m = rot_z(q[0]) * rot_y(q[1]);
        let e = m * Vector3::new(0.0, 0.0, self.d3);
        let (s4, c4) = q[3].fast_sin_cos();
        let w = m * rot_z(q[2]) * Vector3::new(self.d5 * s4, 0.0, self.d3 + self.d5 * c4);
        let rb = self.robot.base().rot;
        let (e, w) = (rb * e, rb * w);
        let n = w.norm();
        if n == 0.0 {
            return e.z;
        }
        let u = w / n;
        let z = Vector3::z();
        e.dot(&(z - u * u.z))
    }
}

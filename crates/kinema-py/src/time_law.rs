//! Time laws: `TimeLaw` and the `time_law` function.

use kinema::traj::{sample_times, MotionLimits, Profile, TimeLaw};
use kinema_io::LawAnswer;
use numpy::{PyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::answer::to_python;
use crate::args::{f64_array, opt_real, real, to_numpy};
use crate::errors::{invalid, to_py};
use crate::traj::TrajArrays;

/// A time law s(t) from 0 to 1 scaled by a distance (from :func:`time_law`).
///
/// The motion it describes is ``distance · s(t)``; :meth:`sample` returns
/// position, velocity, acceleration and jerk of that motion.
///
/// Attributes:
///     profile: the family (``"trapezoid"``, ``"scurve"``, ``"cubic"``,
///         ``"quintic"``, ``"linear"``).
///     distance: the distance covered (unit of the limits).
///     duration: T [s].
///     phase_times: durations of the phases [s], in order (zero-length ones
///         left out): trapezoid (t_acc, t_cruise, t_dec), S-curve up to
///         seven, the polynomials and the linear law one.
///     peaks: ``(velocity, acceleration, jerk)``: the largest magnitudes over
///         the law, in closed form, scaled by ``distance``; ``inf`` where the
///         family's derivative jumps (trapezoid, cubic and linear jerk,
///         linear acceleration).
#[pyclass(frozen, name = "TimeLaw", module = "kinema")]
pub(crate) struct PyTimeLaw {
    law: TimeLaw,
    #[pyo3(get)]
    distance: f64,
}

#[pymethods]
impl PyTimeLaw {
    #[getter]
    fn profile(&self) -> &'static str {
        self.law.profile().name()
    }

    #[getter]
    fn duration(&self) -> f64 {
        self.law.duration()
    }

    #[getter]
    fn phase_times(&self) -> Vec<f64> {
        self.law.phase_times().to_vec()
    }

    /// The law as ``kinema traj law --json`` prints it: ``profile``,
    /// ``distance``, ``duration``, ``phase_times``, the peaks (``None`` where
    /// unbounded) and the trapezoid's or S-curve's phase lengths; with ``dt``
    /// [s] also ``samples``: ``columns`` (t, p, v, a, j) and ``rows`` every
    /// ``dt`` seconds.
    ///
    /// Raises:
    ///     InvalidInput: a ``dt`` that is not a positive time.
    #[pyo3(signature = (dt=None))]
    fn to_dict<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = opt_real)] dt: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &LawAnswer::new(&self.law, self.distance, dt).map_err(to_py)?)
    }

    #[getter]
    fn peaks(&self) -> (f64, f64, f64) {
        let p = self.law.peaks();
        let scale = |v: f64| if v.is_finite() { v * self.distance } else { f64::INFINITY };
        (scale(p.sd), scale(p.sdd), scale(p.sddd))
    }

    /// The law at the times ``t`` [s] (a number or an array of any shape):
    /// ``(p, v, a, j)``, four float64 arrays of ``t``'s shape with
    /// ``p = distance·s(t)``, ``v = distance·ṡ(t)``, ``a = distance·s̈(t)``,
    /// ``j = distance·s⃛(t)``. Before 0, ``p = 0``; after the end,
    /// ``p = distance``; the derivatives are 0 there. ``j`` is 0 where the
    /// family's jerk is an impulse.
    ///
    /// Raises:
    ///     InvalidInput: ``t`` is not numeric or contains NaN.
    fn sample(&self, py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<TrajArrays> {
        let times = f64_array(t, "t")?;
        let shape = times.shape().to_vec();
        let times = times.as_slice()?;
        if times.iter().any(|v| v.is_nan()) {
            return Err(invalid("`t` contains NaN".into()));
        }
        let d = self.distance;
        let count = times.len();
        let (mut p, mut v, mut a, mut j) = (
            Vec::with_capacity(count),
            Vec::with_capacity(count),
            Vec::with_capacity(count),
            Vec::with_capacity(count),
        );
        for &ti in times {
            let st = self.law.at(ti);
            p.push(st.s * d);
            v.push(st.sd * d);
            a.push(st.sdd * d);
            j.push(st.sddd * d);
        }
        Ok([
            to_numpy(py, shape.clone(), p)?.unbind(),
            to_numpy(py, shape.clone(), v)?.unbind(),
            to_numpy(py, shape.clone(), a)?.unbind(),
            to_numpy(py, shape, j)?.unbind(),
        ])
    }

    /// Sample times 0, dt, 2·dt, … and the end time itself, as a 1-D array
    /// (the times :meth:`Robot.ptp` and ``kinema traj law --dt`` use).
    ///
    /// Raises:
    ///     InvalidInput: ``dt`` is not a positive time step.
    fn times(&self, py: Python<'_>, #[pyo3(from_py_with = real)] dt: f64) -> PyResult<Py<PyArrayDyn<f64>>> {
        let t = sample_times(self.law.duration(), dt).map_err(to_py)?;
        Ok(to_numpy(py, t.len(), t)?.unbind())
    }

    fn __repr__(&self) -> String {
        format!(
            "TimeLaw(profile='{}', distance={}, duration={:.6} s)",
            self.law.profile().name(),
            self.distance,
            self.law.duration()
        )
    }
}

/// A time law, as ``kinema traj law`` builds it: the fastest law of
/// ``profile`` that covers ``distance`` within the limits ``vmax``, ``amax``
/// (and ``jmax``; needed by ``"scurve"``, optional for ``"quintic"``), or —
/// with ``duration`` instead of limits — a law lasting ``duration`` seconds
/// (trapezoid and S-curve in thirds: accelerate, cruise, brake).
///
/// ``profile``: ``"trapezoid"``, ``"scurve"``, ``"cubic"``, ``"quintic"`` or
/// ``"linear"`` (``amax`` may be left out for ``"linear"``). ``distance`` (≥ 0)
/// and the limits share one unit (m, rad, …); the law's samples are scaled by
/// ``distance`` (1 by default: the normalised law s(t)).
///
/// Raises:
///     InvalidInput: unknown profile; both or neither of ``duration`` and the
///         limits; a limit, distance or duration that is not positive and
///         finite; ``jmax`` missing for the S-curve.
#[pyfunction]
#[pyo3(signature = (profile="trapezoid", distance=1.0, vmax=None, amax=None, jmax=None, duration=None))]
pub(crate) fn time_law(
    profile: &str,
    #[pyo3(from_py_with = real)] distance: f64,
    #[pyo3(from_py_with = opt_real)] vmax: Option<f64>,
    #[pyo3(from_py_with = opt_real)] amax: Option<f64>,
    #[pyo3(from_py_with = opt_real)] jmax: Option<f64>,
    #[pyo3(from_py_with = opt_real)] duration: Option<f64>,
) -> PyResult<PyTimeLaw> {
    let profile = profile.parse::<Profile>().map_err(to_py)?;
    let law = if let Some(duration) = duration {
        if vmax.is_some() || amax.is_some() || jmax.is_some() {
            return Err(invalid("give either `duration` or the limits `vmax`, `amax` (and `jmax`), not both".into()));
        }
        if !(distance.is_finite() && distance >= 0.0) {
            return Err(invalid(format!("invalid `distance`: {distance} must be a finite number ≥ 0")));
        }
        TimeLaw::from_duration(profile, duration)
    } else {
        let Some(vel) = vmax else {
            return Err(invalid("give either `duration` or the limits `vmax` and `amax` (and `jmax`)".into()));
        };
        let acc = match amax {
            Some(a) => a,
            // The linear law has no acceleration phase; the core ignores this limit.
            None if profile == Profile::Linear => f64::INFINITY,
            None => return Err(invalid(format!("the {profile} profile needs an acceleration limit `amax`"))),
        };
        TimeLaw::from_limits(profile, distance, &MotionLimits { vel, acc, jerk: jmax })
    }
    .map_err(to_py)?;
    Ok(PyTimeLaw { law, distance })
}

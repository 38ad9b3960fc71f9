//! The Python exceptions of kinema and the mapping of core errors onto them.

use kinema::{Error, ModelError};
use kinema_io::{ClosestAnswer, UnreachableAnswer};
use pyo3::prelude::*;

use crate::answer::to_python;

pyo3::import_exception!(kinema._errors, KinemaError);
pyo3::import_exception!(kinema._errors, InvalidInput);
pyo3::import_exception!(kinema._errors, UnknownRobot);
pyo3::import_exception!(kinema._errors, DescriptionError);
pyo3::import_exception!(kinema._errors, RobotFileError);
pyo3::import_exception!(kinema._errors, Unreachable);
pyo3::import_exception!(kinema._errors, TrajectoryError);
pyo3::import_exception!(kinema._errors, ProgramError);
pyo3::import_exception!(kinema._errors, PlanningError);

/// A core error as a Python exception with the core's message.
pub(crate) fn to_py(e: Error) -> PyErr {
    let message = e.to_string();
    // A batch row or path sample is classified by what is wrong there.
    match e.root() {
        Error::Unreachable { solver, reason, closest } => {
            // The answer `kinema ik --json` prints for the same target (exit code 2).
            let answer = UnreachableAnswer {
                error: "unreachable",
                solver: solver.clone(),
                reason: reason.to_string(),
                closest: closest.as_ref().map(|c| ClosestAnswer {
                    q: c.q.clone(),
                    position_error: c.position_error,
                    orientation_error: c.orientation_error,
                }),
            };
            Unreachable::new_err(UnreachableArgs(message, answer))
        }
        Error::Model(ModelError::UnknownRobot { .. }) => UnknownRobot::new_err(message),
        Error::Input(_)
        | Error::Infeasible { .. }
        | Error::UnsupportedStructure { .. }
        | Error::Overflow { .. }
        | Error::RpySingularity { .. } => InvalidInput::new_err(message),
        Error::Model(_) => DescriptionError::new_err(message),
        Error::File(_) => RobotFileError::new_err(message),
        Error::Trajectory { .. } => TrajectoryError::new_err(message),
        _ => KinemaError::new_err(message),
    }
}

/// The arguments of an `Unreachable` exception, converted when Python first
/// looks at it: the message, the solver, the reason, the closest
/// configuration and the whole answer, as dicts of `kinema-io`'s types.
struct UnreachableArgs(String, UnreachableAnswer);

impl<'py> IntoPyObject<'py> for UnreachableArgs {
    type Target = pyo3::types::PyTuple;
    type Output = Bound<'py, pyo3::types::PyTuple>;
    type Error = PyErr;

    fn into_pyobject(self, py: Python<'py>) -> PyResult<Self::Output> {
        let UnreachableArgs(message, answer) = self;
        let closest = to_python(py, &answer.closest)?;
        let dict = to_python(py, &answer)?;
        (message, answer.solver, answer.reason, closest, dict).into_pyobject(py)
    }
}

/// A collision-check error as a Python exception: the core's own as
/// [`to_py`]; a bad margin or mismatched parts as `InvalidInput`; shapes,
/// meshes, scenes and SRDFs that cannot be used as `DescriptionError`.
pub(crate) fn geometry_to_py(e: kinema_geometry::Error) -> PyErr {
    use kinema_geometry::Error as G;
    match e {
        G::Kinema(e) => to_py(e),
        e @ (G::Margin { .. } | G::Mismatch { .. }) => InvalidInput::new_err(e.to_string()),
        e => DescriptionError::new_err(e.to_string()),
    }
}

/// An `InvalidInput` exception with `message`.
pub(crate) fn invalid(message: String) -> PyErr {
    InvalidInput::new_err(message)
}

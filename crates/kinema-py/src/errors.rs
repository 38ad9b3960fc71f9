//! The Python exceptions of kinema and the mapping of core errors onto them.

use kinema::Error;
use pyo3::prelude::*;

pyo3::import_exception!(kinema._errors, KinemaError);
pyo3::import_exception!(kinema._errors, InvalidInput);
pyo3::import_exception!(kinema._errors, UnknownRobot);
pyo3::import_exception!(kinema._errors, DescriptionError);
pyo3::import_exception!(kinema._errors, RobotFileError);
pyo3::import_exception!(kinema._errors, Unreachable);
pyo3::import_exception!(kinema._errors, TrajectoryError);
pyo3::import_exception!(kinema._errors, ProgramError);

/// A core error as a Python exception with the core's message.
pub(crate) fn to_py(e: Error) -> PyErr {
    let message = e.to_string();
    // A batch row or path sample is classified by what is wrong there.
    match e.root() {
        Error::Unreachable { solver, reason, closest } => {
            let closest = closest.as_ref().map(|c| ClosestArg(c.q.clone(), c.position_error, c.orientation_error));
            Unreachable::new_err((message, solver.clone(), reason.to_string(), closest))
        }
        Error::UnknownRobot { .. } => UnknownRobot::new_err(message),
        Error::JointCount { .. }
        | Error::BadJointValue { .. }
        | Error::UnknownPose { .. }
        | Error::OutOfRange { .. }
        | Error::TooFew { .. }
        | Error::MissingLimit { .. }
        | Error::UnknownName { .. }
        | Error::DoesNotFit { .. }
        | Error::Infeasible { .. }
        | Error::Syntax { .. }
        | Error::UnsupportedStructure { .. }
        | Error::WrongLength { .. }
        | Error::NotFinite { .. }
        | Error::Overflow { .. }
        | Error::RpySingularity { .. } => InvalidInput::new_err(message),
        Error::Description { .. } | Error::Urdf { .. } | Error::MimicJoint { .. } | Error::InvalidModel { .. } => {
            DescriptionError::new_err(message)
        }
        Error::Io { .. } | Error::FileTooLarge { .. } => RobotFileError::new_err(message),
        Error::Trajectory { .. } => TrajectoryError::new_err(message),
        _ => KinemaError::new_err(message),
    }
}

/// The closest configuration of an unreachable target, given to Python as a dict.
struct ClosestArg(Vec<f64>, f64, f64);

impl<'py> IntoPyObject<'py> for ClosestArg {
    type Target = pyo3::types::PyDict;
    type Output = Bound<'py, pyo3::types::PyDict>;
    type Error = PyErr;

    fn into_pyobject(self, py: Python<'py>) -> PyResult<Self::Output> {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("q", self.0)?;
        d.set_item("position_error", self.1)?;
        d.set_item("orientation_error", self.2)?;
        Ok(d)
    }
}

/// An `InvalidInput` exception with `message`.
pub(crate) fn invalid(message: String) -> PyErr {
    InvalidInput::new_err(message)
}

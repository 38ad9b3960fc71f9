//! Python bindings of the kinema core (`import kinema`).
//!
//! Glue only: arguments are converted to the core's types, the core computes,
//! and the results are returned as numpy arrays. Every number comes from the
//! `kinema` crate. Errors of the core become Python exceptions (defined in
//! `python/kinema/_errors.py`) carrying the core's `Display` text, which is
//! what the command line prints.
//!
//! Layout conventions of the arrays handed to Python: homogeneous transforms
//! are 4×4 row-major (C order); Jacobians are 6×n with rows
//! \[vx vy vz ωx ωy ωz\]; batches stack along the first axis.
//!
//! Every result that one of the other doors (the CLI's `--json`, the HTTP
//! API) also gives has a `to_dict` (the robot's own: `Robot.fk_dict`,
//! `Robot.manip_dict`, …) returning that door's answer: a `kinema-io` type
//! converted by `answer`.
//!
//! The files, by what they do: `answer` (answers as Python objects),
//! `errors` (exceptions), `args` (argument conversion), `robot` (the `Robot` class: loading, forward kinematics,
//! Jacobians), `describe` (robots defined in code: `from_dh`, `from_urdf_string`), `collision` (the `Scene` class, collision and distance), `dynamics`, `ik` (with `batch` for `ik_batch`), `traj`
//! (joint-space motions), `cartesian` (`lin`, `circ`), `check`, `time_law`, `toolbox` (the toolbox's `ctraj` and spatialmath poses), `plot` (matplotlib figures),
//! `program` (the robot language), `cell`, `pickle` (robots and scenes pickled by description); `npio` and `fast` are the per-call
//! and batch paths of numpy arrays. The `Robot` class's methods are spread
//! over these files (PyO3's `multiple-pymethods`).

mod answer;
mod args;
mod batch;
mod cartesian;
mod cell;
mod check;
mod collision;
mod describe;
mod dynamics;
mod errors;
mod fast;
mod ik;
mod npio;
mod pickle;
mod plan;
mod plot;
mod program;
mod robot;
mod show;
mod time_law;
mod toolbox;
mod traj;

use pyo3::prelude::*;

// `npio` (shared, as source, with `benchmarks/bare_call`) finds these at the crate root.
use args::shape_text;
use errors::invalid;

/// Compiled part of the ``kinema`` package (import ``kinema``, not this).
#[pymodule]
fn _kinema(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<robot::PyRobot>()?;
    m.add_class::<ik::PyIkSolution>()?;
    m.add_class::<traj::PyJointTrajectory>()?;
    m.add_class::<time_law::PyTimeLaw>()?;
    m.add_class::<program::PyPlan>()?;
    m.add_class::<check::PyCheckReport>()?;
    m.add_class::<cell::PyCell>()?;
    m.add_class::<cell::PyCellReport>()?;
    m.add_class::<collision::PyScene>()?;
    m.add_function(wrap_pyfunction!(time_law::time_law, m)?)?;
    m.add_function(wrap_pyfunction!(program::run_program, m)?)?;
    m.add_function(wrap_pyfunction!(toolbox::interpolate_poses, m)?)?;
    m.add_function(wrap_pyfunction!(toolbox::to_se3_py, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

//! `kinema serve`: the interactive 3D viewer on 127.0.0.1.

use std::io::Write;

use anyhow::{Context, Result};
use clap::Args;
use kinema_geometry::{load_robot_geometry, load_urdf, ros_package_path, RobotGeometry, Scene, UrdfOptions};
use kinema_serve::CellMotion;

#[derive(Args)]
pub struct ServeArgs {
    /// The robot shown first: a built-in name, a .toml description or a .urdf file
    /// (every built-in robot can be picked on the page).
    #[arg(long, short, default_value = "lbr-iiwa-14-r820")]
    robot: String,
    /// For a URDF: the tip link of the chain (default: the only leaf link).
    #[arg(long)]
    tip: Option<String>,
    /// A scene file: its obstacles (and robots, standing) are drawn, and the
    /// page's collision checks and distances are taken against them.
    #[arg(long)]
    scene: Option<std::path::PathBuf>,
    /// A cell file (as `kinema cell` reads): its robots are run on their common clock and played on
    /// the page (play, pause, scrub, speed), among its obstacles.
    #[arg(long, conflicts_with = "scene")]
    cell: Option<std::path::PathBuf>,
    /// TCP port on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8080)]
    port: u16,
}

pub(crate) fn run(a: ServeArgs) -> Result<()> {
    let robot = crate::load_robot(&a.robot, a.tip.as_deref())?;
    let (visual, collision) = link_shapes(&a.robot, a.tip.as_deref());
    let mut scene = a.scene.as_deref().map(Scene::load).transpose()?;
    let mut cell = None;
    if let Some(file) = &a.cell {
        let (members, report, obstacles) = crate::cell_cmd::for_viewer(file)?;
        let motions: Vec<CellMotion> = members
            .into_iter()
            .zip(report.q)
            .map(|((name, robot, geometry), q)| CellMotion { name, robot, geometry, q })
            .collect();
        cell = Some((report.times, motions));
        scene = obstacles;
    }
    let server = kinema_serve::Server::bind(("127.0.0.1", a.port), Some(robot))
        .and_then(|s| s.with_link_shapes(visual, collision))
        .and_then(|s| match &scene {
            Some(scene) => s.with_scene(scene),
            None => Ok(s),
        })
        .and_then(|s| match &cell {
            Some((times, motions)) => s.with_cell(times, motions),
            None => Ok(s),
        })
        .with_context(|| format!("cannot start the viewer on port {}", a.port))?;
    let mut out = std::io::stdout().lock();
    writeln!(out, "kinema serve: {}", server.url())?;
    out.flush()?;
    drop(out);
    eprintln!("serving `{}` and the built-in robots; Ctrl-C to stop", server.app().default_robot().name());
    // Ctrl-C or SIGTERM: stop accepting, stop running programs, let requests
    // in progress finish (a short grace time), then exit normally.
    server.run_until_signal();
    eprintln!("kinema serve: stopped");
    Ok(())
}

/// The shapes the page draws for robot `spec` from a file: a URDF's
/// `<visual>` and `<collision>` elements (meshes found beside it and in
/// `ROS_PACKAGE_PATH`), a robot file's `[[shape]]`s. A built-in robot's come
/// with the server. Shapes that cannot be loaded are left out with a
/// warning: the page then draws the link frames.
fn link_shapes(spec: &str, tip: Option<&str>) -> (Option<RobotGeometry>, Option<RobotGeometry>) {
    if kinema::builtin_source(spec).is_some() {
        return (None, None);
    }
    let options = UrdfOptions { tip: tip.map(str::to_string), package_paths: ros_package_path(), skip_visual: false };
    let lower = spec.to_ascii_lowercase();
    let loaded = if lower.ends_with(".urdf") || lower.ends_with(".xml") {
        load_urdf(spec, &options).map(|u| (Some(u.visual), Some(u.collision)))
    } else {
        load_robot_geometry(spec, &options).map(|(_, collision)| (None, Some(collision)))
    };
    loaded.unwrap_or_else(|e| {
        eprintln!("warning: {spec}: the viewer draws no link shapes: {e}");
        (None, None)
    })
}

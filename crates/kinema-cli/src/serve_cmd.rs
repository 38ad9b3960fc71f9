//! `kinema serve`: the interactive 3D viewer on 127.0.0.1.

use std::io::Write;

use anyhow::{Context, Result};
use clap::Args;

#[derive(Args)]
pub struct ServeArgs {
    /// The robot shown first: a built-in name, a .toml description or a .urdf file
    /// (every built-in robot can be picked on the page).
    #[arg(long, short, default_value = "lbr-iiwa-14-r820")]
    robot: String,
    /// For a URDF: the tip link of the chain (default: the only leaf link).
    #[arg(long)]
    tip: Option<String>,
    /// TCP port on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8080)]
    port: u16,
}

pub(crate) fn run(a: ServeArgs) -> Result<()> {
    let robot = crate::load_robot(&a.robot, a.tip.as_deref())?;
    let server = kinema_serve::Server::bind(("127.0.0.1", a.port), Some(robot))
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

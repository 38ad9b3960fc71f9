//! The `kinema` binary's integration tests, one module per area, in one test
//! binary (each binary links the whole crate). Run one area with
//! `cargo test -p kinema-cli --test all readme::`.

#[path = "../common/mod.rs"]
mod common;
#[path = "../../../kinema/tests/common/mutate.rs"]
mod mutate;

mod cell;
mod cell_plan;
mod cli;
mod cli_dyn;
mod cli_ik;
mod cli_lang;
mod cli_misuse;
#[cfg(feature = "scorbot")]
mod cli_scorbot;
mod cli_traj;
mod collide;
#[cfg(feature = "serve")]
mod doors;
mod lang_avoid;
mod place;
mod plan;
// The README's commands include `kinema plot`, `scorbot` and `serve`.
#[cfg(all(feature = "plot", feature = "scorbot", feature = "serve"))]
mod readme;
#[cfg(all(feature = "plot", feature = "scorbot", feature = "serve"))]
mod readme_seeds;
mod robust;
#[cfg(feature = "serve")]
mod serve_browser;
mod shard;
mod traj_limits;

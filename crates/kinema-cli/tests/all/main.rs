//! The `kinema` binary's integration tests, one module per area, in one test
//! binary (each binary links the whole crate). Run one area with
//! `cargo test -p kinema-cli --test all readme::`.

#[path = "../common/mod.rs"]
mod common;
#[path = "../../../kinema/tests/common/mutate.rs"]
mod mutate;

mod cell;
mod cli;
mod collide;
#[cfg(feature = "serve")]
mod doors;
// The README's commands include `kinema plot`, `scorbot` and `serve`.
#[cfg(all(feature = "plot", feature = "scorbot", feature = "serve"))]
mod readme;
mod robust;
#[cfg(feature = "serve")]
mod serve_browser;
mod traj_limits;

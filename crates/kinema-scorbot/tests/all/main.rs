//! The Scorbot crate's integration tests, one module per area, in one test
//! binary (each binary links the whole crate). Run one area with
//! `cargo test -p kinema-scorbot --test all driver_sim::`.

mod calibrate_square;
mod driver_sim;
mod errors;
mod sim;

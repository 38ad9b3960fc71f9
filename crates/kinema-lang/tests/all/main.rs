//! The language's integration tests, one module per area, in one test binary
//! (each binary links the whole crate). Run one area with
//! `cargo test -p kinema-lang --test all fuzz::`.

#[path = "../../../kinema/tests/common/mutate.rs"]
mod mutate;

mod avoid;
mod bounds;
mod fuzz;
mod lang;

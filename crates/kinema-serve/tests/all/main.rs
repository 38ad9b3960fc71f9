//! The server's integration tests in one test binary (each binary links the
//! whole crate). Run one area with `cargo test -p kinema-serve --test all load::`.

#[path = "../../../kinema/tests/common/mutate.rs"]
mod mutate;

mod api;
mod http;
mod load;
mod plan;
mod viewer;

//! kinema-geometry's integration tests, one module per area, in one test
//! binary. Run one area with `cargo test -p kinema-geometry --test all urdf::`.

mod approach;
mod builtin_shapes;
mod coal;
mod common;
mod fast_paths;
mod meshes;
mod plan;
mod plan_problems;
mod primitives;
mod scene;
mod self_collision;
mod spheres;
mod srdf;
mod sweep;
mod urdf;

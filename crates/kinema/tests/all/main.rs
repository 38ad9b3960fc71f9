//! The core's integration tests, one module per area, in one test binary:
//! each binary links the whole crate, so one binary instead of 26 saves most
//! of a fresh clone's test build. Run one area with
//! `cargo test -p kinema --test all ik_geo::`.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/mutate.rs"]
mod mutate;

mod analysis;
mod bad_input;
mod bad_urdf;
mod descriptions;
mod dynamics;
mod dynamics_fast;
mod ik_admissible;
mod ik_contract;
mod ik_geo;
mod ik_geo_general;
mod ik_iiwa;
mod ik_numeric;
mod ik_pieper;
mod ik_rommel;
mod ik_scara;
mod ik_scorbot;
mod ik_srs;
mod ik_toy_family;
mod jacobian;
mod module_graph;
mod place;
mod random_chains;
mod reach;
mod reference;
mod seeds;
mod traj_boundary;
mod traj_cart;
mod traj_cell;
mod traj_expr;
mod traj_law;
mod traj_ptp;
mod urdf_links;

//! The closed-form families, one module each. A family recognises the
//! robots it solves from their structure, writes its kernel
//! ([`ClosedForm`](super::ClosedForm)) and, where it has them, its typed
//! targets and redundancy ([`Family`](super::family::Family)); it registers
//! with one line in [`FAMILIES`](super::registry::FAMILIES).

pub mod geo;
pub mod iiwa;
pub mod pieper;
pub mod rommel;
pub mod scara;
pub mod scorbot;

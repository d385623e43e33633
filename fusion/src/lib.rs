//! vigil's fusion layer: every sample on GPS time, attitude and health cross-checks, the ownship
//! state, the traffic picture and its threat geometry. It is a deterministic function of the decoded
//! messages and their host receive times: no clock, no environment.
#![deny(missing_docs)]

pub mod attitude;
pub mod geometry;
pub mod ingest;
pub mod magnetic;
pub mod ownship;
pub mod pipeline;
pub mod time;
pub mod traffic;
pub mod units;

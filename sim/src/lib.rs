//! Scenario simulator: truth trajectories, device models (clocks, noise, faults) and their wire
//! bytes, built with the drivers' own encoders. (Filled in by the simulator issue; device models
//! needed earlier, such as the TT-Multi-RF control responder, live here too.)
#![deny(missing_docs)]

pub mod ttmrf_module;

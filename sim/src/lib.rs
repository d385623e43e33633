//! Scenario simulator: truth trajectories, device models (clocks, noise, faults) and their wire
//! bytes, built with the drivers' own encoders, written as vigil recordings.
//!
//! - [`scenario`]: the scenario model (TOML) and the built-in named scenarios;
//! - [`trajectory`], [`geo`], [`units`], [`magnetic`]: the world's geometry, atmosphere (ISA),
//!   GPS time and magnetic declination (WMM2025 behind [`magnetic::MagneticModel`]);
//! - [`truth`]: the ownship's and intruders' true state at any GPS time, and truth records;
//! - [`device`]: the [`device::DeviceModel`] trait and the BAHRS and Watson models;
//! - [`link`]: baud-rate pacing, host read chunking and latency, link faults;
//! - [`engine`]: the run loop ([`Simulator`]) feeding a [`Sink`];
//! - [`record`]: the MCAP sink (the recording format itself is `vigil_record`; decoding a
//!   recording is `vigil_drivers::replay`).
//!
//! Everything is a deterministic function of (scenario, seed): no clock, no environment, no
//! unseeded randomness.
//!
//! ```
//! use vigil_sim::{MemorySink, Simulator, scenario};
//!
//! let s = scenario::builtin("headon").unwrap();
//! let mut sim = Simulator::new(&s, 1).unwrap();
//! let mut sink = MemorySink::default();
//! sim.run(2_000_000_000, &mut sink).unwrap();
//! assert!(sink.truth.iter().any(|r| r.device == "bahrs" && r.kind == "inertial"));
//! ```
#![deny(missing_docs)]

pub mod device;
pub mod engine;
pub mod geo;
pub mod link;
pub mod magnetic;
pub mod record;
pub mod rng;
pub mod scenario;
pub mod trajectory;
pub mod truth;
pub mod ttmrf_module;
pub mod units;

pub use engine::{MemorySink, PortInfo, RunInfo, Simulator, Sink, SinkError};
pub use link::{Chunk, HostClock};
pub use scenario::Scenario;
pub use truth::{OwnshipTruth, TruthRecord, World};

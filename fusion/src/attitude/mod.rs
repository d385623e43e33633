//! Attitude and health cross-check (building blocks): angles on the circle and slerp, detection
//! thresholds from a false-alarm probability, persistence with hysteresis, and three-source fault
//! isolation. The per-sample comparison that uses them arrives with the attitude issue.

pub mod angles;
pub mod compare;
pub mod gates;
pub mod isolation;
pub mod params;
pub mod persistence;
pub mod samples;
pub mod stats;

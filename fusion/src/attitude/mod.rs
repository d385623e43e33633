//! Attitude and health cross-check (issue 8): is the BAHRS telling the truth? Its attitude is
//! compared at each of its samples with the VN-200 INS and the Watson AHRS, the disagreeing unit
//! is isolated, and one record per comparison is emitted.
//!
//! Building blocks: [`angles`] (wrap, 3-2-1 Euler, slerp), [`stats`] (thresholds from a
//! false-alarm probability), [`persistence`] (low-pass, counter hysteresis, CUSUM), [`isolation`]
//! (pairwise isolation with the magnetic-disturbance rule). The check: [`params`] (the parameter
//! table), [`samples`] (inputs), [`gates`] (validity, freshness, frozen), [`compare`] (both
//! detectors per axis), [`vertical`] (vertical channel), [`vote`] (voted attitude), [`record`]
//! (the emitted record), [`coverage`] (what was compared and why not) and [`checker`] (the
//! stateful [`checker::AttitudeChecker`]). [`health`]: the health cross-check of the BAHRS signal
//! health and sync pulses against the VN-200 INS status (issue 25 point 4), with its rule table.

pub mod angles;
pub mod checker;
pub mod compare;
pub mod coverage;
pub mod gates;
pub mod health;
pub mod inertial;
pub mod isolation;
pub mod params;
pub mod persistence;
pub mod record;
pub mod samples;
pub mod stats;
pub mod synthetic;
pub mod vertical;
pub mod vote;

#[cfg(test)]
mod checker_tests;

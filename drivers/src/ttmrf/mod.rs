//! Aerobits TT-Multi-RF traffic receiver (ADS-B 1090, UAT 978, FLARM, GNSS), firmware 2.77.5.
//!
//! One module per protocol of the manual. Every traffic message maps to the common
//! [`crate::traffic::TrafficReport`].

pub mod asterix;
pub mod at;
pub mod csv;
pub mod flarm_category;
pub mod gdl90;
pub mod json;
pub mod mavlink;
pub mod mixed;
pub mod nmea;
pub mod raw;
pub mod text;

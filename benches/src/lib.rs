//! Criterion benchmarks of vigil's hot paths live in `benches/`; this library holds the stream
//! builders they share.
#![deny(missing_docs)]

pub mod bahrs;
pub mod modes;

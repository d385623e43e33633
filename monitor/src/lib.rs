//! Integrity rules over vigil's fused outputs and the alert life cycle (raise, persist, clear,
//! latch). (Filled in by the service issue.)
#![deny(missing_docs)]

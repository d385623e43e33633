//! Text protocols of the TT-Multi-RF on one port (to be completed).

pub mod line;

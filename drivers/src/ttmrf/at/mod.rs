//! TT-Multi-RF at protocol (to be implemented).

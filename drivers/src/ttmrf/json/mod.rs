//! TT-Multi-RF json protocol (to be implemented).

//! TT-Multi-RF mavlink protocol (to be implemented).

//! TT-Multi-RF gdl90 protocol (to be implemented).

//! TT-Multi-RF csv protocol (to be implemented).

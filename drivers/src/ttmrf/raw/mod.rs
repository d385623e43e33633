//! TT-Multi-RF raw protocol (to be implemented).

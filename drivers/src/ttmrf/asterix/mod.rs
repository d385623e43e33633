//! TT-Multi-RF asterix protocol (to be implemented).

//! TT-Multi-RF nmea protocol (to be implemented).

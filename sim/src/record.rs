//! MCAP recording (filled next).

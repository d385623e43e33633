//! BAHRS baro-inertial AHRS, serial protocol 2.0 (protocol id 0x0003).

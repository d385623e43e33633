//! Mode S and ADS-B (DO-260B) decoding of raw frames. (Implemented by the raw Mode S issue.)

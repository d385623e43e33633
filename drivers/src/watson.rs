//! Watson Industries AHRS-E304 ASCII attitude string.

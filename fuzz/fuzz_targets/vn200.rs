//! Arbitrary bytes into the VN-200 decoder (binary, split packets and ASCII on one port): no panic,
//! split invariance, full byte accounting.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vigil_drivers::{testkit, vn200};

fuzz_target!(|data: &[u8]| {
    testkit::check_arbitrary_input(vn200::Vn200Decoder::new, data);
});

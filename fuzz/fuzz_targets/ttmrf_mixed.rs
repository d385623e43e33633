//! Arbitrary bytes into the TT-Multi-RF MixedDecoder (text lines and raw HEX lines on one port):
//! no panic, split invariance, full byte accounting.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vigil_drivers::testkit;

fuzz_target!(|data: &[u8]| {
    testkit::check_arbitrary_input(vigil_drivers::ttmrf::mixed::MixedDecoder::new, data);
});

//! Arbitrary bytes into the BAHRS decoder: no panic, split invariance, full byte accounting.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vigil_drivers::{bahrs, testkit};

fuzz_target!(|data: &[u8]| {
    testkit::check_arbitrary_input(bahrs::Decoder::new, data);
});

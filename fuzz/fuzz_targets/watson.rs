//! Arbitrary bytes into the Watson line decoder: no panic, split invariance, full byte accounting.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vigil_drivers::{testkit, watson};

fuzz_target!(|data: &[u8]| {
    testkit::check_arbitrary_input(watson::Decoder::new, data);
});

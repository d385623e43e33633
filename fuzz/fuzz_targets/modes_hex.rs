//! Arbitrary bytes into HEX/HEXd line framing and the Mode S decoder with its tracker: no panic,
//! split invariance, full byte accounting.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vigil_drivers::modes::{DecodeOptions, ModesDecoder, TrackerConfig};
use vigil_drivers::testkit;
use vigil_drivers::ttmrf::raw::HexDecoder;

fuzz_target!(|data: &[u8]| {
    testkit::check_arbitrary_input(
        || {
            ModesDecoder::new(
                HexDecoder::new(),
                TrackerConfig::default(),
                DecodeOptions::default(),
            )
        },
        data,
    );
});

//! Every payload vigil publishes, in one place: the header they share and one module per topic.
//!
//! Rules every payload follows (they are the contract with consumers in other processes and other
//! languages): `#[repr(C)]`, fixed size (traffic: a fixed-size header and a slice of fixed-size
//! targets), no pointers, plain integers and floats only (enumerations
//! travel as `u8` codes with named constants, so an unknown code from a newer publisher is never
//! undefined behaviour), SI units unless the field name says otherwise, an explicit iceoryx2
//! `type_name` carrying the schema version (so the Rust module path is not part of the contract),
//! and a [`Header`] first with the schema version, a sequence number and the times.
//!
//! Floats that may be unknown are NaN (never a sentinel like 0); JSON output prints NaN as `null`.

pub mod alerts;
pub mod attitude;
pub mod integrity;
pub mod ownship;
pub mod traffic;

use core::fmt::Debug;

use iceoryx2::prelude::ZeroCopySend;
use serde::{Serialize, Serializer};

use crate::names::Topic;

/// Schema version of every payload in this crate. Bumped on any layout change; it is also part of
/// each `type_name`, so iceoryx2 refuses to connect a publisher and a subscriber built from
/// different layouts instead of letting one misread the other's bytes.
pub const SCHEMA_VERSION: u32 = 3;

/// Common first field of every payload.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, ZeroCopySend, Serialize)]
#[type_name("vigil.Header.v1")]
pub struct Header {
    /// [`SCHEMA_VERSION`] of the publisher that wrote the sample.
    pub schema_version: u32,
    /// Explicit padding (keeps the layout free of implicit holes); always 0.
    #[serde(skip)]
    pub reserved: u32,
    /// Sequence number per publisher, starting at 1 and incremented by one per sample sent, so a
    /// subscriber sees every sample it missed as a gap. Set by [`crate::Publisher`].
    pub seq: u64,
    /// GPS time the content refers to (time of validity), ns since the GPS epoch
    /// (1980-01-06 00:00:00 UTC, no leap seconds); 0 when not known.
    pub gps_time_ns: i64,
    /// Host `CLOCK_MONOTONIC` when the publisher sent the sample, ns. The clock is shared by all
    /// processes of a host, so a subscriber computes its receive latency from it. Set by
    /// [`crate::Publisher`].
    pub send_mono_ns: u64,
}

/// A type published on one of vigil's services, as the process holds it.
///
/// The fixed-size payloads travel as they are ([`FixedPayload`]); the traffic picture travels
/// as a [`traffic::TrafficHeader`] and a slice of targets sized by its count (see
/// [`crate::TrafficPublisher`]).
pub trait Payload: Debug + Clone + Default + Serialize + 'static {
    /// The topic whose service carries this payload.
    const TOPIC: Topic;
    /// The common header.
    fn header(&self) -> &Header;
    /// The common header, mutable (the publisher stamps it).
    fn header_mut(&mut self) -> &mut Header;
}

/// A payload that travels as one fixed-size `#[repr(C)]` value: every topic but traffic.
pub trait FixedPayload: Payload + ZeroCopySend + Copy {}

impl<T: Payload + ZeroCopySend + Copy> FixedPayload for T {}

macro_rules! impl_payload {
    ($ty:ty, $topic:expr) => {
        impl $crate::payload::Payload for $ty {
            const TOPIC: $crate::names::Topic = $topic;
            fn header(&self) -> &$crate::payload::Header {
                &self.header
            }
            fn header_mut(&mut self) -> &mut $crate::payload::Header {
                &mut self.header
            }
        }
    };
}
pub(crate) use impl_payload;

mod sealed {
    pub trait Sealed {}
}

/// A structure of this crate that travels on iceoryx2 as it is: `#[repr(C)]`, plain integers and
/// floats, explicit padding fields (no implicit holes; `tests/c_layout.rs` checks every offset),
/// so its bytes are all initialised and its layout is the C header's. Sealed: only this crate's
/// structures are.
pub trait Wire: ZeroCopySend + Copy + sealed::Sealed {}

macro_rules! wire {
    ($($t:ty),* $(,)?) => {
        $(impl sealed::Sealed for $t {} impl Wire for $t {})*
    };
}
wire!(
    Header,
    attitude::AttitudePayload,
    ownship::OwnshipPayload,
    traffic::Target,
    traffic::TrafficHeader,
    integrity::IntegrityPayload,
    alerts::AlertPayload,
);

/// The iceoryx2 type name of a structure (its `#[type_name(...)]`, schema version included):
/// what another process or language must give to open the service, and what `vigil bridge`
/// names as the Zenoh encoding's schema.
pub fn type_name<T: Wire>() -> &'static str {
    // SAFETY: `type_name` only returns the string the derive stored; it is unsafe to implement
    // (a wrong name is unsound), not to call.
    unsafe { <T as ZeroCopySend>::type_name() }
}

/// The bytes of a structure as it travels on iceoryx2 (`vigil bridge`'s raw encoding).
pub fn wire_bytes<T: Wire>(v: &T) -> &[u8] {
    // SAFETY: a `Wire` type has no implicit padding (see the trait), so every byte of `v` is
    // initialised; the slice borrows `v` and covers exactly its size.
    unsafe { core::slice::from_raw_parts((v as *const T).cast::<u8>(), size_of::<T>()) }
}

/// Copies `text` into a fixed byte field, NUL-padded, truncated at a UTF-8 character boundary so
/// the stored bytes always stay valid UTF-8.
pub fn write_text(field: &mut [u8], text: &str) {
    let mut end = text.len().min(field.len());
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    field.fill(0);
    field[..end].copy_from_slice(&text.as_bytes()[..end]);
}

/// Reads a NUL-padded text field: the bytes before the first NUL, up to the first invalid UTF-8
/// byte (a field from a misbehaving writer never fails the reader).
pub fn read_text(field: &[u8]) -> &str {
    let end = field.iter().position(|&b| b == 0).unwrap_or(field.len());
    let bytes = &field[..end];
    match core::str::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => core::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default(),
    }
}

/// serde helper: a NUL-padded text field as a JSON string.
pub(crate) fn ser_text<S: Serializer, const N: usize>(
    field: &[u8; N],
    s: S,
) -> Result<S::Ok, S::Error> {
    s.serialize_str(read_text(field))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wire_bytes_are_the_fields_in_order() {
        let h = Header {
            schema_version: 3,
            reserved: 0,
            seq: 0x0102_0304_0506_0708,
            gps_time_ns: -2,
            send_mono_ns: 9,
        };
        let b = wire_bytes(&h);
        assert_eq!(b.len(), 32);
        assert_eq!(&b[0..4], &3u32.to_ne_bytes());
        assert_eq!(&b[8..16], &0x0102_0304_0506_0708u64.to_ne_bytes());
        assert_eq!(&b[16..24], &(-2i64).to_ne_bytes());
        assert_eq!(type_name::<Header>(), "vigil.Header.v1");
    }

    #[test]
    fn text_round_trips_and_truncates_on_char_boundary() {
        let mut f = [0xFFu8; 8];
        write_text(&mut f, "N123AB");
        assert_eq!(&f, b"N123AB\0\0");
        assert_eq!(read_text(&f), "N123AB");
        // "abcdefgé" is 9 bytes (é = 2 bytes); 8 bytes would split é, so 7 are kept.
        write_text(&mut f, "abcdefgé");
        assert_eq!(read_text(&f), "abcdefg");
        // Full field without a NUL, then invalid UTF-8: read up to the invalid byte.
        assert_eq!(read_text(b"ABCDEFGH"), "ABCDEFGH");
        assert_eq!(read_text(&[b'A', 0xC3, b'B']), "A");
    }
}

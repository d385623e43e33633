//! vigil's recording format: MCAP files with one raw channel per device port (the bytes as read,
//! log time = host monotonic receive time), optional JSON channels (truth, decoded, fused) and
//! metadata records, and the reader that hands a recording back as port chunks in receive order.
//!
//! - [`mod@write`]: [`RawRecorder`], the one writer of every vigil recording (the simulator's
//!   `McapSink`, `vigil record`, `vigil run`'s recording);
//! - [`read`]: [`read_recording_from`] streams any recording, damaged or truncated ones included,
//!   one chunk in memory at a time; [`Recorded`] is one message read back.
//!
//! The crate knows the format only: which decoded and fused channels `vigil run` adds, and their
//! messages, belong to the service (`vigil_service::recording`); what a truth record holds belongs
//! to the simulator. Nothing here decodes a device's bytes.
#![deny(missing_docs)]

pub mod link;
pub mod read;
pub mod write;

pub use link::PortLink;
pub use read::{
    ReadOutcome, Recorded, read_metadata, read_metadata_from, read_recording, read_recording_from,
    recorded_span, recorded_span_from,
};
pub use write::{
    CHUNK_BYTES, COMPRESS_BY_DEFAULT, METADATA_NAME, RAW_SCHEMA_PREFIX, RawRecorder, TRUTH_TOPIC,
    raw_topic, write_options,
};

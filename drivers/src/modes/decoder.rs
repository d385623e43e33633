//! The Mode S [`DeviceDecoder`]: a raw framing decoder (HEX/HEXd or Beast) followed by the
//! frame decode and the tracker. One output per frame that passed its checks; frames that fail
//! are only counted.
//!
//! Counters ([`DecodeStats`] plus [`ModesCounters`]):
//! - `checksum_failures`: DF11/17/18 parity failures, and AP frames whose recovered address is
//!   not a known aircraft (they cannot be told from corrupted frames);
//! - `unknown_types`: DFs not handled (DF1-3, 6-10, 12-15, 19, 22, 23) and unknown Beast types;
//! - `malformed`: broken lines/frames from the framing and frames whose length contradicts their
//!   DF;
//! - the bytes of every rejected frame are added to `bytes_skipped`, so that
//!   `bytes_consumed` = bytes of output frames + `bytes_skipped` still holds.

use bytes::BytesMut;
use serde::Serialize;

use super::df::{self, DecodeOptions, ModeS, Reject};
use super::tracker::{Position, Tracker, TrackerConfig};
use crate::traffic::TrafficReport;
use crate::ttmrf::raw::{BeastDecoder, HexDecoder, ModeAcFrame, ModeSFrame, RawFrame, UatFrame};
use crate::{DecodeStats, DeviceDecoder};

/// Counters beyond [`DecodeStats`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct ModesCounters {
    /// Mode S frames framed (before checks).
    pub mode_s_frames: u64,
    /// Mode A/C frames passed on.
    pub mode_ac_frames: u64,
    /// UAT frames passed on.
    pub uat_frames: u64,
    /// DF11/17/18 frames whose parity failed.
    pub parity_failures: u64,
    /// AP frames from addresses never seen with verified parity.
    pub unknown_address: u64,
    /// DF17 frames repaired by single-bit correction (only with the option on).
    pub corrected: u64,
    /// CPR positions rejected by the zone, latitude, range or jump checks (also counted in
    /// [`DecodeStats::invalid_values`]).
    pub cpr_rejections: u64,
    /// Aircraft evicted from the full tracker table.
    pub evictions: u64,
    /// Mode S frames per downlink format (index = DF, 0..=24) that passed their checks.
    pub df_counts: [u64; 25],
}

/// One decoded Mode S frame with what the tracker made of it.
#[derive(Debug, Clone, PartialEq)]
pub struct ModesOutput {
    /// The raw frame as received (before any opt-in correction) and its receive metadata.
    pub frame: ModeSFrame,
    /// The decoded frame.
    pub msg: ModeS,
    /// The position this frame completed, if any.
    pub position: Option<Position>,
    /// NIC of this position frame (type code plus the supplements known).
    pub nic: Option<u8>,
    /// Traffic report, when this frame updated position or velocity of a located aircraft.
    pub report: Option<TrafficReport>,
}

/// What [`ModesDecoder`] yields.
#[derive(Debug, Clone, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum ModesMessage {
    /// A Mode S frame that passed its checks. Not boxed: boxing would allocate per frame.
    ModeS(ModesOutput),
    /// A Mode A/C reply (no checks exist for it).
    ModeAc(ModeAcFrame),
    /// A UAT frame, passed on.
    Uat(UatFrame),
}

/// Mode S decoder over a raw framing decoder `F`.
#[derive(Debug, Clone)]
pub struct ModesDecoder<F> {
    framing: F,
    tracker: Tracker,
    opts: DecodeOptions,
    stats: DecodeStats,
    counters: ModesCounters,
    emitted: u64,
    rejected_bytes: u64,
    extra_checksum: u64,
    extra_unknown: u64,
    extra_malformed: u64,
}

impl ModesDecoder<HexDecoder> {
    /// A decoder of HEX / HEXd / AVR lines.
    pub fn hex(cfg: TrackerConfig, opts: DecodeOptions) -> Self {
        Self::new(HexDecoder::new(), cfg, opts)
    }
}

impl ModesDecoder<BeastDecoder> {
    /// A decoder of a Beast stream.
    pub fn beast(cfg: TrackerConfig, opts: DecodeOptions) -> Self {
        Self::new(BeastDecoder::new(), cfg, opts)
    }
}

impl<F: DeviceDecoder<Message = RawFrame>> ModesDecoder<F> {
    /// A decoder over the given framing.
    pub fn new(framing: F, cfg: TrackerConfig, opts: DecodeOptions) -> Self {
        ModesDecoder {
            framing,
            tracker: Tracker::new(cfg),
            opts,
            stats: DecodeStats::default(),
            counters: ModesCounters::default(),
            emitted: 0,
            rejected_bytes: 0,
            extra_checksum: 0,
            extra_unknown: 0,
            extra_malformed: 0,
        }
    }

    /// The Mode S counters.
    pub fn counters(&self) -> ModesCounters {
        ModesCounters {
            evictions: self.tracker.evictions,
            cpr_rejections: self.tracker.cpr_rejections,
            ..self.counters
        }
    }

    /// The tracker.
    pub fn tracker(&self) -> &Tracker {
        &self.tracker
    }

    fn sync_stats(&mut self) {
        let i = *self.framing.stats();
        self.stats = DecodeStats {
            bytes_consumed: i.bytes_consumed,
            bytes_skipped: i.bytes_skipped + self.rejected_bytes,
            frames_decoded: self.emitted,
            checksum_failures: i.checksum_failures + self.extra_checksum,
            unknown_types: i.unknown_types + self.extra_unknown,
            malformed: i.malformed + self.extra_malformed,
            unsupported_version: i.unsupported_version,
            last_frame_start: i.last_frame_start,
            // Issue 24 ("validate per record"): a raw frame cannot carry an out-of-range value
            // (its fields are bounded by their encoding), so its impossible record is a CPR
            // position that cannot be true (a pair straddling a zone boundary, beyond the
            // receiver's range, or a jump no aircraft makes): that frame's position is dropped
            // alone and counted here, the aircraft's other frames and every other aircraft kept.
            invalid_values: i.invalid_values + self.tracker.cpr_rejections,
        };
    }

    /// Handles one framed message; `None` when it failed its checks.
    fn process(&mut self, raw: RawFrame) -> Option<ModesMessage> {
        let frame = match raw {
            RawFrame::ModeS(f) => f,
            RawFrame::ModeAc(f) => {
                self.counters.mode_ac_frames += 1;
                return Some(ModesMessage::ModeAc(f));
            }
            RawFrame::Uat(f) => {
                self.counters.uat_frames += 1;
                return Some(ModesMessage::Uat(f));
            }
        };
        self.counters.mode_s_frames += 1;
        let msg = match df::decode(frame.data(), self.opts) {
            Ok(m) => m,
            Err(Reject::Parity { .. }) => {
                self.counters.parity_failures += 1;
                self.extra_checksum += 1;
                return None;
            }
            Err(Reject::UnknownDf(_)) => {
                self.extra_unknown += 1;
                return None;
            }
            Err(Reject::Length { .. }) => {
                self.extra_malformed += 1;
                return None;
            }
        };
        let up = self.tracker.update(&msg, &frame.meta);
        if !up.accepted {
            self.counters.unknown_address += 1;
            self.extra_checksum += 1;
            return None;
        }
        if matches!(msg.parity, df::Parity::Corrected(_)) {
            self.counters.corrected += 1;
        }
        if let Some(c) = self.counters.df_counts.get_mut(usize::from(msg.df)) {
            *c += 1;
        }
        Some(ModesMessage::ModeS(ModesOutput {
            frame,
            msg,
            position: up.position,
            nic: up.nic,
            report: up.report,
        }))
    }

    fn pump(&mut self, buf: &mut BytesMut, eof: bool) -> Option<ModesMessage> {
        loop {
            let raw = if eof {
                self.framing.decode_eof(buf)
            } else {
                self.framing.decode(buf)
            };
            let Some(raw) = raw else {
                self.sync_stats();
                return None;
            };
            let fs = self.framing.stats();
            let frame_len = fs.bytes_consumed - fs.last_frame_start;
            if let Some(m) = self.process(raw) {
                self.emitted += 1;
                self.sync_stats();
                return Some(m);
            }
            self.rejected_bytes += frame_len;
        }
    }
}

impl<F: DeviceDecoder<Message = RawFrame>> DeviceDecoder for ModesDecoder<F> {
    type Message = ModesMessage;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<ModesMessage> {
        self.pump(buf, false)
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<ModesMessage> {
        self.pump(buf, true)
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    /// Mutable counters; note they are recomputed from the framing's counters after every call.
    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

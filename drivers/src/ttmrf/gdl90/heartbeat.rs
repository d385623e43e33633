//! GDL90 Heartbeat, message ID 0 (GDL 90 Data Interface Specification 560-1058-00 Rev A, 3.1).
//!
//! ```text
//! byte 0  ID = 0x00
//! byte 1  status 1: b7 GPS Pos Valid | b6 Maint Req | b5 IDENT | b4 Addr Type | b3 GPS Batt Low
//!                   | b2 RATCS | b1 reserved | b0 UAT Initialized
//! byte 2  status 2: b7 time stamp bit 16 | b6 CSA Requested | b5 CSA Not Available
//!                   | b4..b1 reserved | b0 UTC OK
//! byte 3-4 time stamp bits 15..0, seconds since 0000Z, LS byte first
//! byte 5-6 message counts, MS byte first: b15..b11 uplink count, b10 reserved,
//!          b9..b0 basic and long message count
//! ```

use serde::Serialize;

/// Message ID of the Heartbeat.
pub const ID: u8 = 0;
/// Length of the clear message, ID included.
pub const LEN: usize = 7;

/// GDL90 Heartbeat: receiver status and UTC time of the last second.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Heartbeat {
    /// The receiver has a valid GPS position.
    pub gps_pos_valid: bool,
    /// The receiver needs maintenance.
    pub maint_req: bool,
    /// IDENT talkback active.
    pub ident: bool,
    /// Address type talkback (the ownship uses a non-ICAO, anonymous address).
    pub addr_type_talkback: bool,
    /// GPS battery low.
    pub gps_batt_low: bool,
    /// ATC services talkback (RATCS).
    pub ratcs: bool,
    /// The UAT receiver is initialised.
    pub uat_initialized: bool,
    /// CSA (conflict situation awareness) requested.
    pub csa_requested: bool,
    /// CSA not available.
    pub csa_not_available: bool,
    /// UTC timing is valid.
    pub utc_ok: bool,
    /// Reserved bits as received (status 1 bit 1 in bit 0, status 2 bits 4..1 in bits 4..1), kept
    /// so that encoding reproduces the frame.
    pub reserved_bits: u8,
    /// Seconds since 0000Z (17 bits, 0..131071; valid values are below 86400).
    pub timestamp_s: u32,
    /// Uplink messages received in the last second (5 bits).
    pub uplink_count: u8,
    /// Basic and Long messages received in the last second (10 bits).
    pub basic_long_count: u16,
    /// The reserved bit 10 of the message counts as received.
    pub counts_reserved_bit: bool,
}

fn bit(b: u8, n: u8) -> bool {
    b & (1 << n) != 0
}

impl Heartbeat {
    /// Decodes the clear message (ID included). `None` when the length is not [`LEN`].
    pub fn decode(m: &[u8]) -> Option<Self> {
        let &[_, s1, s2, t0, t1, c0, c1] = m else {
            return None;
        };
        let counts = u16::from_be_bytes([c0, c1]);
        Some(Self {
            gps_pos_valid: bit(s1, 7),
            maint_req: bit(s1, 6),
            ident: bit(s1, 5),
            addr_type_talkback: bit(s1, 4),
            gps_batt_low: bit(s1, 3),
            ratcs: bit(s1, 2),
            uat_initialized: bit(s1, 0),
            csa_requested: bit(s2, 6),
            csa_not_available: bit(s2, 5),
            utc_ok: bit(s2, 0),
            reserved_bits: ((s1 >> 1) & 1) | (s2 & 0x1E),
            timestamp_s: (u32::from(s2 >> 7) << 16) | u32::from(u16::from_le_bytes([t0, t1])),
            uplink_count: (counts >> 11) as u8,
            basic_long_count: counts & 0x3FF,
            counts_reserved_bit: counts & 0x400 != 0,
        })
    }

    /// Encodes the clear message (ID included). Out-of-range fields are masked to their widths.
    pub fn encode(&self) -> [u8; LEN] {
        let s1 = u8::from(self.gps_pos_valid) << 7
            | u8::from(self.maint_req) << 6
            | u8::from(self.ident) << 5
            | u8::from(self.addr_type_talkback) << 4
            | u8::from(self.gps_batt_low) << 3
            | u8::from(self.ratcs) << 2
            | (self.reserved_bits & 1) << 1
            | u8::from(self.uat_initialized);
        let s2 = (((self.timestamp_s >> 16) & 1) as u8) << 7
            | u8::from(self.csa_requested) << 6
            | u8::from(self.csa_not_available) << 5
            | (self.reserved_bits & 0x1E)
            | u8::from(self.utc_ok);
        let t = ((self.timestamp_s & 0xFFFF) as u16).to_le_bytes();
        let counts = (u16::from(self.uplink_count & 0x1F) << 11)
            | u16::from(self.counts_reserved_bit) << 10
            | (self.basic_long_count & 0x3FF);
        let c = counts.to_be_bytes();
        [ID, s1, s2, t[0], t[1], c[0], c[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_example() {
        // GDL 90 spec 2.2.4 example, clear message 00 81 41 DB D0 08 02:
        // status 1 = 0x81: GPS Pos Valid (b7) and UAT Initialized (b0);
        // status 2 = 0x41: CSA Requested (b6) and UTC OK (b0), time stamp bit 16 = 0;
        // time stamp = 0xD0DB (LS byte first) = 53467 s = 14:51:07Z;
        // counts = 0x0802: uplink = 0x0802 >> 11 = 1, basic/long = 0x0802 & 0x3FF = 2.
        let m = [0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02];
        let h = Heartbeat::decode(&m).unwrap();
        assert_eq!(
            h,
            Heartbeat {
                gps_pos_valid: true,
                uat_initialized: true,
                csa_requested: true,
                utc_ok: true,
                timestamp_s: 53467,
                uplink_count: 1,
                basic_long_count: 2,
                ..Default::default()
            }
        );
        assert_eq!(h.encode(), m);
    }

    #[test]
    fn every_field() {
        // status 1 = 0x7C: Maint Req, IDENT, Addr Type, GPS Batt Low, RATCS;
        // status 2 = 0xA0: time stamp bit 16 and CSA Not Available;
        // time 0x0001 + 65536 = 65537 s; counts 0xFBFF: uplink 31, reserved bit 10 = 0, count 1023.
        let m = [0x00, 0x7C, 0xA0, 0x01, 0x00, 0xFB, 0xFF];
        let h = Heartbeat::decode(&m).unwrap();
        assert!(!h.gps_pos_valid && h.maint_req && h.ident && h.addr_type_talkback);
        assert!(h.gps_batt_low && h.ratcs && !h.uat_initialized);
        assert!(!h.csa_requested && h.csa_not_available && !h.utc_ok);
        assert_eq!(h.timestamp_s, 65537);
        assert_eq!(h.uplink_count, 31);
        assert_eq!(h.basic_long_count, 1023);
        assert!(!h.counts_reserved_bit);
        assert_eq!(h.reserved_bits, 0);
        assert_eq!(h.encode(), m);
        assert_eq!(Heartbeat::decode(&m[..6]), None);
    }
}

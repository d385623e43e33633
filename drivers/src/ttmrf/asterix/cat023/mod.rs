//! ASTERIX CAT023 edition 1.2, CNS/ATM ground station and service status reports
//! (EUROCONTROL-SPEC-0149-16 ed 1.2). The TT-Multi-RF sends one CAT023 "ground station status"
//! record per second as a heartbeat (manual 7.2.1 "ADS-B ASTERIX protocol").
//!
//! UAP (FRN: item, length rule):
//! ```text
//!  1 I023/010 Data Source Identifier       2
//!  2 I023/000 Report Type                  1
//!  3 I023/015 Service Type and Identification 1  (SID b8..b5, STYP b4..b1)
//!  4 I023/070 Time of Day                  3     (1/128 s)
//!  5 I023/100 Ground Station Status        1+    (NOGO ODP OXT MSC TSV SPO RN FX | GSSP 7 bits FX)
//!  6 I023/101 Service Configuration        2+    (RP 0.5 s | SC b8..b6, spare, FX | SSRP 7 bits FX)
//!  7 I023/200 Operational Range            1     (1 NM)
//!  8 I023/110 Service Status               1+    (spare b8..b5, STAT b4..b2, FX)
//!  9 I023/120 Service Statistics           1+6n  (TYPE | REF b8, spare | counter 32 bits)
//! 10-12 spare
//! 13 RE                                    explicit
//! 14 SP                                    explicit
//! ```
//! A record must carry I023/010 (mandatory in the standard).

#[cfg(test)]
mod tests;

use serde::Serialize;

use super::common::{DataSource, decode_tod, encode_tod};
use super::item::{ItemError, Rule, be_u64, fspec_len, item_len, push_fspec, set_bits};

/// ASTERIX category number.
pub const CAT: u8 = 23;

const EXT1: Rule = Rule::Extended { first: 1, ext: 1 };

/// Item name and rule at each FRN (index = FRN - 1).
pub const UAP: [Option<(&str, Rule)>; 14] = [
    Some(("I023/010", Rule::Fixed(2))),
    Some(("I023/000", Rule::Fixed(1))),
    Some(("I023/015", Rule::Fixed(1))),
    Some(("I023/070", Rule::Fixed(3))),
    Some(("I023/100", EXT1)),
    Some(("I023/101", Rule::Extended { first: 2, ext: 1 })),
    Some(("I023/200", Rule::Fixed(1))),
    Some(("I023/110", EXT1)),
    Some(("I023/120", Rule::Repetitive(6))),
    None,
    None,
    None,
    Some(("I023/RE", Rule::Explicit)),
    Some(("I023/SP", Rule::Explicit)),
];

/// I023/015 Service Type and Identification.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct ServiceType {
    /// SID service identification, 0..=15.
    pub sid: u8,
    /// STYP: 1 ADS-B VDL4, 2 ADS-B Ext Squitter, 3 ADS-B UAT, 4 TIS-B VDL4, 5 TIS-B Ext
    /// Squitter, 6 TIS-B UAT, 7 FIS-B VDL4, 8 GRAS VDL4, 9 MLT.
    pub styp: u8,
}

/// I023/100 Ground Station Status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct GroundStationStatus {
    /// NOGO: data not released for operational use.
    pub nogo: bool,
    /// ODP: data processor overload.
    pub odp: bool,
    /// OXT: ground interface data communications overload.
    pub oxt: bool,
    /// MSC: monitoring system connected.
    pub msc: bool,
    /// TSV: time source not valid.
    pub tsv: bool,
    /// SPO: indication of spoofing attack.
    pub spo: bool,
    /// RN: renumbering indication for track numbers.
    pub rn: bool,
    /// GSSP ground station status reporting period, s (first extension).
    pub gssp_s: Option<u8>,
}

/// I023/101 Service Configuration.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ServiceConfiguration {
    /// RP report period for the service, s (LSB 0.5 s).
    pub rp_s: f64,
    /// SC service class: 0 no information, 1 NRA class, 2..7 reserved.
    pub sc: u8,
    /// SSRP service status reporting period, s (first extension).
    pub ssrp_s: Option<u8>,
}

/// One I023/120 Service Statistics element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct ServiceStatistic {
    /// TYPE: 0 unknown messages received, 1 too old messages, 2 failed message conversions,
    /// 3 total messages received, 4 total messages transmitted, 20.. link-specific counts.
    pub kind: u8,
    /// REF: false counted from UTC midnight, true counted since the previous report.
    pub since_last_report: bool,
    /// Counter value.
    pub value: u32,
}

/// One CAT023 record: every decoded item, `None` when absent.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Cat023Record {
    /// I023/010 Data Source Identifier.
    pub data_source: Option<DataSource>,
    /// I023/000 Report Type: 1 ground station status, 2 service status, 3 service statistics.
    pub report_type: Option<u8>,
    /// I023/015 Service Type and Identification.
    pub service: Option<ServiceType>,
    /// I023/070 Time of Day, s since midnight UTC.
    pub time_of_day_s: Option<f64>,
    /// I023/100 Ground Station Status.
    pub ground_station_status: Option<GroundStationStatus>,
    /// I023/101 Service Configuration.
    pub service_configuration: Option<ServiceConfiguration>,
    /// I023/200 Operational Range, NM.
    pub operational_range_nm: Option<u8>,
    /// I023/110 Service Status STAT: 0 unknown, 1 failed, 2 disabled, 3 degraded, 4 normal,
    /// 5 initialisation.
    pub service_status: Option<u8>,
    /// I023/120 Service Statistics.
    pub service_statistics: Option<Vec<ServiceStatistic>>,
    /// Items present but not decoded (RE, SP), by name.
    pub undecoded: Vec<&'static str>,
}

fn bit(o: u8, n: u8) -> bool {
    o & (1 << (n - 1)) != 0
}

/// Decodes one record from the start of `b`; returns it and its length in octets.
pub fn decode_record(b: &[u8]) -> Result<(Cat023Record, usize), ItemError> {
    let fl = fspec_len(b).ok_or(ItemError::Truncated("fspec"))?;
    let mut pos = fl;
    let mut r = Cat023Record::default();
    for index in set_bits(&b[..fl]) {
        let (name, rule) = UAP
            .get(index)
            .copied()
            .flatten()
            .ok_or(ItemError::UndefinedFrn(index + 1))?;
        let rest = b.get(pos..).unwrap_or(&[]);
        let len = item_len(rule, rest, name)?;
        let item = &rest[..len];
        match index {
            0 => r.data_source = Some(DataSource::decode(item)?),
            1 => r.report_type = Some(item[0]),
            2 => {
                r.service = Some(ServiceType {
                    sid: item[0] >> 4,
                    styp: item[0] & 0x0F,
                })
            }
            3 => r.time_of_day_s = Some(decode_tod(item)?),
            4 => {
                let o = item[0];
                r.ground_station_status = Some(GroundStationStatus {
                    nogo: bit(o, 8),
                    odp: bit(o, 7),
                    oxt: bit(o, 6),
                    msc: bit(o, 5),
                    tsv: bit(o, 4),
                    spo: bit(o, 3),
                    rn: bit(o, 2),
                    gssp_s: item.get(1).map(|&e| e >> 1),
                })
            }
            5 => {
                r.service_configuration = Some(ServiceConfiguration {
                    rp_s: f64::from(item[0]) * 0.5,
                    sc: item[1] >> 5,
                    ssrp_s: item.get(2).map(|&e| e >> 1),
                })
            }
            6 => r.operational_range_nm = Some(item[0]),
            7 => r.service_status = Some((item[0] >> 1) & 7),
            8 => {
                r.service_statistics = Some(
                    item[1..]
                        .chunks_exact(6)
                        .map(|e| ServiceStatistic {
                            kind: e[0],
                            since_last_report: e[1] & 0x80 != 0,
                            value: be_u64(&e[2..6]) as u32,
                        })
                        .collect(),
                )
            }
            _ => r.undecoded.push(name),
        }
        pos += len;
    }
    if r.data_source.is_none() {
        return Err(ItemError::Malformed("I023/010 missing"));
    }
    Ok((r, pos))
}

impl Cat023Record {
    /// Appends the record (FSPEC and every decoded item present, in UAP order). At most 255
    /// statistics elements are written.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let mut indices = Vec::new();
        let mut body = Vec::new();
        if let Some(s) = self.data_source {
            indices.push(0);
            s.encode(&mut body);
        }
        if let Some(t) = self.report_type {
            indices.push(1);
            body.push(t);
        }
        if let Some(s) = self.service {
            indices.push(2);
            body.push((s.sid & 0x0F) << 4 | (s.styp & 0x0F));
        }
        if let Some(t) = self.time_of_day_s {
            indices.push(3);
            encode_tod(t, &mut body);
        }
        if let Some(g) = self.ground_station_status {
            indices.push(4);
            let o = u8::from(g.nogo) << 7
                | u8::from(g.odp) << 6
                | u8::from(g.oxt) << 5
                | u8::from(g.msc) << 4
                | u8::from(g.tsv) << 3
                | u8::from(g.spo) << 2
                | u8::from(g.rn) << 1;
            match g.gssp_s {
                Some(p) => body.extend_from_slice(&[o | 1, (p & 0x7F) << 1]),
                None => body.push(o),
            }
        }
        if let Some(c) = self.service_configuration {
            indices.push(5);
            let rp = (c.rp_s / 0.5).round().clamp(0.0, 255.0) as u8;
            let o2 = (c.sc & 7) << 5;
            match c.ssrp_s {
                Some(p) => body.extend_from_slice(&[rp, o2 | 1, (p & 0x7F) << 1]),
                None => body.extend_from_slice(&[rp, o2]),
            }
        }
        if let Some(r) = self.operational_range_nm {
            indices.push(6);
            body.push(r);
        }
        if let Some(s) = self.service_status {
            indices.push(7);
            body.push((s & 7) << 1);
        }
        if let Some(stats) = &self.service_statistics {
            indices.push(8);
            let n = stats.len().min(255);
            body.push(n as u8);
            for s in &stats[..n] {
                body.push(s.kind);
                body.push(u8::from(s.since_last_report) << 7);
                body.extend_from_slice(&s.value.to_be_bytes());
            }
        }
        push_fspec(&indices, out);
        out.extend_from_slice(&body);
    }
}

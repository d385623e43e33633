//! CAT021 ed 2.1 status and quality items: I021/040 Target Report Descriptor, I021/090 Quality
//! Indicators and I021/200 Target Status (EUROCONTROL-SPEC-0149-12 ed 2.1, 5.2).

use serde::Serialize;

use super::super::item::ItemError;

fn b(o: u8, bit: u8) -> bool {
    o & (1 << (bit - 1)) != 0
}

fn fx(octets: &mut [u8]) {
    let n = octets.len();
    for o in &mut octets[..n.saturating_sub(1)] {
        *o |= 1;
    }
}

/// First extension of I021/040.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct DescriptorExt1 {
    /// DCR: differential correction.
    pub dcr: bool,
    /// GBS: ground bit set (the target reports being on the ground).
    pub gbs: bool,
    /// SIM: simulated target report.
    pub sim: bool,
    /// TST: test target.
    pub tst: bool,
    /// SAA: equipment not capable of providing selected altitude.
    pub saa: bool,
    /// CL confidence level: 0 report valid, 1 report suspect, 2 no information, 3 reserved.
    pub cl: u8,
}

/// Second extension of I021/040 (bits 8..7 spare).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct DescriptorExt2 {
    /// IPC (bit 6): independent position check failed.
    pub ipc: bool,
    /// NOGO (bit 5): NOGO bit set.
    pub nogo: bool,
    /// CPR (bit 4): CPR validation failed.
    pub cpr: bool,
    /// LDPJ (bit 3): local decoding position jump detected.
    pub ldpj: bool,
    /// RCF (bit 2): range check failed.
    pub rcf: bool,
}

/// I021/040 Target Report Descriptor. Edition 2.1 defines the first part and two extensions;
/// any further extension (later editions add TBC and MCP) is skipped by the length rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct TargetReportDescriptor {
    /// ATP address type: 0 24-bit ICAO, 1 duplicate address, 2 surface vehicle, 3 anonymous
    /// (the TT-Multi-RF uses 3 for FLARM and other non-ICAO ids, manual 8.2.1), 4..7 reserved.
    pub atp: u8,
    /// ARC altitude reporting capability: 0 25 ft, 1 100 ft, 2 unknown, 3 invalid.
    pub arc: u8,
    /// RC: range check passed, CPR validation pending.
    pub rc: bool,
    /// RAB: report from a field monitor (fixed transponder) rather than a target.
    pub rab: bool,
    /// First extension.
    pub ext1: Option<DescriptorExt1>,
    /// Second extension.
    pub ext2: Option<DescriptorExt2>,
}

impl TargetReportDescriptor {
    /// Decodes the item (its length already delimited by the FX rule).
    pub fn decode(bytes: &[u8]) -> Result<Self, ItemError> {
        let &o = bytes.first().ok_or(ItemError::Malformed("I021/040"))?;
        Ok(Self {
            atp: o >> 5,
            arc: (o >> 3) & 3,
            rc: b(o, 3),
            rab: b(o, 2),
            ext1: bytes.get(1).map(|&o| DescriptorExt1 {
                dcr: b(o, 8),
                gbs: b(o, 7),
                sim: b(o, 6),
                tst: b(o, 5),
                saa: b(o, 4),
                cl: (o >> 1) & 3,
            }),
            ext2: bytes.get(2).map(|&o| DescriptorExt2 {
                ipc: b(o, 6),
                nogo: b(o, 5),
                cpr: b(o, 4),
                ldpj: b(o, 3),
                rcf: b(o, 2),
            }),
        })
    }

    /// Appends the item: octets up to the last extension present (a missing first extension
    /// before a present second one is sent as a zero octet).
    pub fn encode(&self, out: &mut Vec<u8>) {
        let mut o = [0u8; 3];
        o[0] = (self.atp & 7) << 5
            | (self.arc & 3) << 3
            | u8::from(self.rc) << 2
            | u8::from(self.rab) << 1;
        let e1 = self.ext1.unwrap_or_default();
        o[1] = u8::from(e1.dcr) << 7
            | u8::from(e1.gbs) << 6
            | u8::from(e1.sim) << 5
            | u8::from(e1.tst) << 4
            | u8::from(e1.saa) << 3
            | (e1.cl & 3) << 1;
        let e2 = self.ext2.unwrap_or_default();
        o[2] = u8::from(e2.ipc) << 5
            | u8::from(e2.nogo) << 4
            | u8::from(e2.cpr) << 3
            | u8::from(e2.ldpj) << 2
            | u8::from(e2.rcf) << 1;
        let n = if self.ext2.is_some() {
            3
        } else if self.ext1.is_some() {
            2
        } else {
            1
        };
        fx(&mut o[..n]);
        out.extend_from_slice(&o[..n]);
    }
}

/// First extension of I021/090.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct QualityExt1 {
    /// NICbaro: barometric altitude cross-checked.
    pub nic_baro: bool,
    /// SIL, 0..=3.
    pub sil: u8,
    /// NACp, 0..=15.
    pub nac_p: u8,
}

/// Second extension of I021/090.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct QualityExt2 {
    /// SIL supplement: false per flight hour, true per sample.
    pub sil_per_sample: bool,
    /// SDA, 0..=3.
    pub sda: u8,
    /// GVA, 0..=3.
    pub gva: u8,
}

/// I021/090 Quality Indicators. Extensions after the third are skipped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct QualityIndicators {
    /// NUCr or NACv, 0..=7.
    pub nac_v: u8,
    /// NUCp or NIC, 0..=15.
    pub nic: u8,
    /// First extension.
    pub ext1: Option<QualityExt1>,
    /// Second extension.
    pub ext2: Option<QualityExt2>,
    /// Third extension: PIC (position integrity category), 0..=15.
    pub pic: Option<u8>,
}

impl QualityIndicators {
    /// Decodes the item (its length already delimited by the FX rule).
    pub fn decode(bytes: &[u8]) -> Result<Self, ItemError> {
        let &o = bytes.first().ok_or(ItemError::Malformed("I021/090"))?;
        Ok(Self {
            nac_v: o >> 5,
            nic: (o >> 1) & 0x0F,
            ext1: bytes.get(1).map(|&o| QualityExt1 {
                nic_baro: b(o, 8),
                sil: (o >> 5) & 3,
                nac_p: (o >> 1) & 0x0F,
            }),
            ext2: bytes.get(2).map(|&o| QualityExt2 {
                sil_per_sample: b(o, 6),
                sda: (o >> 3) & 3,
                gva: (o >> 1) & 3,
            }),
            pic: bytes.get(3).map(|&o| o >> 4),
        })
    }

    /// Appends the item: octets up to the last extension present.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let mut o = [0u8; 4];
        o[0] = (self.nac_v & 7) << 5 | (self.nic & 0x0F) << 1;
        let e1 = self.ext1.unwrap_or_default();
        o[1] = u8::from(e1.nic_baro) << 7 | (e1.sil & 3) << 5 | (e1.nac_p & 0x0F) << 1;
        let e2 = self.ext2.unwrap_or_default();
        o[2] = u8::from(e2.sil_per_sample) << 5 | (e2.sda & 3) << 3 | (e2.gva & 3) << 1;
        o[3] = (self.pic.unwrap_or(0) & 0x0F) << 4;
        let n = if self.pic.is_some() {
            4
        } else if self.ext2.is_some() {
            3
        } else if self.ext1.is_some() {
            2
        } else {
            1
        };
        fx(&mut o[..n]);
        out.extend_from_slice(&o[..n]);
    }
}

/// I021/200 Target Status (ed 2.1: ICF, LNAV, one spare bit, PS, SS).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct TargetStatus {
    /// ICF: intent change flag.
    pub icf: bool,
    /// LNAV: LNAV mode NOT engaged (the bit is set when LNAV is off).
    pub lnav_not_engaged: bool,
    /// PS priority status: 0 none, 1 general emergency, 2 lifeguard/medical, 3 minimum fuel,
    /// 4 no communications, 5 unlawful interference, 6 downed aircraft (7 undefined in ed 2.1).
    pub ps: u8,
    /// SS surveillance status: 0 no condition, 1 permanent alert (emergency), 2 temporary alert
    /// (Mode 3/A change other than emergency), 3 SPI set.
    pub ss: u8,
}

impl TargetStatus {
    /// Decodes the one-octet item.
    pub fn decode(bytes: &[u8]) -> Result<Self, ItemError> {
        let &[o] = bytes else {
            return Err(ItemError::Malformed("I021/200"));
        };
        Ok(Self {
            icf: b(o, 8),
            lnav_not_engaged: b(o, 7),
            ps: (o >> 2) & 7,
            ss: o & 3,
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        out.push(
            u8::from(self.icf) << 7
                | u8::from(self.lnav_not_engaged) << 6
                | (self.ps & 7) << 2
                | (self.ss & 3),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptor_of_the_sample() {
        // CAT021 sample: I021/040 = 01 40.
        // 0x01: ATP 000 (24-bit ICAO), ARC 00 (25 ft), RC 0, RAB 0, FX 1.
        // 0x40 = 0100 0000: DCR 0, GBS 1, SIM 0, TST 0, SAA 0, CL 00, FX 0.
        let d = TargetReportDescriptor::decode(&[0x01, 0x40]).unwrap();
        assert_eq!((d.atp, d.arc, d.rc, d.rab), (0, 0, false, false));
        let e = d.ext1.unwrap();
        assert!(e.gbs && !e.dcr && !e.sim && !e.tst && !e.saa);
        assert_eq!(e.cl, 0);
        assert_eq!(d.ext2, None);
        let mut out = Vec::new();
        d.encode(&mut out);
        assert_eq!(out, [0x01, 0x40]);
    }

    #[test]
    fn descriptor_every_extension() {
        // 0x6F = 011 01 1 1 1: ATP 3 (anonymous), ARC 1 (100 ft), RC, RAB, FX.
        // 0xBB = 1 0 1 1 1 01 1: DCR, SIM, TST, SAA, CL 1, FX.
        // 0x3E = 00 1 1 1 1 1 0: (spare 2) IPC, NOGO, CPR, LDPJ, RCF, no FX.
        let bytes = [0x6F, 0xBB, 0x3E];
        let d = TargetReportDescriptor::decode(&bytes).unwrap();
        assert_eq!((d.atp, d.arc, d.rc, d.rab), (3, 1, true, true));
        let e1 = d.ext1.unwrap();
        assert!(e1.dcr && !e1.gbs && e1.sim && e1.tst && e1.saa);
        assert_eq!(e1.cl, 1);
        let e2 = d.ext2.unwrap();
        assert!(e2.ipc && e2.nogo && e2.cpr && e2.ldpj && e2.rcf);
        let mut out = Vec::new();
        d.encode(&mut out);
        assert_eq!(out, bytes);
        // Bit n is 1 << (n - 1): in the second extension 0x10 is bit 5, NOGO alone.
        let d = TargetReportDescriptor::decode(&[0x01, 0x01, 0x10]).unwrap();
        assert_eq!(
            d.ext2,
            Some(DescriptorExt2 {
                nogo: true,
                ..Default::default()
            })
        );
    }

    #[test]
    fn quality() {
        // 0x00: NACv 0, NIC 0 (the sample).
        let q = QualityIndicators::decode(&[0x00]).unwrap();
        assert_eq!((q.nac_v, q.nic, q.ext1), (0, 0, None));
        // 0x51 = 010 1000 1: NACv 2, NIC 8, FX. 0xD3 = 1 10 1001 1: NICbaro, SIL 2, NACp 9, FX.
        // 0x2D = 00 1 01 10 1: SIL per sample, SDA 1, GVA 2, FX. 0xB0: PIC 11.
        let bytes = [0x51, 0xD3, 0x2D, 0xB0];
        let q = QualityIndicators::decode(&bytes).unwrap();
        assert_eq!((q.nac_v, q.nic), (2, 8));
        assert_eq!(
            q.ext1,
            Some(QualityExt1 {
                nic_baro: true,
                sil: 2,
                nac_p: 9
            })
        );
        assert_eq!(
            q.ext2,
            Some(QualityExt2 {
                sil_per_sample: true,
                sda: 1,
                gva: 2
            })
        );
        assert_eq!(q.pic, Some(11));
        let mut out = Vec::new();
        q.encode(&mut out);
        assert_eq!(out, bytes);
    }

    #[test]
    fn target_status() {
        // 0xC7 = 1 1 0 001 11: ICF, LNAV not engaged, (spare), PS 1 (general emergency),
        // SS 3 (SPI).
        let s = TargetStatus::decode(&[0xC7]).unwrap();
        assert!(s.icf && s.lnav_not_engaged);
        assert_eq!((s.ps, s.ss), (1, 3));
        let mut out = Vec::new();
        s.encode(&mut out);
        assert_eq!(out, [0xC7]);
        // The spare bit 6 is ignored: 0x38 = 0 0 1 110 00 -> PS 6 (downed aircraft), SS 0.
        assert_eq!(TargetStatus::decode(&[0x38]).unwrap().ps, 6);
        assert!(TargetStatus::decode(&[]).is_err());
    }
}

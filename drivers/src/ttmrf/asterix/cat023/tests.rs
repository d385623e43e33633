//! CAT023 record tests: hand-built records for every item, skipping of RE/SP, errors and round
//! trips.

use proptest::prelude::*;

use super::*;

/// A ground-station-status record packed by hand.
///
/// FSPEC `FF 86`: FF = FRN 1..7 (010, 000, 015, 070, 100, 101, 200), FX; the second octet's
/// bits 8..2 are FRN 8..14: 0x86 = 1000 011 0 -> FRN 8 (110), 13 (RE), 14 (SP), no FX.
const GSS_RECORD: &[u8] = &[
    0xFF, 0x86, // FSPEC
    0x00, 0x81, // 010: SAC 0, SIC 129 (the module's default ASTERIX_SIC)
    0x01, // 000: report type 1 (ground station status)
    0x12, // 015: SID 1, STYP 2 (ADS-B Ext Squitter)
    0x38, 0x41, 0x76, // 070: 3686774 / 128 = 28802.921875 s
    0x83, 0x02, // 100: 1000 001 1 = NOGO, RN, FX; 0000 001 0 = GSSP 1 s
    0x02, 0x21, 0x0A, // 101: RP 2 * 0.5 = 1 s; 001 0000 1 = SC 1, FX; 0000 101 0 = SSRP 5 s
    0xFA, // 200: 250 NM
    0x08, // 110: 0000 100 0 = STAT 4 (normal)
    0x03, 0xEE, 0xFF, // RE, length 3
    0x02, 0x55, // SP, length 2
];

#[test]
fn hand_built_ground_station_status() {
    let (r, len) = decode_record(GSS_RECORD).unwrap();
    assert_eq!(len, GSS_RECORD.len());
    assert_eq!(r.data_source, Some(DataSource { sac: 0, sic: 129 }));
    assert_eq!(r.report_type, Some(1));
    assert_eq!(r.service, Some(ServiceType { sid: 1, styp: 2 }));
    assert_eq!(r.time_of_day_s, Some(28_802.921_875));
    assert_eq!(
        r.ground_station_status,
        Some(GroundStationStatus {
            nogo: true,
            rn: true,
            gssp_s: Some(1),
            ..Default::default()
        })
    );
    assert_eq!(
        r.service_configuration,
        Some(ServiceConfiguration {
            rp_s: 1.0,
            sc: 1,
            ssrp_s: Some(5)
        })
    );
    assert_eq!(r.operational_range_nm, Some(250));
    assert_eq!(r.service_status, Some(4));
    assert_eq!(r.service_statistics, None);
    assert_eq!(r.undecoded, vec!["I023/RE", "I023/SP"]);
    // Without RE/SP the encoder reproduces the rest: FSPEC 0x80 for the second octet.
    let mut out = Vec::new();
    r.encode(&mut out);
    let mut expect = vec![0xFF, 0x80];
    expect.extend_from_slice(&GSS_RECORD[2..GSS_RECORD.len() - 5]);
    assert_eq!(out, expect);
}

#[test]
fn statistics_and_short_forms() {
    // FSPEC 81 C0: FRN 1 (010) | FRN 8 (110), 9 (120).
    // 100 and 101 absent; 110 = 0x02 -> STAT 1 (failed);
    // 120: REP 2; TYPE 3, REF 0, counter 0x00010000 = 65536; TYPE 0, REF 1, counter 7.
    let b = [
        0x81, 0xC0, 0x01, 0x02, 0x02, 0x02, 0x03, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x80, 0x00,
        0x00, 0x00, 0x07,
    ];
    let (r, len) = decode_record(&b).unwrap();
    assert_eq!(len, b.len());
    assert_eq!(r.service_status, Some(1));
    assert_eq!(
        r.service_statistics,
        Some(vec![
            ServiceStatistic {
                kind: 3,
                since_last_report: false,
                value: 65536
            },
            ServiceStatistic {
                kind: 0,
                since_last_report: true,
                value: 7
            }
        ])
    );
    let mut out = Vec::new();
    r.encode(&mut out);
    assert_eq!(out, b);
    // 100 and 101 without extensions: FSPEC 0x0C = FRN 5, 6 ... plus 010: 0x8C.
    // 100 = 0x40 (ODP), 101 = RP 0x10 (8 s), 0xE0 (SC 7).
    let b = [0x8C, 0x00, 0x05, 0x40, 0x10, 0xE0];
    let (r, _) = decode_record(&b).unwrap();
    let g = r.ground_station_status.unwrap();
    assert!(g.odp && !g.nogo && g.gssp_s.is_none());
    assert_eq!(
        r.service_configuration,
        Some(ServiceConfiguration {
            rp_s: 8.0,
            sc: 7,
            ssrp_s: None
        })
    );
}

#[test]
fn errors() {
    // FRN 10 is spare.
    assert_eq!(
        decode_record(&[0x81, 0x20, 0x00, 0x01]),
        Err(ItemError::UndefinedFrn(10))
    );
    // 120 with REP 1 but only 5 octets.
    assert_eq!(
        decode_record(&[0x81, 0x40, 0x00, 0x01, 0x01, 1, 2, 3, 4, 5]),
        Err(ItemError::Truncated("I023/120"))
    );
    assert_eq!(
        decode_record(&[0x40, 0x01]),
        Err(ItemError::Malformed("I023/010 missing"))
    );
    for cut in 0..GSS_RECORD.len() {
        assert!(decode_record(&GSS_RECORD[..cut]).is_err(), "cut {cut}");
    }
}

prop_compose! {
    fn record()(
        sac_sic in any::<(u8, u8)>(),
        rt in proptest::option::of(any::<u8>()),
        svc in proptest::option::of((0u8..16, 0u8..16)),
        tod in proptest::option::of(0u32..0x100_0000),
        gss in proptest::option::of((any::<u8>(), proptest::option::of(0u8..128))),
        cfg in proptest::option::of((any::<u8>(), 0u8..8, proptest::option::of(0u8..128))),
        range in proptest::option::of(any::<u8>()),
        stat in proptest::option::of(0u8..8),
        stats in proptest::option::of(proptest::collection::vec(any::<(u8, bool, u32)>(), 0..5)),
    ) -> Cat023Record {
        Cat023Record {
            data_source: Some(DataSource { sac: sac_sic.0, sic: sac_sic.1 }),
            report_type: rt,
            service: svc.map(|(sid, styp)| ServiceType { sid, styp }),
            time_of_day_s: tod.map(|c| f64::from(c) / 128.0),
            ground_station_status: gss.map(|(o, p)| GroundStationStatus {
                nogo: o & 0x80 != 0,
                odp: o & 0x40 != 0,
                oxt: o & 0x20 != 0,
                msc: o & 0x10 != 0,
                tsv: o & 0x08 != 0,
                spo: o & 0x04 != 0,
                rn: o & 0x02 != 0,
                gssp_s: p,
            }),
            service_configuration: cfg.map(|(rp, sc, p)| ServiceConfiguration {
                rp_s: f64::from(rp) * 0.5,
                sc,
                ssrp_s: p,
            }),
            operational_range_nm: range,
            service_status: stat,
            service_statistics: stats.map(|v| {
                v.into_iter()
                    .map(|(kind, since_last_report, value)| ServiceStatistic {
                        kind,
                        since_last_report,
                        value,
                    })
                    .collect()
            }),
            undecoded: Vec::new(),
        }
    }
}

proptest! {
    #[test]
    fn round_trip(r in record()) {
        let mut bytes = Vec::new();
        r.encode(&mut bytes);
        let (back, len) = decode_record(&bytes).unwrap();
        prop_assert_eq!(len, bytes.len());
        prop_assert_eq!(back, r);
    }
}

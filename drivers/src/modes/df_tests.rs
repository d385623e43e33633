//! Frame-level tests: every handled DF, parity rules, lengths, corrupted frames.

use super::*;
use crate::modes::encode;
use crate::modes::hex_frame;

fn dec(hex: &str) -> Result<ModeS, Reject> {
    let (f, n) = hex_frame(hex);
    decode(&f[..n], DecodeOptions::default())
}

#[test]
fn df17_identification_klm1023() {
    let m = dec("8D4840D6202CC371C32CE0576098").unwrap();
    assert_eq!((m.df, m.icao, m.parity), (17, 0x48_40D6, Parity::Verified));
    let Content::Extended {
        ca_cf,
        me: Me::Identification(id),
        ..
    } = m.content
    else {
        panic!("{m:?}")
    };
    assert_eq!(ca_cf, 5);
    assert_eq!(id.callsign.as_str(), "KLM1023");
}

#[test]
fn df0_df4_df5_df16_df20_df21_from_the_capture() {
    // Values as dump1090 printed them for the ulss7 capture.
    let m = dec("02A184999C5FE3").unwrap(); // DF:0 addr 504DD9, 6425 ft
    assert_eq!(
        (m.df, m.icao, m.parity),
        (0, 0x50_4DD9, Parity::AddressParity)
    );
    assert!(matches!(
        m.content,
        Content::Surveillance {
            altitude_ft: Some(6425),
            squawk: None,
            ..
        }
    ));
    let m = dec("200014102064DA").unwrap(); // DF:4 addr 780C5D, AC 5136, 31000 ft
    assert_eq!((m.df, m.icao), (4, 0x78_0C5D));
    assert!(matches!(
        m.content,
        Content::Surveillance {
            altitude_ft: Some(31_000),
            ..
        }
    ));
    let m = dec("282018154A9D59").unwrap(); // DF:5 addr 400159, squawk 1017
    assert_eq!((m.df, m.icao), (5, 0x40_0159));
    let Content::Surveillance {
        squawk: Some(s),
        altitude_ft: None,
        mb: None,
        ..
    } = m.content
    else {
        panic!("{m:?}")
    };
    assert_eq!(s.to_string(), "1017");
    let m = dec("80A18498902583B6A913421BF699").unwrap(); // DF:16 504DD9, 6400 ft
    assert_eq!((m.df, m.icao), (16, 0x50_4DD9));
    assert!(matches!(
        m.content,
        Content::Surveillance {
            altitude_ft: Some(6400),
            ..
        }
    ));
    let m = dec("A0200233EA59BF163F57ECD3CB13").unwrap(); // DF:20 400159, 2675 ft
    assert_eq!((m.df, m.icao), (20, 0x40_0159));
    let Content::Surveillance {
        altitude_ft: Some(2675),
        mb: Some(mb),
        callsign: None,
        ..
    } = m.content
    else {
        panic!("{m:?}")
    };
    assert_eq!(mb, 0x00EA_59BF_163F_57EC);
    let m = dec("A800133A000000000000006F37A1").unwrap(); // DF:21 4249B5, squawk 2751, MB 0
    assert_eq!((m.df, m.icao), (21, 0x42_49B5));
    let Content::Surveillance {
        squawk: Some(s),
        mb: Some(0),
        callsign: None,
        ..
    } = m.content
    else {
        panic!("{m:?}")
    };
    assert_eq!(s.to_string(), "2751");
}

#[test]
fn df20_bds20_callsign() {
    // Hand-built DF20 carrying BDS 2,0 "KLM1023": MB = 0x20 then the 48-bit characters of the
    // KLM1023 identification squitter (bytes 5..11 of 8D4840D6202CC371C32CE0576098).
    let mut f = [0u8; 14];
    f[0] = 20 << 3;
    f[4] = 0x20;
    f[5..11].copy_from_slice(&[0x2C, 0xC3, 0x71, 0xC3, 0x2C, 0xE0]);
    crate::modes::crc::set_parity(&mut f, 0x48_40D6);
    let m = decode(&f, DecodeOptions::default()).unwrap();
    assert_eq!(m.icao, 0x48_40D6);
    let Content::Surveillance {
        callsign: Some(c), ..
    } = m.content
    else {
        panic!("{m:?}")
    };
    assert_eq!(c.as_str(), "KLM1023");
}

#[test]
fn df11_with_and_without_interrogator_code() {
    // From the capture: "*5f4001594b0fbb; CRC: 000000 DF:11 AA:400159 CA:7".
    let m = dec("5F4001594B0FBB").unwrap();
    assert_eq!((m.df, m.icao, m.parity), (11, 0x40_0159, Parity::Verified));
    assert_eq!(m.content, Content::AllCall { capability: 7 });
    let f = encode::df11(5, 0x48_40D6, 9).unwrap();
    let m = decode(&f, DecodeOptions::default()).unwrap();
    assert_eq!((m.icao, m.parity), (0x48_40D6, Parity::Interrogator(9)));
    // A remainder above 127 is a corrupted frame, not an interrogator code.
    let mut g = f;
    g[6] ^= 0x80;
    g[5] ^= 0x01;
    assert!(matches!(
        decode(&g, DecodeOptions::default()),
        Err(Reject::Parity { df: 11, .. })
    ));
}

#[test]
fn corrupted_extended_squitters_are_rejected() {
    let (f, _) = hex_frame("8D4840D6202CC371C32CE0576098");
    let mut rng = crate::testkit::XorShift::new(5);
    for _ in 0..2000 {
        let mut g = f;
        let flips = 1 + rng.below(3) as usize;
        crate::testkit::flip_bits(&mut g[1..], flips, &mut rng);
        if g == f {
            continue;
        }
        match decode(&g, DecodeOptions::default()) {
            Err(Reject::Parity { .. }) => {}
            other => panic!("corrupted frame accepted: {g:02X?} {other:?}"),
        }
    }
}

#[test]
fn single_bit_correction_is_opt_in_and_df17_only() {
    let (f, _) = hex_frame("8D4840D6202CC371C32CE0576098");
    let on = DecodeOptions {
        correct_df17_single_bit: true,
    };
    let mut g = f;
    g[6] ^= 0x10; // byte 6 bit 3 = bit 51
    assert!(decode(&g, DecodeOptions::default()).is_err());
    let m = decode(&g, on).unwrap();
    assert_eq!(m.parity, Parity::Corrected(51));
    let Content::Extended {
        me: Me::Identification(id),
        ..
    } = m.content
    else {
        panic!()
    };
    assert_eq!(id.callsign.as_str(), "KLM1023");
    // Two errors are not "corrected".
    g[9] ^= 0x01;
    assert!(decode(&g, on).is_err());
    // DF18 is never corrected.
    let mut h = f;
    h[0] = (18 << 3) | 5;
    crate::modes::crc::set_parity(&mut h, 0);
    h[6] ^= 0x10;
    assert!(decode(&h, on).is_err());
}

#[test]
fn lengths_and_unknown_formats() {
    let (f, _) = hex_frame("8D4840D6202CC371C32CE0576098");
    assert_eq!(
        decode(&f[..7], DecodeOptions::default()),
        Err(Reject::Length { df: 17, len: 7 })
    );
    assert_eq!(
        decode(&[], DecodeOptions::default()),
        Err(Reject::UnknownDf(0)).or(Err(Reject::Length { df: 0, len: 0 }))
    );
    let mut g = [0u8; 7];
    g[0] = 19 << 3;
    assert_eq!(
        decode(&g, DecodeOptions::default()),
        Err(Reject::UnknownDf(19))
    );
    g[0] = 2 << 3;
    assert_eq!(
        decode(&g, DecodeOptions::default()),
        Err(Reject::UnknownDf(2))
    );
    assert_eq!(downlink_format(&[0xC0]), 24);
    assert_eq!(downlink_format(&[0xF8]), 24);
    let mut d24 = [0u8; 14];
    d24[0] = 0xC5;
    assert!(matches!(
        decode(&d24, DecodeOptions::default()),
        Ok(ModeS {
            df: 24,
            content: Content::NotDecoded,
            ..
        })
    ));
}

#[test]
fn df18_cf_rules() {
    // DF18 CF 1 (non-ICAO) carries ADS-B ME; CF 3 (coarse TIS-B) is recognised only.
    let (f, _) = hex_frame("8D4840D6202CC371C32CE0576098");
    let mut g = f;
    g[0] = (18 << 3) | 1;
    crate::modes::crc::set_parity(&mut g, 0);
    let m = decode(&g, DecodeOptions::default()).unwrap();
    assert!(matches!(
        m.content,
        Content::Extended {
            ca_cf: 1,
            me: Me::Identification(_),
            ..
        }
    ));
    g[0] = (18 << 3) | 3;
    crate::modes::crc::set_parity(&mut g, 0);
    let m = decode(&g, DecodeOptions::default()).unwrap();
    assert_eq!(m.content, Content::NotDecoded);
}

#[test]
fn random_frames_never_panic() {
    let mut rng = crate::testkit::XorShift::new(99);
    let mut f = [0u8; 14];
    let mut accepted = 0;
    for _ in 0..100_000 {
        rng.fill(&mut f);
        let n = [0usize, 1, 3, 7, 13, 14][rng.below(6) as usize];
        for opts in [
            DecodeOptions::default(),
            DecodeOptions {
                correct_df17_single_bit: true,
            },
        ] {
            if decode(&f[..n], opts).is_ok() {
                accepted += 1;
            }
        }
    }
    // AP formats accept anything (their address is unverifiable): some frames pass.
    assert!(accepted > 0);
}

#[test]
fn pymodes_published_surveillance_vectors() {
    // pyModeS tests/test_surv.py: DF4 20001718029FCD -> 36 000 ft; DF5 2A00516D492B80 -> FS 2,
    // squawk 0356.
    let m = dec("20001718029FCD").unwrap();
    assert!(matches!(
        m.content,
        Content::Surveillance {
            altitude_ft: Some(36_000),
            ..
        }
    ));
    let m = dec("2A00516D492B80").unwrap();
    let Content::Surveillance {
        status: 2,
        squawk: Some(s),
        ..
    } = m.content
    else {
        panic!("{m:?}")
    };
    assert_eq!(s.to_string(), "0356");
    // Synthetic headers from the same file, parity built for address 400940: AC 0x1030 ->
    // 25 000 ft, AC 0 -> unknown, ID 0x0808 -> 1200, ID 0x0AA2 -> 7500.
    let build = |header: u32| {
        let mut f = [0u8; 7];
        f[..4].copy_from_slice(&header.to_be_bytes());
        crate::modes::crc::set_parity(&mut f, 0x40_0940);
        decode(&f, DecodeOptions::default()).unwrap()
    };
    let m = build(0x2000_1030);
    assert_eq!(m.icao, 0x40_0940);
    assert!(matches!(
        m.content,
        Content::Surveillance {
            altitude_ft: Some(25_000),
            ..
        }
    ));
    assert!(matches!(
        build(0x2000_0000).content,
        Content::Surveillance {
            altitude_ft: None,
            ..
        }
    ));
    for (h, sq) in [(0x2800_0808, "1200"), (0x2800_0AA2, "7500")] {
        let Content::Surveillance {
            squawk: Some(s), ..
        } = build(h).content
        else {
            panic!()
        };
        assert_eq!(s.to_string(), sq);
    }
}

#[test]
fn status_is_vs_for_df0_and_df16_and_fs_for_the_others() {
    // Annex 10 Vol IV 3.1.2.8.2: DF0 and DF16 carry VS (bit 6: 1 = on the ground), DF4, 5, 20
    // and 21 FS (bits 6-8). First word by hand: DF << 27 | the field.
    let status = |word: u32, len: usize| {
        let mut f = [0u8; 14];
        f[..4].copy_from_slice(&word.to_be_bytes());
        crate::modes::crc::set_parity(&mut f[..len], 0x40_0940);
        match decode(&f[..len], DecodeOptions::default()).unwrap().content {
            Content::Surveillance { status, .. } => status,
            c => panic!("{c:?}"),
        }
    };
    // DF0, VS = 1 (bit 6 is 1 << 26); FS-shaped bits 7-8 set alongside it do not count.
    assert_eq!(status(1 << 26, 7), 1);
    assert_eq!(status(3 << 24, 7), 0);
    // DF16, VS = 1.
    assert_eq!(status((16 << 27) | (1 << 26), 14), 1);
    // DF4 and DF20: FS = 5 (bits 6-8 = 101).
    assert_eq!(status((4 << 27) | (5 << 24), 7), 5);
    assert_eq!(status((20 << 27) | (5 << 24), 14), 5);
}

#[test]
fn a_single_bit_correction_is_counted_when_enabled() {
    // The Riddle's even frame with bit 60 flipped: repaired only with the option, and counted.
    use crate::modes::ModesDecoder;
    use crate::modes::decoder::ModesMessage;
    use crate::{DeviceDecoder, decode_slice};
    let (mut f, _) = hex_frame("8D40621D58C382D690C8AC2863A7");
    f[7] ^= 0x10;
    let hex: String = f.iter().map(|b| format!("{b:02X}")).collect();
    let line = format!("*{hex};\r\n");
    let cfg = crate::modes::TrackerConfig::default();
    let mut on = ModesDecoder::hex(
        cfg,
        DecodeOptions {
            correct_df17_single_bit: true,
        },
    );
    assert!(matches!(
        decode_slice(&mut on, line.as_bytes())[..],
        [ModesMessage::ModeS(_)]
    ));
    assert_eq!(on.counters().corrected, 1);
    let mut off = ModesDecoder::hex(cfg, DecodeOptions::default());
    assert!(decode_slice(&mut off, line.as_bytes()).is_empty());
    assert_eq!(
        (off.counters().corrected, off.counters().parity_failures),
        (0, 1)
    );
    assert_eq!(off.stats().checksum_failures, 1);
}

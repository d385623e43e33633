//! ASCII tests against every example sentence of the ICD that this crate decodes, with its
//! checksum, plus encoders, checksum styles and round trips.
//!
//! OCR repairs (each checked by the example's own checksum, which then verifies): spaces
//! removed (`$VNBOM, 1*45`), `$VNR.RG` read as `$VNRRG`, `$VNRG,75,...` (A.1.1) as `$VNWRG`,
//! and line-wrapped responses (Registers 15, 27, 59, 63, 64, 72, 73) joined.
//!
//! Document errors found by the checksums: `$VNWRG,5,921600` is printed with `*46` and `*6D`
//! (both copied from the read examples); its XOR is 0x63. Register 32's read example prints
//! SyncOutPulseWidth `10000000` with `*6B`, which verifies only with the default `100000000`.
#![allow(clippy::excessive_precision)] // values transcribed from the ICD

use proptest::prelude::*;

use super::*;
use crate::vn200::binary::{GnssFix, Quaternion, Ypr};
use crate::vn200::status::{InsMode, InsStatus};

/// Scans and parses one framed sentence.
fn decode(s: &str) -> AsciiMessage {
    let line = format!("{s}\r\n");
    match scan(line.as_bytes()) {
        Scan::Sentence { body, len, .. } => {
            assert_eq!(len, line.len());
            let m = AsciiMessage::parse(body).unwrap_or_else(|e| panic!("{s}: {e}"));
            // Every decoded sentence serialises (for `vigil decode`) and re-encodes to a body
            // that parses to the same message.
            serde_json::to_string(&m).unwrap_or_else(|e| panic!("{s}: {e}"));
            assert_eq!(AsciiMessage::parse(&m.body()).as_ref(), Ok(&m), "{s}");
            m
        }
        other => panic!("{s}: {other:?}"),
    }
}

fn read(s: &str) -> RegisterValue {
    match decode(s) {
        AsciiMessage::ReadResponse { value } => value,
        other => panic!("{s}: {other:?}"),
    }
}

fn cmd(s: &str) -> Command {
    match decode(s) {
        AsciiMessage::Command { command } => command,
        other => panic!("{s}: {other:?}"),
    }
}

fn meas(s: &str) -> Measurement {
    match read(s) {
        RegisterValue::Measurement(m) => m,
        other => panic!("{s}: {other:?}"),
    }
}

#[test]
fn command_examples_section_1_3() {
    // Each command encodes to the ICD's bytes and its echo decodes to the same command.
    let cases: Vec<(&str, Command)> = vec![
        ("$VNRRG,11*73", Command::ReadRegister(11)),
        ("$VNRRG,5*46", Command::ReadRegister(5)),
        ("$VNWNV*57", Command::WriteSettings),
        ("$VNRFS*5F", Command::RestoreFactorySettings),
        ("$VNRST*4D", Command::Reset),
        ("$VNFWU*5C", Command::FirmwareUpdate),
        ("$VNKMD,1*47", Command::KnownMagneticDisturbance(true)),
        ("$VNKAD,1*4B", Command::KnownAccelerationDisturbance(true)),
        (
            "$VNSIH,73.2*7E",
            Command::SetInitialHeading(InitialHeading::Heading { heading_deg: 73.2 }),
        ),
        (
            "$VNSIH,73.2,87.1,10.2*73",
            Command::SetInitialHeading(InitialHeading::Ypr(Ypr {
                yaw_deg: 73.2,
                pitch_deg: 87.1,
                roll_deg: 10.2,
            })),
        ),
        (
            "$VNSIH,-0.3574,0.5894,0.3812,0.6161*6A",
            Command::SetInitialHeading(InitialHeading::Quaternion(Quaternion {
                x: -0.3574,
                y: 0.5894,
                z: 0.3812,
                s: 0.6161,
            })),
        ),
        ("$VNASY,1*4E", Command::AsyncOutputEnable(true)),
        ("$VNSFB*4F", Command::SetFilterBias),
        ("$VNBOM,1*45", Command::PollBinaryOutput(1)),
        (
            "$VNWRG,5,921600*63",
            Command::WriteRegister(RegisterValue::BaudRate {
                baud: 921600,
                port: None,
            }),
        ),
    ];
    for (text, command) in cases {
        assert_eq!(
            String::from_utf8(command.encode(ChecksumKind::Xor8)).unwrap(),
            format!("{text}\r\n")
        );
        // The port's codec writes the same bytes.
        let mut dst = bytes::BytesMut::new();
        tokio_util::codec::Encoder::encode(&mut CommandEncoder, command.clone(), &mut dst).unwrap();
        assert_eq!(&dst[..], format!("{text}\r\n").as_bytes());
        assert_eq!(cmd(text), command, "{text}");
    }
    // The response to the read example.
    assert_eq!(
        read("$VNRRG,5,115200*6D"),
        RegisterValue::BaudRate {
            baud: 115200,
            port: None
        }
    );
    // The ICD's printed checksums for the write example are wrong (see the module doc).
    for bad in ["$VNWRG,5,921600*46\r\n", "$VNWRG,5,921600*6D\r\n"] {
        assert_eq!(scan(bad.as_bytes()), Scan::BadChecksum);
    }
    assert!(!Command::PollBinaryOutput(1).is_echoed());
}

#[test]
fn checksum_bypass_and_crc16() {
    assert_eq!(cmd("$VNRRG,1*XX"), Command::ReadRegister(1));
    assert_eq!(
        cmd("$VNWRG,06,1,1*XX"),
        Command::WriteRegister(RegisterValue::AsyncOutputType {
            ador: 1,
            port: Some(1)
        })
    );
    let crc = Command::ReadRegister(1).encode(ChecksumKind::Crc16);
    // CRC-16/XMODEM of "VNRRG,1", computed with the ICD's snippet in crc.rs' tests.
    let expected = format!("$VNRRG,1*{:04X}\r\n", crate::vn200::crc::crc16(b"VNRRG,1"));
    assert_eq!(String::from_utf8(crc.clone()).unwrap(), expected);
    assert!(matches!(
        scan(&crc),
        Scan::Sentence {
            kind: ChecksumKind::Crc16,
            ..
        }
    ));
    let bypass = Command::ReadRegister(1).encode(ChecksumKind::BypassCrc16);
    assert_eq!(bypass, b"$VNRRG,1*XXXX\r\n");
    // Lower-case x, three digits, non-hex: not a checksum.
    for s in [
        "$VNRRG,1*xx\r\n",
        "$VNRRG,1*46A\r\n",
        "$VNRRG,1*G6\r\n",
        "$VNRRG,1\r\n",
    ] {
        assert_eq!(scan(s.as_bytes()), Scan::Invalid, "{s}");
    }
    assert_eq!(scan(b"$VNRRG,1*4"), Scan::NeedMore);
    assert_eq!(scan(b"$VNRRG,1*47\r\n"), Scan::BadChecksum);
    assert_eq!(scan(b"$VNRRG\x01,1*47\r\n"), Scan::Invalid);
    assert_eq!(
        scan(b"$GPGGA,1*00\r\n"),
        Scan::Foreign { len: 13 },
        "foreign sentences are not checked"
    );
}

#[test]
fn a_signed_checksum_is_not_hex_digits() {
    // 1.4: the checksum is two (XOR) or four (CRC) hex digits. Rust's from_str_radix also takes a
    // leading '+', which must not pass for a digit.
    // XOR of "VNRRG,18,V" by hand: the two R, the two commas and the two V cancel, leaving
    // N ^ G ^ '1' ^ '8' = 0x4E ^ 0x47 ^ 0x31 ^ 0x38 = 0x09 ^ 0x09 = 0x00.
    assert!(matches!(
        scan(b"$VNRRG,18,V*00\r\n"),
        Scan::Sentence {
            kind: ChecksumKind::Xor8,
            ..
        }
    ));
    assert_eq!(scan(b"$VNRRG,18,V*+0\r\n"), Scan::Invalid);
    // CRC-16/XMODEM of "VNRRG,285" is 0x0001 (the ICD's snippet of 1.4.3, run apart from this
    // crate).
    assert!(matches!(
        scan(b"$VNRRG,285*0001\r\n"),
        Scan::Sentence {
            kind: ChecksumKind::Crc16,
            ..
        }
    ));
    assert_eq!(scan(b"$VNRRG,285*+001\r\n"), Scan::Invalid);
}

#[test]
fn error_sentences() {
    assert_eq!(
        decode("$VNERR,03*72"),
        AsciiMessage::Error {
            code: ErrorCode::InvalidChecksum
        }
    );
    let e = AsciiMessage::Error {
        code: ErrorCode::InsufficientBaudRate,
    };
    let bytes = e.encode(ChecksumKind::Xor8);
    assert!(bytes.starts_with(b"$VNERR,0C*"));
    let s = String::from_utf8(bytes).unwrap();
    assert_eq!(decode(s.trim_end()), e);
}

#[test]
fn system_register_examples() {
    assert_eq!(
        read("$VNRRG,01,VN-200T-DEV*77"),
        RegisterValue::Model {
            model: "VN-200T-DEV".into()
        }
    );
    assert_eq!(
        read("$VNRRG,02,3*6E"),
        RegisterValue::HardwareVersion { version: 3 }
    );
    assert_eq!(
        read("$VNRRG,03,0100049094*5D"),
        RegisterValue::SerialNumber { serial: 100049094 }
    );
    assert_eq!(
        read("$VNRRG,04,2.1.0.0*76"),
        RegisterValue::FirmwareVersion {
            version: "2.1.0.0".into()
        }
    );
    assert_eq!(
        read("$VNRRG,05,115200*5D"),
        RegisterValue::BaudRate {
            baud: 115200,
            port: None
        }
    );
    assert_eq!(
        read("$VNRRG,06,0*69"),
        RegisterValue::AsyncOutputType {
            ador: 0,
            port: None
        }
    );
    assert_eq!(
        read("$VNRRG,07,10*59"),
        RegisterValue::AsyncOutputFreq {
            rate_hz: 10,
            port: None
        }
    );
    assert_eq!(
        cmd("$VNWRG,07,10*5C"),
        Command::WriteRegister(RegisterValue::AsyncOutputFreq {
            rate_hz: 10,
            port: None
        })
    );
    assert_eq!(
        read("$VNRRG,30,0,0,0,0,1,0,1*6C"),
        RegisterValue::CommProtocol(CommProtocolControl {
            ascii_checksum: 1,
            error_mode: 1,
            ..Default::default()
        })
    );
    assert_eq!(
        read("$VNRRG,32,3,0,0,0,6,1,0,100000000,0*6B"),
        RegisterValue::SyncControl(SyncControl {
            sync_in_mode: 3,
            sync_out_mode: 6,
            sync_out_polarity: 1,
            sync_out_pulse_width_ns: 100_000_000,
            ..Default::default()
        })
    );
    assert!(matches!(
        cmd("$VNWRG,32,5,1,1,0,1,0,1,100000,0*5F"),
        Command::WriteRegister(RegisterValue::SyncControl(SyncControl {
            sync_in_mode: 5,
            sync_out_pulse_width_ns: 100000,
            ..
        }))
    ));
    assert_eq!(
        read("$VNRRG,33,0,1854248756,2329*67"),
        RegisterValue::SyncStatus(SyncStatus {
            sync_in_count: 0,
            sync_in_time_us: 1854248756,
            sync_out_count: 2329
        })
    );
    assert_eq!(
        read("$VNRRG,55,0,0,5,0,1*6B"),
        RegisterValue::GnssBasic(GnssBasicConfig {
            rate_hz: 5,
            resv5: 1,
            ..Default::default()
        })
    );
    assert_eq!(
        read("$VNRRG,57,0,0,0*6D"),
        RegisterValue::GnssAntennaOffset {
            position_m: [0.0; 3]
        }
    );
    assert_eq!(
        cmd("$VNWRG,57,1,1,1*69"),
        Command::WriteRegister(RegisterValue::GnssAntennaOffset {
            position_m: [1.0; 3]
        })
    );
    assert_eq!(
        read("$VNRRG,67,2,1,0,0*71"),
        RegisterValue::InsBasic(InsBasicConfig {
            scenario: 2,
            ahrs_aiding: 1,
            ..Default::default()
        })
    );
    assert_eq!(
        read("$VNRRG,99,0013,10,10,16,02,EBF9,003F,0000*79"),
        RegisterValue::GnssSystem(GnssSystemConfig {
            systems: 0x0013,
            min_cno_db: 10,
            min_elev_deg: 10,
            max_sats: 16,
            sbas_mode: 0x02,
            sbas_select: [0xEBF9, 0x003F, 0x0000],
        })
    );
    assert_eq!(
        read("$VNRRG,101,0,0,0,0,00000000*6F"),
        RegisterValue::NmeaOutput {
            index: 1,
            config: NmeaOutputConfig::default()
        }
    );
    assert_eq!(
        read("$VNRRG,102,0,0,0,0,00000000*6C"),
        RegisterValue::NmeaOutput {
            index: 2,
            config: NmeaOutputConfig::default()
        }
    );
    for (s, index) in [
        ("$VNWRG,101,1,1,0,0,1*5B", 1),
        ("$VNWRG,102,1,1,0,0,1*58", 2),
    ] {
        assert_eq!(
            cmd(s),
            Command::WriteRegister(RegisterValue::NmeaOutput {
                index,
                config: NmeaOutputConfig {
                    port: 1,
                    rate_hz: 1,
                    msg_selection: 1,
                    ..Default::default()
                }
            })
        );
    }
    // An unlisted register keeps its fields.
    assert_eq!(
        read("$VNRRG,47,1,0,0,0,1,0,0,0,1,0,0,0*71"),
        RegisterValue::Other {
            id: 47,
            fields: "1,0,0,0,1,0,0,0,1,0,0,0"
                .split(',')
                .map(String::from)
                .collect()
        }
    );
    assert_eq!(
        read("$VNRRG,00,*5F"),
        RegisterValue::Other {
            id: 0,
            fields: vec![String::new()]
        }
    );
}

#[test]
fn binary_output_register_examples() {
    for (s, index) in [
        ("$VNRRG,75,0,0,00*5D", 1),
        ("$VNRRG,76,0,0,00*5E", 2),
        ("$VNRRG,77,0,0,00*5F", 3),
    ] {
        let RegisterValue::BinaryOutput { index: i, config } = read(s) else {
            panic!("{s}")
        };
        assert_eq!(i, index);
        assert_eq!(config.masks(), Some([0; 7]));
        assert_eq!((config.async_mode, config.rate_divisor), (0, 0));
    }
    for (s, index) in [
        ("$VNWRG,75,1,160,0*6E", 1),
        ("$VNWRG,76,1,160,0*6D", 2),
        ("$VNWRG,77,1,160,0*6C", 3),
    ] {
        let Command::WriteRegister(RegisterValue::BinaryOutput { index: i, config }) = cmd(s)
        else {
            panic!("{s}")
        };
        assert_eq!((i, config.async_mode, config.rate_divisor), (index, 1, 160));
    }
    // A.1.1: 40 Hz on port 1, TimeStartup + Ypr (Common 0009) and YprU (Attitude 0100).
    let c = BinaryOutputConfig::from_masks(1, 20, [0x0009, 0, 0, 0, 0x0100, 0, 0]);
    let w = Command::WriteRegister(RegisterValue::BinaryOutput {
        index: 1,
        config: c.clone(),
    });
    assert_eq!(
        w.encode(ChecksumKind::Xor8),
        b"$VNWRG,75,1,20,11,0009,0100*63\r\n"
    );
    assert_eq!(cmd("$VNWRG,75,1,20,11,0009,0100*63"), w);
    // B.1.1: group bytes 90 10, type words 0100 8001 0002 (group 11 is beyond this ICD).
    let Command::WriteRegister(RegisterValue::BinaryOutput { config, .. }) =
        cmd("$VNWRG,75,1,20,90,10,0100,8001,0002*69")
    else {
        panic!()
    };
    assert_eq!(config.group_bytes, [0x90, 0x10]);
    assert_eq!(config.type_words, [0x0100, 0x8001, 0x0002]);
    assert_eq!(config.masks(), None);
    // GNSS raw measurements (offset 16): type words 8000 0001.
    let c = BinaryOutputConfig::from_masks(1, 160, [0, 0, 0, 1 << 16, 0, 0, 0]);
    assert_eq!(c.type_words, [0x8000, 0x0001]);
    assert_eq!(c.masks(), Some([0, 0, 0, 1 << 16, 0, 0, 0]));
    // By hand: groups 0 and 1 (group byte 03), one word each; group 0 with an extension word
    // (8001 then 0003: types 0 and 16, 17); a zero second group byte is allowed, a group
    // beyond 6 in it is not; a word left over is inconsistent.
    let masks = |groups: &[u8], words: &[u16]| {
        BinaryOutputConfig {
            async_mode: 1,
            rate_divisor: 20,
            group_bytes: groups.to_vec(),
            type_words: words.to_vec(),
        }
        .masks()
    };
    assert_eq!(
        masks(&[0x03], &[0x0001, 0x0002]),
        Some([1, 2, 0, 0, 0, 0, 0])
    );
    assert_eq!(
        masks(&[0x03], &[0x8001, 0x0003, 0x0002]),
        Some([1 | 3 << 16, 2, 0, 0, 0, 0, 0])
    );
    assert_eq!(masks(&[0x81, 0x00], &[0x0001]), Some([1, 0, 0, 0, 0, 0, 0]));
    assert_eq!(masks(&[0x81, 0x01], &[0x0001, 0x0001]), None);
    assert_eq!(masks(&[0x01], &[0x0001, 0x0002]), None);
}

#[test]
fn measurement_register_examples() {
    let Measurement::Ypr(y) = meas("$VNRRG,08,-043.661,+027.314,+003.630*57") else {
        panic!()
    };
    assert_eq!(
        (y.yaw_deg, y.pitch_deg, y.roll_deg),
        (-43.661, 27.314, 3.63)
    );
    let Measurement::Quaternion(q) = meas("$VNRRG,09,+0.116262,+0.207575,-0.368156,+0.898809*79")
    else {
        panic!()
    };
    assert_eq!(q.s, 0.898809);
    let Measurement::QuatMagAccelGyro(v) = meas(
        "$VNRRG,15,+0.116342,+0.207593,-0.368129,+0.898805,+00.1825,+00.6844,+00.8199,+00.231,-00.613,-09.781,-00.000473,-00.001378,-00.000821*68",
    ) else {
        panic!()
    };
    assert_eq!(
        (v.mag_gauss[0], v.accel_mps2[2], v.gyro_radps[2]),
        (0.1825, -9.781, -0.000821)
    );
    assert!(matches!(
        meas("$VNRRG,17,+00.1825,+00.6856,+00.8186*58"),
        Measurement::Mag {
            mag_gauss: [0.1825, 0.6856, 0.8186]
        }
    ));
    assert!(matches!(
        meas("$VNRRG,18,+00.227,-00.604,-09.782*62"),
        Measurement::Accel {
            accel_mps2: [0.227, -0.604, -9.782]
        }
    ));
    assert!(matches!(
        meas("$VNRRG,19,-00.000870,-00.000517,-00.000352*5C"),
        Measurement::Gyro { .. }
    ));
    let Measurement::MagAccelGyro(v) = meas(
        "$VNRRG,20,+00.1864,+00.6832,+00.8199,+00.225,-00.602,-09.750,+00.000210,+00.000101,+00.000701*6A",
    ) else {
        panic!()
    };
    assert_eq!(v.gyro_radps[2], 0.000701);
    let Measurement::YprMagAccelGyro(v) = meas(
        "$VNRRG,27,-043.682,+027.313,+003.621,+00.1838,+00.6821,+00.8213,+00.217,-00.614,-09.789,-00.000944,+00.000167,-00.001173*4B",
    ) else {
        panic!()
    };
    assert_eq!((v.ypr.yaw_deg, v.accel_mps2[2]), (-43.682, -9.789));
    let Measurement::Imu(v) = meas(
        "$VNRRG,54,+00.1852,+00.6821,+00.8213,+00.256,-00.512,-09.593,-00.003840,-00.001172,-00.008491,+30.8,+099.266*50",
    ) else {
        panic!()
    };
    assert_eq!((v.temperature_c, v.pressure_kpa), (30.8, 99.266));
    let Measurement::GnssLla(g) = meas(
        "$VNRRG,58,412149.600017,2255,4,16,+32.89195710,-096.70376510,+00166.071,-000.003,+000.005,-000.001,+001.691,+001.467,+003.168,+000.120,2.00E-09*0E",
    ) else {
        panic!()
    };
    assert_eq!(
        (g.gps_tow_s, g.gps_week, g.fix, g.num_sats),
        (412149.600017, 2255, GnssFix(4), 16)
    );
    assert_eq!(
        (g.lla.lat_deg, g.lla.lon_deg, g.lla.alt_m),
        (32.8919571, -96.7037651, 166.071)
    );
    assert_eq!(g.time_u_s, 2.0e-9);
    let Measurement::GnssEcef(g) = meas(
        "$VNRRG,59,412181.600085,2255,4,16,-0625836.676,-5324476.881,+3443993.363,+000.005,-000.025,-000.001,+001.602,+001.720,+003.332,+000.152,2.00E-09*38",
    ) else {
        panic!()
    };
    assert_eq!(g.pos_ecef_m, [-625836.676, -5324476.881, 3443993.363]);
    let Measurement::InsLla(i) = meas(
        "$VNRRG,63,412213.876136,2255,D085,-043.662,+027.311,+003.617,+32.89195471,-096.70376455,+00166.338,-000.025,+000.029,-000.013,49.53,00.56,0.085*1F",
    ) else {
        panic!()
    };
    // InsStatus D085 (hex): mode 1 Aligning, GnssFix, reserved bits 7, 12, 14, 15 kept.
    assert_eq!(i.ins_status, InsStatus(0xD085));
    assert_eq!(i.ins_status.mode(), InsMode::Aligning);
    assert_eq!((i.att_u_deg, i.pos_u_m, i.vel_u_mps), (49.53, 0.56, 0.085));
    let Measurement::InsEcef(i) = meas(
        "$VNRRG,64,412245.948863,2255,9885,-043.684,+027.304,+003.619,-0625836.775,-5324477.244,+3443993.271,+000.024,-000.026,-000.020,49.71,00.53,0.081*50",
    ) else {
        panic!()
    };
    assert_eq!(i.ins_status, InsStatus(0x9885));
    let Measurement::InsStateLla(s) = meas(
        "$VNRRG,72,-043.677,+027.312,+003.622,+32.89195377,-096.70376441,+00165.563,-000.021,+000.008,-000.004,+00.214,-00.632,-09.776,+00.000265,-00.000066,-00.000169*56",
    ) else {
        panic!()
    };
    assert_eq!(s.lla.alt_m, 165.563);
    let Measurement::InsStateEcef(s) = meas(
        "$VNRRG,73,-043.685,+027.307,+003.620,-625837.01261876,-5324475.55439920,+3443992.576,+000.036,-000.037,-000.026,+00.204,-00.611,-09.811,+00.000983,+00.000605,+00.000106*55",
    ) else {
        panic!()
    };
    assert_eq!(s.pos_ecef_m[0], -625837.01261876);
    let Measurement::DeltaThetaVel {
        theta,
        delta_vel_mps,
    } = meas("$VNRRG,80,+1015.760010,-183.271,-079.636,-510.731,-2581.277,-2649.806,-7913.753*63")
    else {
        panic!()
    };
    assert_eq!(
        (theta.delta_time_s, delta_vel_mps[2]),
        (1015.76001, -7913.753)
    );
    assert!(matches!(
        meas("$VNRRG,115,+00.000,+00.000,+00.000*5F"),
        Measurement::Heave(_)
    ));
    let Measurement::YprLinBodyAccelGyro(v) = meas(
        "$VNRRG,239,-043.704,+027.306,+003.615,-04.282,-00.065,-01.100,+00.000124,+00.000052,-00.000678*57",
    ) else {
        panic!()
    };
    assert_eq!(v.lin_accel_mps2[0], -4.282);
    let Measurement::YprLinNedAccelGyro(v) = meas(
        "$VNRRG,240,-043.668,+027.306,+003.626,-03.101,+02.972,+01.045,-00.000744,+00.000544,+00.000181*53",
    ) else {
        panic!()
    };
    assert_eq!(v.gyro_radps[2], 0.000181);
}

#[test]
fn async_outputs_with_appended_fields() {
    let plain = decode("$VNYPR,+010.071,+000.278,-002.026*60");
    let AsciiMessage::Async(a) = &plain else {
        panic!()
    };
    assert_eq!(
        a.data,
        Measurement::Ypr(Ypr {
            yaw_deg: 10.071,
            pitch_deg: 0.278,
            roll_deg: -2.026
        })
    );
    assert_eq!((a.appended_status, a.appended_count), (None, None));
    let AsciiMessage::Async(a) = decode("$VNYPR,+010.071,+000.278,-002.026,T1162704*2F") else {
        panic!()
    };
    assert_eq!((a.appended_status, a.appended_count), (None, Some(1162704)));
    let AsciiMessage::Async(a) = decode("$VNYPR,+010.071,+000.278,-002.026,S0000*1F") else {
        panic!()
    };
    assert_eq!((a.appended_status, a.appended_count), (Some(0), None));
    let AsciiMessage::Async(a) = decode("$VNYPR,+010.071,+000.278,-002.026,T1162704,S0000*50")
    else {
        panic!()
    };
    assert_eq!(
        (a.appended_status, a.appended_count),
        (Some(0), Some(1162704))
    );
    // Re-encoded in the example's order (count, then status), shortest float format.
    let m = AsciiMessage::Async(a);
    let e = String::from_utf8(m.encode(ChecksumKind::Xor8)).unwrap();
    assert!(
        e.starts_with("$VNYPR,10.071,0.278,-2.026,T1162704,S0000*"),
        "{e}"
    );
    assert_eq!(decode(e.trim_end()), m);
    // Status before count (the ICD's text order) is accepted too.
    let AsciiMessage::Async(b) = AsciiMessage::parse("VNYPR,1,2,3,S00FF,T7").unwrap() else {
        panic!()
    };
    assert_eq!((b.appended_status, b.appended_count), (Some(0xFF), Some(7)));
    // Every async header maps to its register.
    for (h, id) in measurement::MEASUREMENTS {
        let n = match id {
            8 | 17 | 18 | 19 | 115 => 3,
            9 => 4,
            15 => 13,
            20 | 239 | 240 => 9,
            27 => 12,
            54 => 11,
            58 | 59 | 63 | 64 => 15,
            72 | 73 => 15,
            80 => 7,
            _ => unreachable!(),
        };
        let mut fields: Vec<String> = (0..n).map(|k| format!("{}.5", k)).collect();
        if matches!(id, 58 | 59 | 63 | 64) {
            fields[1] = "2255".into();
            fields[2] = if id >= 63 { "D085".into() } else { "3".into() };
            if id < 63 {
                fields[3] = "9".into();
            }
        }
        let body = format!("{h},{}", fields.join(","));
        let m = AsciiMessage::parse(&body).unwrap_or_else(|e| panic!("{h}: {e}"));
        let AsciiMessage::Async(a) = &m else {
            panic!("{h}")
        };
        assert_eq!(a.data.register_id(), id);
        assert_eq!(a.data.async_header(), h);
        assert_eq!(AsciiMessage::parse(&m.body()).unwrap(), m, "{h} round trip");
        // One field short or one too many is malformed.
        assert!(AsciiMessage::parse(&format!("{h},{}", fields[1..].join(","))).is_err());
        assert!(AsciiMessage::parse(&format!("{body},1.0")).is_err());
    }
}

#[test]
fn unknown_and_malformed() {
    assert!(matches!(
        AsciiMessage::parse("VNXYZ,1"),
        Err(AsciiError::UnknownHeader(_))
    ));
    assert!(matches!(
        AsciiMessage::parse("VNKMD,2"),
        Err(AsciiError::Malformed { .. })
    ));
    assert!(matches!(
        AsciiMessage::parse("VNYPR,1,2"),
        Err(AsciiError::Malformed { .. })
    ));
    assert!(matches!(
        AsciiMessage::parse("VNRRG,300"),
        Err(AsciiError::Malformed { .. })
    ));
    assert!(matches!(
        AsciiMessage::parse("VNSIH,1,2"),
        Err(AsciiError::Malformed { .. })
    ));
    assert!(matches!(
        AsciiMessage::parse("VNERR,XYZ"),
        Err(AsciiError::Malformed { .. })
    ));
    // A field more than the sentence holds is refused, not ignored.
    assert!(AsciiMessage::parse("VNERR,03").is_ok());
    // (Register 5 takes an optional serial port after the baud rate.)
    for extra in ["VNERR,03,1", "VNRRG,5,115200,1,2"] {
        assert!(
            matches!(
                AsciiMessage::parse(extra),
                Err(AsciiError::Malformed { .. })
            ),
            "{extra}"
        );
    }
    assert!(AsciiMessage::parse("VNRRG,5,115200").is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// decode(encode(x)) == x for commands with finite floats and for register writes.
    #[test]
    fn prop_command_round_trip(
        a in -1.0e6f32..1.0e6, b in -1.0e3f32..1.0e3, c in any::<u32>(), d in any::<u16>(),
        k in 0usize..8, kind in 0usize..4,
    ) {
        let kinds = [ChecksumKind::Xor8, ChecksumKind::Crc16, ChecksumKind::BypassXor8, ChecksumKind::BypassCrc16];
        let command = match k {
            0 => Command::SetInitialHeading(InitialHeading::Heading { heading_deg: a }),
            1 => Command::SetInitialHeading(InitialHeading::Ypr(Ypr { yaw_deg: a, pitch_deg: b, roll_deg: -b })),
            2 => Command::WriteRegister(RegisterValue::BaudRate { baud: c, port: Some(2) }),
            3 => Command::WriteRegister(RegisterValue::BinaryOutput {
                index: 2,
                config: BinaryOutputConfig::from_masks(3, d, [u32::from(d) | 1, 0, 0, u32::from(d) << 16 | 1, 0, 0, 0]),
            }),
            4 => Command::WriteRegister(RegisterValue::GnssAntennaOffset { position_m: [a, b, 0.25] }),
            5 => Command::WriteRegister(RegisterValue::Measurement(Measurement::InsLla(InsSolutionLla {
                gps_tow_s: f64::from(a), gps_week: d, ins_status: InsStatus(d), ypr: Ypr { yaw_deg: b, ..Default::default() },
                ..Default::default()
            }))),
            6 => Command::WriteRegister(RegisterValue::GnssSystem(GnssSystemConfig { systems: d, sbas_select: [d, 1, 2], ..Default::default() })),
            _ => Command::ReadRegister(c as u8),
        };
        let bytes = command.encode(kinds[kind]);
        let Scan::Sentence { body, len, .. } = scan(&bytes) else { panic!("{bytes:?}") };
        prop_assert_eq!(len, bytes.len());
        prop_assert!(serde_json::to_string(&command).is_ok());
        prop_assert_eq!(AsciiMessage::parse(body).unwrap(), AsciiMessage::Command { command });
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// decode(encode(x)) == x for every measurement register, as async output and as a read
    /// response, with finite values.
    #[test]
    fn prop_measurement_round_trip(
        v in proptest::collection::vec(-1.0e5f32..1.0e5, 15),
        d in -1.0e6f64..1.0e6, w in any::<u16>(), k in 0usize..19, count in any::<u32>(),
    ) {
        let id = measurement::MEASUREMENTS[k].1;
        // Build the register's fields from the random values, then parse them as the message.
        let mut fields = Vec::new();
        for (i, x) in v.iter().enumerate() {
            fields.push(match (id, i) {
                (58 | 59 | 63 | 64, 0) => d.to_string(),
                (58 | 59 | 63 | 64, 1) => w.to_string(),
                (58 | 59, 2 | 3) => (w % 256).to_string(),
                (63 | 64, 2) => format!("{w:04X}"),
                _ => x.to_string(),
            });
        }
        let n = match id {
            8 | 17 | 18 | 19 | 115 => 3,
            9 => 4,
            15 => 13,
            20 | 239 | 240 => 9,
            27 => 12,
            54 => 11,
            80 => 7,
            _ => 15,
        };
        let body = format!("VNRRG,{id},{}", fields[..n].join(","));
        let m = AsciiMessage::parse(&body).unwrap();
        let AsciiMessage::ReadResponse { value: RegisterValue::Measurement(meas) } = m.clone() else {
            panic!("{body}")
        };
        prop_assert_eq!(AsciiMessage::parse(&m.body()).unwrap(), m);
        let a = AsciiMessage::Async(AsyncOutput { data: meas, appended_status: Some(w), appended_count: Some(count) });
        for kind in [ChecksumKind::Xor8, ChecksumKind::Crc16] {
            let bytes = a.encode(kind);
            let Scan::Sentence { body, .. } = scan(&bytes) else { panic!() };
            prop_assert_eq!(AsciiMessage::parse(body).unwrap(), a.clone());
        }
    }
}

/// Every other register example of the ICD (registers vigil does not type): the checksum
/// verifies and the contents are kept as fields. `$VNRWG,44,...` (a misprint of VNWRG, with a
/// bypassed checksum) is not a command and is refused as unknown.
#[test]
fn remaining_register_examples_verify() {
    let reads = [
        "$VNRRG,206,0,0,0,0*47",
        "$VNRRG,21,0.231839,0.0121824,0.426962,1.1364E-05,3.94035E-05,-9.79498*65",
        "$VNRRG,35,1,1,1,1*75",
        "$VNRRG,36,4,4,4,5,5,5,5.5,5.5,5.5*75",
        "$VNRRG,38,6,6,6,3,3,3,5,5,5*64",
        "$VNRRG,23,1,0,0,0,1,0,0,0,1,0,0,0*73",
        "$VNRRG,25,1,0,0,0,1,0,0,0,1,0,0,0*75",
        "$VNRRG,26,1,0,0,0,1,0,0,0,1*6A",
        "$VNRRG,82,0,0,0,0,0*65",
        "$VNRRG,84,1,0,0,0,1,0,0,0,1,0,0,0*7E",
        "$VNRRG,85,0,4,4,4,0,0,3,3,3,0*79",
        "$VNRRG,44,0,1,5*6B",
        "$VNRRG,50,0,0,0*6A",
        "$VNRRG,51,1,0.1,0.01*5A",
        "$VNRRG,157,0,0,0*5C",
        "$VNRRG,105,+00.000,+00.000,+00.000,00.0000,00.0000,00.0000*5C",
        "$VNRRG,144,05,2,5,00,0,0*40",
        "$VNRRG,83,1,1,0,0,1000,0.000,+00.00000000,+000.00000000,+00000.000*4E",
        "$VNRRG,116,0,0.05,20,0.05,0.08,0,0*4D",
    ];
    for r in reads {
        let id: u8 = r[7..].split(',').next().unwrap().parse().unwrap();
        let RegisterValue::Other { id: got, fields } = read(r) else {
            panic!("{r}")
        };
        assert_eq!(got, id);
        assert_eq!(fields.len(), r.split(',').count() - 2, "{r}");
    }
    let writes = [
        "$VNWRG,00,ABCDEF123*6D",
        "$VNWRG,206,1,1,1,1*42",
        "$VNWRG,35,0,0,0,0*70",
        "$VNWRG,36,4,3,2,4,3,2,4,3,2*6A",
        "$VNWRG,38,4,3,2,4,3,2,4,3,2*64",
        "$VNWRG,23,0.71,0.011,0.012,0.013,0.72,0.014,0.015,0.016,0.73,0.1,0.2,0.3*47",
        "$VNWRG,25,0.71,0.011,0.012,0.013,0.72,0.014,0.015,0.016,0.73,0.1,0.2,0.3*41",
        "$VNWRG,26,1,0,0,0,-1,0,0,0,-1*6F",
        "$VNWRG,82,1,1,1,0,0*61",
        "$VNWRG,84,0.71,0.011,0.012,0.013,0.72,0.014,0.015,0.016,0.73,0.1,0.2,0.3*4A",
        "$VNWRG,85,4,0,0,0,4,0,0,0,0,0*7B",
        "$VNWRG,50,1,2,3*6F",
        "$VNWRG,157,1,1,1*58",
        "$VNWRG,83,0,0,0,0,10,2014,30,-94,100*45",
        "$VNWRG,21,0.234,0,0.4212,0,0,-9.79375*XX",
        "$VNWRG,30,0,0,0,0,1,3,1*XX",
        "$VNWRG,55,0,0,5,0,1*XX",
        "$VNWRG,67,2,1,0,0*XX",
        "$VNWRG,99,0013,10,10,16,02,EBF9,003F,0000*XX",
    ];
    for w in writes {
        assert!(matches!(cmd(w), Command::WriteRegister(_)), "{w}");
    }
    assert!(matches!(
        AsciiMessage::parse("VNRWG,44,1,1,5"),
        Err(AsciiError::UnknownHeader(_))
    ));
}

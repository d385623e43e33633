//! The configuration client against scripted sensor answers.

use std::time::Duration;

use bytes::BytesMut;

use super::*;
use crate::DeviceDecoder;
use crate::vn200::decoder::Vn200Decoder;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// Feeds sensor bytes through the stream decoder into the client.
fn feed(client: &mut ConfigClient, bytes: &[u8], now: Duration) -> usize {
    let mut d = Vn200Decoder::new();
    let mut buf = BytesMut::from(bytes);
    let mut answered = 0;
    while let Some(m) = d.decode(&mut buf) {
        answered += usize::from(client.handle_message(&m, now));
    }
    answered
}

#[test]
fn writes_binary_outputs_and_matches_echoes() {
    let mut c = ConfigClient::new(ms(500), 3);
    // Output 1: the A.1.1 example (Common 0009 + Attitude 0100, 40 Hz on port 1).
    c.configure_binary_output(1, 1, 20, [0x0009, 0, 0, 0, 0x0100, 0, 0])
        .unwrap();
    // Output 2: GNSS raw measurements at 5 Hz (offset 16: words 8000 0001).
    c.configure_binary_output(2, 1, 160, [0, 0, 0, 1 << 16, 0, 0, 0])
        .unwrap();
    assert_eq!(
        c.configure_binary_output(4, 1, 1, [1, 0, 0, 0, 0, 0, 0]),
        Err(ClientError::BadIndex(4))
    );

    let first = c.poll_transmit(ms(0)).unwrap();
    assert_eq!(first, b"$VNWRG,75,1,20,11,0009,0100*63\r\n");
    // Nothing more until answered or timed out.
    assert_eq!(c.poll_transmit(ms(100)), None);
    assert_eq!(c.poll_timeout(), Some(ms(500)));
    // The sensor echoes, with a binary message and an async sentence around it.
    let mut answer = vec![
        0xFA, 0x01, 0x08, 0x00, 0x93, 0x50, 0x2E, 0x42, 0x83, 0x3E, 0xF1, 0x3F, 0x48, 0xB5, 0x04,
        0xBB, 0x92, 0x88,
    ];
    answer.extend_from_slice(b"$VNYPR,+010.071,+000.278,-002.026*60\r\n");
    answer.extend_from_slice(&first);
    assert_eq!(feed(&mut c, &answer, ms(120)), 1);

    let second = c.poll_transmit(ms(130)).unwrap();
    let second_text = String::from_utf8(second.clone()).unwrap();
    assert!(
        second_text.starts_with("$VNWRG,76,1,160,08,8000,0001*"),
        "{second_text}"
    );
    // The sensor answers with an error (hex code 0C: insufficient baud rate).
    assert_eq!(
        feed(&mut c, b"$VNERR,0C*72\r\n", ms(140)),
        0,
        "checksum of the script is wrong: not an answer"
    );
    let err = crate::vn200::ascii::AsciiMessage::Error {
        code: ErrorCode::InsufficientBaudRate,
    }
    .encode(ChecksumKind::Xor8);
    assert_eq!(feed(&mut c, &err, ms(150)), 1);
    assert!(c.is_done());
    assert_eq!(c.report().len(), 2);
    assert_eq!(
        c.report()[0].outcome,
        Outcome::Accepted { echo_matches: true }
    );
    assert_eq!(c.report()[0].attempts, 1);
    assert_eq!(
        c.report()[1].outcome,
        Outcome::Rejected {
            code: ErrorCode::InsufficientBaudRate
        }
    );
    assert!(!c.all_accepted());
}

#[test]
fn retries_on_timeout_then_gives_up() {
    let mut c = ConfigClient::new(ms(200), 2);
    c.push(Command::WriteSettings).unwrap();
    c.push(Command::ReadRegister(5)).unwrap();
    assert_eq!(c.poll_transmit(ms(0)).unwrap(), b"$VNWNV*57\r\n");
    assert_eq!(c.poll_transmit(ms(199)), None);
    // Timeout: sent again.
    assert_eq!(c.poll_transmit(ms(200)).unwrap(), b"$VNWNV*57\r\n");
    // Second timeout with max 2 attempts: recorded as timed out, the next command goes out.
    assert_eq!(c.poll_transmit(ms(400)).unwrap(), b"$VNRRG,5*46\r\n");
    assert_eq!(c.report()[0].outcome, Outcome::TimedOut);
    assert_eq!(c.report()[0].attempts, 2);
    // A late echo of the first command does not answer the read.
    assert_eq!(feed(&mut c, b"$VNWNV*57\r\n", ms(410)), 0);
    // The read's response answers it.
    assert_eq!(feed(&mut c, b"$VNRRG,5,115200*6D\r\n", ms(420)), 1);
    assert_eq!(
        c.report()[1].outcome,
        Outcome::Accepted { echo_matches: true }
    );
    assert!(c.is_done());
    assert_eq!(c.poll_transmit(ms(1000)), None);
}

#[test]
fn echo_of_a_different_value_is_reported() {
    let mut c = ConfigClient::new(ms(200), 1);
    c.push(Command::WriteRegister(RegisterValue::BaudRate {
        baud: 921600,
        port: None,
    }))
    .unwrap();
    let _ = c.poll_transmit(ms(0)).unwrap();
    // Echo of another register: ignored. Echo of register 5 with another value: reported.
    assert_eq!(feed(&mut c, b"$VNWRG,07,10*5C\r\n", ms(10)), 0);
    let echo = Command::WriteRegister(RegisterValue::BaudRate {
        baud: 115200,
        port: None,
    })
    .encode(ChecksumKind::Xor8);
    assert_eq!(feed(&mut c, &echo, ms(20)), 1);
    assert_eq!(
        c.report()[0].outcome,
        Outcome::Accepted {
            echo_matches: false
        }
    );
    assert!(c.push(Command::PollBinaryOutput(1)).is_err());
}

#[test]
fn setup_session_runs_in_order_against_an_echoing_sensor() {
    let outputs = [
        (1u8, 1u16, 4u16, [0x51FA, 0, 0, 0, 0, 0, 0]),
        (2, 1, 160, [0, 0, 0, 1 << 16 | 1 << 17, 0, 0, 0]),
    ];
    let mut c = ConfigClient::setup_session(ms(300), 3, &outputs, true).unwrap();
    let mut sent = Vec::new();
    let mut now = ms(0);
    // A scripted sensor that echoes every command it receives, 5 ms later; it drops the first
    // copy of the WriteSettings command (a lost byte), so that one is retried.
    let mut dropped = false;
    while !c.is_done() {
        match c.poll_transmit(now) {
            Some(cmd) => {
                sent.push(String::from_utf8(cmd.clone()).unwrap());
                if cmd.starts_with(b"$VNWNV") && !dropped {
                    dropped = true;
                } else {
                    now += ms(5);
                    assert_eq!(feed(&mut c, &cmd, now), 1);
                }
            }
            None => now = c.poll_timeout().unwrap(),
        }
    }
    assert_eq!(
        sent.iter().map(|s| &s[..6]).collect::<Vec<_>>(),
        ["$VNASY", "$VNWRG", "$VNWRG", "$VNWNV", "$VNWNV", "$VNASY"]
    );
    assert!(sent[1].starts_with("$VNWRG,75,1,4,01,51FA*"));
    assert!(sent[2].starts_with("$VNWRG,76,1,160,08,8000,0003*"));
    assert_eq!(c.report().len(), 5);
    assert!(c.all_accepted());
    assert_eq!(c.report()[3].attempts, 2);
}

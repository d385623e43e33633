//! The VN-200 and TT-Multi-RF models answer commands written to their live pseudo-terminals
//! through tokio-serial (the simulator's `Sink::host_input` path), decoded by the drivers.

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_serial::SerialPortBuilderExt;
use vigil_drivers::decode_slice;
use vigil_drivers::ttmrf::at::AtResponse;
use vigil_drivers::ttmrf::text::{TextDecoder, TextMessage, TextMode};
use vigil_drivers::vn200::ascii::{AsciiMessage, ErrorCode, RegisterValue};
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};

/// Opens `path`, writes `command` after 300 ms, reads for `d`.
async fn talk(path: String, baud: u32, command: &'static [u8], d: Duration) -> Vec<u8> {
    let mut port = tokio_serial::new(&path, baud)
        .open_native_async()
        .expect("open pty with tokio-serial");
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    let write_at = tokio::time::Instant::now() + Duration::from_millis(300);
    let deadline = tokio::time::Instant::now() + d;
    let mut written = false;
    loop {
        let until = if written { deadline } else { write_at };
        match tokio::time::timeout_at(until, port.read(&mut buf)).await {
            Ok(Ok(0)) => break,
            Ok(Ok(n)) => out.extend_from_slice(&buf[..n]),
            Ok(Err(e)) => panic!("read {path}: {e}"),
            Err(_) if !written => {
                port.write_all(command).await.expect("write to the pty");
                written = true;
            }
            Err(_) => break,
        }
    }
    out
}

#[test]
fn vn200_and_ttmrf_answer_commands_on_live_ports() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_pty_commands");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args([
            "sim",
            "--scenario",
            "headon",
            "--duration",
            "4",
            "--seed",
            "5",
        ])
        .arg("--pty-dir")
        .arg(&dir)
        .stdout(Stdio::piped())
        .spawn()
        .expect("start vigil sim");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let ports: Vec<(String, String, u32)> = (0..4)
        .map(|_| {
            let l = lines.next().expect("port line").unwrap();
            let f: Vec<&str> = l.split(' ').collect();
            (f[0].into(), f[1].into(), f[2].parse().unwrap())
        })
        .collect();
    let port = |name: &str| ports.iter().find(|p| p.0 == name).unwrap().clone();
    let (vn, tt) = (port("vn200"), port("ttmrf"));
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let (v, t) = rt.block_on(async {
        tokio::join!(
            talk(
                vn.1,
                vn.2,
                b"$VNRRG,75*XX\r\n$VNRRG,99*XX\r\n",
                Duration::from_millis(1500)
            ),
            talk(tt.1, tt.2, b"AT+CONFIG=1\r\n", Duration::from_millis(1500)),
        )
    });
    assert!(child.wait().unwrap().success());
    let msgs = decode_slice(&mut Vn200Decoder::new(), &v);
    let ascii: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            Vn200Message::Ascii(a) => Some(a),
            _ => None,
        })
        .collect();
    assert!(
        matches!(
            ascii.first(),
            Some(AsciiMessage::ReadResponse {
                value: RegisterValue::BinaryOutput { index: 1, .. }
            })
        ),
        "{ascii:?}"
    );
    // Register 99 (GNSS system configuration) is not modelled: InvalidRegister.
    assert_eq!(
        ascii.get(1),
        Some(&&AsciiMessage::Error {
            code: ErrorCode::InvalidRegister
        })
    );
    // 200 Hz binary output around the answers.
    assert!(msgs.len() > 150, "{} vn200 messages", msgs.len());
    // The TT-Multi-RF acknowledges and enters CONFIGURATION.
    let text = decode_slice(&mut TextDecoder::new(TextMode::Auto), &t);
    let at: Vec<_> = text
        .iter()
        .filter_map(|m| match m {
            TextMessage::At(a) => Some(a),
            _ => None,
        })
        .collect();
    assert!(matches!(at.first(), Some(AtResponse::Ok)), "{at:?}");
    assert!(at.iter().any(|a| matches!(a, AtResponse::State { .. })));
}

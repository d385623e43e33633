//! Issue 26: `vigil demo --gdl90-out` sends GDL90 over UDP; a socket here receives it and vigil's
//! own GDL90 decoder reads every datagram (the byte-level check against the ICD's tables is in
//! `service::gdl90_out`'s unit tests).

use std::net::UdpSocket;
use std::process::{Command, Stdio};
use std::time::Duration;

use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, Gdl90Message, TrafficAltitude};
use vigil_drivers::{DeviceDecoder, decode_slice};

#[test]
fn a_demo_sends_heartbeats_ownship_and_the_head_on_intruder() {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket
        .set_read_timeout(Some(Duration::from_millis(200)))
        .unwrap();
    let port = socket.local_addr().unwrap().port();
    let mut demo = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["demo", "--duration", "15", "--seed", "1"])
        .args(["--gdl90-out", &format!("127.0.0.1:{port}")])
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut datagrams = Vec::new();
    let mut buf = [0u8; 2048];
    loop {
        match socket.recv(&mut buf) {
            Ok(n) => datagrams.push(buf[..n].to_vec()),
            Err(_) => {
                if demo.try_wait().unwrap().is_some() {
                    break;
                }
            }
        }
    }
    assert!(demo.wait().unwrap().success());
    let mut dec = Gdl90Decoder::new(TrafficAltitude::Pressure);
    let (mut heartbeats, mut ownship, mut headon) = (0, 0, 0);
    for d in &datagrams {
        let msgs = decode_slice(&mut dec, d);
        assert_eq!(msgs.len(), 1, "one message per datagram");
        match &msgs[0] {
            Gdl90Message::Heartbeat(h) => {
                heartbeats += 1;
                assert!(h.utc_ok && h.timestamp_s < 86_400);
            }
            Gdl90Message::OwnshipReport(_) => ownship += 1,
            Gdl90Message::TrafficReport(r) if r.address == 0x4B1A09 => {
                headon += 1;
                assert_eq!(r.callsign_str().as_deref(), Some("HEADON9"));
            }
            _ => {}
        }
    }
    assert_eq!(dec.stats().checksum_failures, 0);
    // About one a second of the 15 s, less the start (clock lock, first picture); a loaded CI
    // machine may start later, hence the margin.
    assert!((5..=17).contains(&heartbeats), "{heartbeats} heartbeats");
    assert!(ownship >= 5, "{ownship} ownship reports");
    assert!(
        headon >= 5 && headon <= heartbeats,
        "{headon} head-on reports"
    );
}

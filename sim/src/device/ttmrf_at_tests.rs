//! AT settings switch the model's output protocol (manual 4.1.3, 5.1.1, 5.1.8): a write of
//! `ADSB_RX_PROTOCOL_DECODED` in CONFIGURATION changes what the module sends once back in RUN,
//! driven by raw AT lines and by the drivers' [`ConfigClient`].

use std::time::Duration;

use vigil_drivers::decode_slice;
use vigil_drivers::ttmrf::at::{
    ClientConfig, ConfigClient, DecodedProtocol, Output, Setting, SettingId,
};
use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, Gdl90Message};
use vigil_drivers::ttmrf::mavlink::MavlinkDecoder;

use super::*;
use crate::engine::{RunInfo, Sink, SinkError};
use crate::link::Chunk;

fn headon_json() -> crate::Scenario {
    let mut s = builtin("headon").unwrap();
    let t = s.devices.ttmrf.as_mut().unwrap();
    t.protocol = "json".into();
    t.raw = "off".into();
    s
}

fn protocol(r: &TruthRecord) -> Option<&str> {
    r.values.get("protocol").and_then(|v| v.as_str())
}

#[test]
fn raw_at_lines_switch_json_to_mavlink() {
    // 0.5 s: CONFIGURATION; 1.0 s: MAVLink (manual table 12: 2) and read it back; 1.5 s: RUN.
    let script = vec![
        (5, b"AT+CONFIG=1\r\n".to_vec()),
        (10, b"AT+ADSB_RX_PROTOCOL_DECODED=2\r\n".to_vec()),
        (11, b"AT+ADSB_RX_PROTOCOL_DECODED?\r\n".to_vec()),
        (15, b"AT+CONFIG=0\r\n".to_vec()),
    ];
    let (sink, bytes, truth) = run(&headon_json(), 4_000_000_000, script);
    let start = sink.info.unwrap().start_gps_ns;
    let traffic: Vec<_> = truth.iter().filter(|r| protocol(r).is_some()).collect();
    let back_in_run = 1_501 * MS;
    for r in &traffic {
        let dt = r.t_gps_ns - start;
        assert!(!(501 * MS..back_in_run).contains(&dt), "{dt}");
        let want = if dt < back_in_run { "json" } else { "mavlink" };
        assert_eq!(protocol(r), Some(want), "{dt}");
    }
    let mavlink = traffic
        .iter()
        .filter(|r| protocol(r) == Some("mavlink"))
        .count();
    // One intruder in headon, 2.5 s of RUN after the switch.
    assert!(mavlink >= 2, "{mavlink}");
    // The port: the MAVLink frames decode where the truth has them; the JSON before them and
    // the AT answers (including the value read back) decode as text.
    let frames = decode_slice(&mut MavlinkDecoder::new(), &bytes);
    assert_eq!(frames.len(), mavlink);
    for (f, r) in frames
        .iter()
        .zip(traffic.iter().filter(|r| protocol(r) == Some("mavlink")))
    {
        let v = f.to_traffic().unwrap();
        assert_eq!(v.address_hex(), r.values["address"].as_str().unwrap());
    }
    let text = decode_slice(&mut TextDecoder::new(TextMode::Auto), &bytes);
    let json = text
        .iter()
        .filter(|m| matches!(m, TextMessage::Json(_)))
        .count();
    let json_truth = truth
        .iter()
        .filter(|r| protocol(r) == Some("json") || r.kind == "gnss")
        .count();
    assert_eq!(json, json_truth);
    assert!(text.iter().any(|m| matches!(
        m,
        TextMessage::At(AtResponse::Value { name, value })
            if name == "ADSB_RX_PROTOCOL_DECODED" && value == "2"
    )));
    // No GNSS section after the switch: MAVLink has none.
    assert!(
        truth
            .iter()
            .filter(|r| r.kind == "gnss")
            .all(|r| r.t_gps_ns - start < back_in_run)
    );
}

/// A host running the drivers' configuration client on the TT-Multi-RF port: received chunks go
/// to the client, its writes to the module; `now` is the host receive time of the last chunk.
///
/// The model's port has no baud (a pseudo-terminal), while the client drops what it buffered
/// when it switches baud (at `AT+RUN_END` / `AT+CONFIG_END`: the next state message comes at
/// the other baud). So the host hands the client one line at a time, as a host that applies
/// each baud switch before reading on would see them.
struct ClientHost {
    inner: MemorySink,
    client: ConfigClient,
    port: u16,
    now: Duration,
    /// Host time of the first chunk.
    first: Option<Duration>,
    /// Start the client this long after the first chunk.
    delay: Duration,
    started: bool,
    result: Option<Result<vigil_drivers::ttmrf::at::ConfigReport, String>>,
    finished_at: Option<u64>,
    pending: Vec<u8>,
}

impl ClientHost {
    fn drain(&mut self) {
        while let Some(o) = self.client.poll_output() {
            match o {
                Output::Send(b) => self.pending.extend(b),
                // A pseudo-terminal has no baud: the model accepts what the host sends.
                Output::SetBaud(_) => {}
                Output::Finished(r) => {
                    self.result = Some(r.map_err(|e| format!("{e:?}")));
                    self.finished_at = Some(self.now.as_nanos() as u64);
                }
            }
        }
    }
}

impl Sink for ClientHost {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        self.port = info.ports.iter().position(|p| p.device == "ttmrf").unwrap() as u16;
        self.inner.start(info)
    }
    fn chunk(&mut self, c: &Chunk) -> Result<(), SinkError> {
        self.now = Duration::from_nanos(c.t_host_ns);
        self.first.get_or_insert(self.now);
        if c.port == self.port && self.started && self.result.is_none() {
            for line in c.bytes.split_inclusive(|&b| b == b'\n') {
                self.client.handle_bytes(line, self.now);
                self.drain();
            }
        }
        self.inner.chunk(c)
    }
    fn truth(&mut self, r: &TruthRecord, t: u64) -> Result<(), SinkError> {
        self.inner.truth(r, t)
    }
    fn host_input(&mut self) -> Vec<(u16, Vec<u8>)> {
        if !self.started && self.first.is_some_and(|f| self.now >= f + self.delay) {
            self.started = true;
            self.client.start(self.now);
        }
        if self.started && self.result.is_none() {
            if self.client.poll_timeout().is_some_and(|d| d <= self.now) {
                self.client.handle_timeout(self.now);
            }
            self.drain();
        }
        let out = std::mem::take(&mut self.pending);
        if out.is_empty() {
            Vec::new()
        } else {
            vec![(self.port, out)]
        }
    }
}

#[test]
fn config_client_switches_json_to_gdl90() {
    let s = headon_json();
    let mut sim = Simulator::new(&s, 3).unwrap();
    let wanted = vec![Setting::adsb_decoded(DecodedProtocol::Gdl90)];
    let mut host = ClientHost {
        inner: MemorySink::default(),
        client: ConfigClient::new(wanted, ClientConfig::default()),
        port: 0,
        now: Duration::ZERO,
        first: None,
        // 0.5 s into the run.
        delay: Duration::from_millis(500),
        started: false,
        result: None,
        finished_at: None,
        pending: Vec::new(),
    };
    sim.run(8_000_000_000, &mut host).unwrap();
    let report = host.result.clone().expect("the cycle ends").unwrap();
    // Found JSON (3), wrote GDL90 (4) and read it back.
    assert_eq!(
        report.found,
        vec![(SettingId::AdsbRxProtocolDecoded, Some("3".into()))]
    );
    assert_eq!(report.changed.len(), 1);
    assert_eq!(report.changed[0].to, 4);
    assert!(report.run_confirmed);
    // After the cycle the module sends GDL90: the heartbeat and the head-on intruder's Traffic
    // Reports, decoded from the bytes received after the client finished.
    let finished = host.finished_at.unwrap();
    let port = host.port;
    let after: Vec<u8> = host
        .inner
        .chunks
        .iter()
        .filter(|c| c.port == port && c.t_host_ns > finished)
        .flat_map(|c| c.bytes.clone())
        .collect();
    let msgs = decode_slice(&mut Gdl90Decoder::default(), &after);
    let heartbeats = msgs
        .iter()
        .filter(|m| matches!(m, Gdl90Message::Heartbeat(_)))
        .count();
    let traffic = msgs
        .iter()
        .filter(|m| matches!(m, Gdl90Message::TrafficReport(_)))
        .count();
    assert!(heartbeats >= 2 && traffic >= 2, "{heartbeats} {traffic}");
    let truth: Vec<_> = host
        .inner
        .truth
        .iter()
        .filter(|r| r.device == "ttmrf" && r.kind.starts_with("gdl90_"))
        .collect();
    assert_eq!(truth.len(), 3 * heartbeats);
}

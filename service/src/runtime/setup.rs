//! Device set-up at start (issue 10: "configures the VN-200 binary outputs and the TT-Multi-RF
//! protocols when asked to"): the drivers' sans-IO configuration clients driven over the port
//! right after it opens, before the port's bytes go to the service only.
//!
//! - VN-200 ([`vigil_drivers::vn200::client::ConfigClient`], ICD 1.3, Registers 75-77): one
//!   session pausing the asynchronous outputs, writing binary output 1 (Register 75) with
//!   [`VN200_MASKS`] at the configured rate, and resuming them. Not saved to flash (the write is
//!   repeated at every start and every reopening).
//! - TT-Multi-RF ([`vigil_drivers::ttmrf::at::ConfigClient`], manual 4-5): the decoded protocol
//!   of ADS-B, UAT and FLARM set to the configured text protocol, UAT decoded output on, and the
//!   GNSS NMEA output on or off. The client reads each setting first and writes only what
//!   differs; the module saves the settings itself on leaving CONFIGURATION.
//!
//! Every byte read during a session is also handed on (`forward`), so the service and the
//! recording see the whole stream. A session that fails or times out is logged and the port is
//! used as it is: a configuration problem never stops the service.
//!
//! Decision: only the text decoded protocols (CSV, JSON) are offered for the TT-Multi-RF, because
//! the live path decodes its port as text plus raw HEX (`Ingest`'s own port); the binary
//! protocols (MAVLink, GDL90, ASTERIX) share the UART with no framing the text decoder skips.

use std::time::Duration;

use bytes::BytesMut;
use serde::{Deserialize, Serialize};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_serial::{SerialPort, SerialStream};
use tokio_util::codec::Decoder as _;
use tracing::{info, warn};
use vigil_drivers::Codec;
use vigil_drivers::ttmrf::at::{
    self, ClientConfig, DecodedProtocol, Output, Setting, settings::UatMode,
};
use vigil_drivers::vn200::Vn200Decoder;
use vigil_drivers::vn200::client::ConfigClient as Vn200Client;

/// Register 75 type masks written to the VN-200, indexed by binary group offset: Common TimeGps,
/// Ypr, Quaternion, AngularRate, PosLla, VelNed, Accel, InsStatus, TimeGpsPps; Time TimeStatus;
/// Attitude YprU; INS PosU, VelU: what the time alignment (TimeGps, TimeStatus, TimeGpsPps),
/// the attitude cross-check (Ypr, YprU, InsStatus) and the ownship (PosLla, VelNed, PosU, VelU)
/// read. The simulator's VN-200 model starts with the same outputs (a test ties the two).
pub const VN200_MASKS: [u32; 7] = [
    1 << 1 | 1 << 3 | 1 << 4 | 1 << 5 | 1 << 6 | 1 << 7 | 1 << 8 | 1 << 12 | 1 << 14,
    1 << 9,
    0,
    0,
    1 << 8,
    1 << 9 | 1 << 10,
    0,
];

/// The VN-200's IMU rate, Hz: output rates are `800 / rate_divisor`.
pub const VN200_IMU_HZ: u32 = 800;

/// Longest set-up session, s (the TT-Multi-RF cycle with retries stays well below).
const SESSION_LIMIT: Duration = Duration::from_secs(30);

/// Text protocol of the TT-Multi-RF decoded outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TtText {
    /// JSON (time stamps and the GNSS section included).
    #[default]
    Json,
    /// CSV.
    Csv,
}

/// What to set up on one port.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Setup {
    /// VN-200 binary output 1 at `rate_divisor` (800 Hz / divisor).
    Vn200 {
        /// IMU ticks per output.
        rate_divisor: u16,
    },
    /// TT-Multi-RF decoded protocol and NMEA.
    Ttmrf {
        /// Decoded protocol of ADS-B, UAT and FLARM.
        decoded: TtText,
        /// GNSS NMEA output on.
        gnss_nmea: bool,
        /// The port's RUN baud.
        run_baud: u32,
    },
}

/// The TT-Multi-RF settings of a [`Setup::Ttmrf`].
pub fn ttmrf_settings(decoded: TtText, gnss_nmea: bool) -> Vec<Setting> {
    let p = match decoded {
        TtText::Json => DecodedProtocol::Json,
        TtText::Csv => DecodedProtocol::Csv,
    };
    let mut s = vec![
        Setting::adsb_decoded(p),
        Setting::uat_mode(UatMode::DecodedOnly),
    ];
    // CSV and JSON are in the UAT and FLARM subsets (table 12): these cannot fail.
    s.extend(Setting::uat_decoded(p).ok());
    s.extend(Setting::flarm_decoded(p).ok());
    s.push(Setting::gnss_nmea(gnss_nmea));
    s
}

/// Runs the set-up session on an open port; every byte read is handed to `forward` (with the
/// host monotonic time of the read). Returns whether the device accepted everything.
pub async fn run(
    device: &str,
    setup: Setup,
    serial: &mut SerialStream,
    forward: &mut impl FnMut(Vec<u8>),
) -> bool {
    let r = tokio::time::timeout(SESSION_LIMIT, async {
        match setup {
            Setup::Vn200 { rate_divisor } => vn200(device, rate_divisor, serial, forward).await,
            Setup::Ttmrf {
                decoded,
                gnss_nmea,
                run_baud,
            } => ttmrf(device, decoded, gnss_nmea, run_baud, serial, forward).await,
        }
    })
    .await;
    match r {
        Ok(Ok(ok)) => ok,
        Ok(Err(e)) => {
            warn!("{device}: set-up failed: {e}");
            false
        }
        Err(_) => {
            warn!("{device}: set-up did not finish within {SESSION_LIMIT:?}");
            false
        }
    }
}

/// Reads once with a deadline; `Ok(None)` at the deadline.
async fn read_until(
    serial: &mut SerialStream,
    buf: &mut [u8],
    deadline: tokio::time::Instant,
) -> std::io::Result<Option<usize>> {
    match tokio::time::timeout_at(deadline, serial.read(buf)).await {
        Ok(Ok(0)) => Err(std::io::Error::new(
            std::io::ErrorKind::UnexpectedEof,
            "port closed during set-up",
        )),
        Ok(Ok(n)) => Ok(Some(n)),
        Ok(Err(e)) => Err(e),
        Err(_) => Ok(None),
    }
}

async fn vn200(
    device: &str,
    rate_divisor: u16,
    serial: &mut SerialStream,
    forward: &mut impl FnMut(Vec<u8>),
) -> std::io::Result<bool> {
    let outputs = [(1u8, 1u16, rate_divisor, VN200_MASKS)];
    let Ok(mut client) = Vn200Client::setup_session(Duration::from_millis(500), 3, &outputs, false)
    else {
        return Ok(false);
    };
    let start = tokio::time::Instant::now();
    let mut codec = Codec(Vn200Decoder::new());
    let mut rx = BytesMut::with_capacity(4096);
    let mut buf = vec![0u8; 4096];
    while !client.is_done() {
        let now = start.elapsed();
        while let Some(bytes) = client.poll_transmit(now) {
            serial.write_all(&bytes).await?;
        }
        if client.is_done() {
            break;
        }
        let wake = client
            .poll_timeout()
            .map_or(now + Duration::from_millis(100), |t| t.max(now));
        if let Some(n) = read_until(serial, &mut buf, start + wake).await? {
            forward(buf[..n].to_vec());
            rx.extend_from_slice(&buf[..n]);
            let now = start.elapsed();
            while let Ok(Some(m)) = codec.decode(&mut rx) {
                client.handle_message(&m.message, now);
            }
        }
    }
    for r in client.report() {
        info!(
            "{device}: {} -> {:?} ({} attempt(s))",
            r.command.header(),
            r.outcome,
            r.attempts
        );
    }
    let ok = client.all_accepted();
    if ok {
        info!(
            "{device}: binary output 1 configured at {} Hz",
            VN200_IMU_HZ / u32::from(rate_divisor.max(1))
        );
    } else {
        warn!("{device}: binary output configuration not fully accepted");
    }
    Ok(ok)
}

async fn ttmrf(
    device: &str,
    decoded: TtText,
    gnss_nmea: bool,
    run_baud: u32,
    serial: &mut SerialStream,
    forward: &mut impl FnMut(Vec<u8>),
) -> std::io::Result<bool> {
    let cfg = ClientConfig {
        initial_baud: run_baud,
        ..ClientConfig::default()
    };
    let mut client = at::ConfigClient::new(ttmrf_settings(decoded, gnss_nmea), cfg);
    let start = tokio::time::Instant::now();
    client.start(Duration::ZERO);
    let mut buf = vec![0u8; 4096];
    loop {
        while let Some(out) = client.poll_output() {
            match out {
                Output::Send(bytes) => serial.write_all(&bytes).await?,
                Output::SetBaud(b) => {
                    if let Err(e) = serial.set_baud_rate(b) {
                        warn!("{device}: cannot set {b} baud: {e}");
                    }
                }
                Output::Finished(Ok(report)) => {
                    for c in &report.changed {
                        info!("{device}: {:?} {:?} -> {}", c.id, c.from, c.to);
                    }
                    for w in &report.warnings {
                        warn!("{device}: {w}");
                    }
                    info!(
                        "{device}: protocols configured ({} setting(s) changed)",
                        report.changed.len()
                    );
                    return Ok(true);
                }
                Output::Finished(Err(f)) => {
                    warn!("{device}: {}", f.error);
                    return Ok(false);
                }
            }
        }
        let now = start.elapsed();
        let wake = client
            .poll_timeout()
            .map_or(now + Duration::from_millis(100), |t| t.max(now));
        match read_until(serial, &mut buf, start + wake).await? {
            Some(n) => {
                forward(buf[..n].to_vec());
                client.handle_bytes(&buf[..n], start.elapsed());
            }
            None => client.handle_timeout(start.elapsed()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_drivers::ttmrf::at::SettingId;

    #[test]
    fn ttmrf_settings_select_the_text_protocol_everywhere() {
        let s = ttmrf_settings(TtText::Csv, false);
        let get = |id: SettingId| s.iter().find(|x| x.id() == id).map(Setting::value);
        // Table 12: CSV = 1; UAT_MODE decoded only = 2; NMEA off = 0.
        assert_eq!(get(SettingId::AdsbRxProtocolDecoded), Some(1));
        assert_eq!(get(SettingId::UatDecodedProtocol), Some(1));
        assert_eq!(get(SettingId::FlarmRxProtocolDecoded), Some(1));
        assert_eq!(get(SettingId::UatMode), Some(2));
        assert_eq!(get(SettingId::GnssRxProtocolRaw), Some(0));
        let s = ttmrf_settings(TtText::Json, true);
        assert!(s.contains(&Setting::adsb_decoded(DecodedProtocol::Json)));
        assert!(s.contains(&Setting::gnss_nmea(true)));
    }
}

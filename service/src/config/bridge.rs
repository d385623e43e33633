//! `[bridge]`: the configuration of `vigil bridge` (issue 22), in the same TOML file as `vigil
//! run`'s, validated with the rest (`vigil config --check`) whether or not this build has the
//! bridge (cargo feature `bridge`).
//!
//! Secure by default. Decisions:
//! - The bridge listens on loopback only unless told otherwise (`tcp/127.0.0.1:7447`), and never
//!   advertises itself by multicast scouting (a peer must be given its endpoint).
//! - Any endpoint off the host (listen or connect) must be encrypted: `tls/`, with
//!   `[bridge.tls]` (vigil's Zenoh is built with TCP and TLS links only, no QUIC). A listener off the host must also authenticate its peers: `[bridge.auth]`
//!   (Zenoh's user/password). A configuration that would expose an unauthenticated listener is
//!   refused with the key that does it; nothing is silently downgraded.
//! - "Off the host" is decided on the endpoint's address: 127.0.0.0/8, `::1` and `localhost` are
//!   loopback; anything else (a LAN address, a name, `0.0.0.0`, `[::]`) is not.

use std::net::IpAddr;

use serde::{Deserialize, Serialize};

use super::error::{ConfigError, invalid};

/// Default listen endpoint: loopback only.
pub const DEFAULT_LISTEN: &str = "tcp/127.0.0.1:7447";

/// `[bridge]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BridgeSection {
    /// The vehicle's name, the `<vehicle>` of the key expressions `vigil/<vehicle>/<topic>`:
    /// letters, digits, `-` and `_`.
    pub vehicle: String,
    /// Zenoh mode: `"peer"` (default: subscribers connect to the bridge) or `"client"` (the
    /// bridge connects to a router given in `connect`).
    pub mode: ZenohMode,
    /// Endpoints to listen on (`PROTOCOL/ADDRESS:PORT`, e.g. `"tcp/127.0.0.1:7447"`).
    pub listen: Vec<String>,
    /// Endpoints to connect to (a router, another peer).
    pub connect: Vec<String>,
    /// Payload encoding: `"json"` (the fields of `vigil listen`) or `"raw"` (the `#[repr(C)]`
    /// bytes, for peers of the same architecture).
    pub encoding: BridgeEncoding,
    /// Most samples per second sent per state topic; the newest sample is sent, older ones
    /// skipped (a slow link gets the latest state, not a backlog). Alerts are never limited.
    pub rates: RatesSection,
    /// TLS certificates (required by `tls/` endpoints).
    pub tls: Option<TlsSection>,
    /// User/password authentication of peers (required by a listener off the host).
    pub auth: Option<AuthSection>,
}

impl Default for BridgeSection {
    fn default() -> Self {
        Self {
            vehicle: "uav1".to_string(),
            mode: ZenohMode::Peer,
            listen: vec![DEFAULT_LISTEN.to_string()],
            connect: Vec::new(),
            encoding: BridgeEncoding::Json,
            rates: RatesSection::default(),
            tls: None,
            auth: None,
        }
    }
}

/// Zenoh session mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ZenohMode {
    /// A peer: listens and connects directly.
    Peer,
    /// A client of a router.
    Client,
}

/// Payload encoding on Zenoh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BridgeEncoding {
    /// JSON, the fields `vigil listen` prints (Zenoh encoding `application/json` with the
    /// payload's type name as schema).
    Json,
    /// The `#[repr(C)]` bytes (traffic: the `TrafficHeader` then `count` targets), Zenoh encoding
    /// `zenoh/bytes` with the type name as schema.
    Raw,
}

/// `[bridge.rates]`: most samples per second per state topic, Hz; 0 sends every sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RatesSection {
    /// Voted attitude (published at up to 100 Hz).
    pub attitude_hz: f64,
    /// Ownship solution.
    pub ownship_hz: f64,
    /// Traffic picture (1 Hz from `vigil run`).
    pub traffic_hz: f64,
    /// Integrity report (1 Hz).
    pub integrity_hz: f64,
}

impl Default for RatesSection {
    fn default() -> Self {
        Self {
            attitude_hz: 10.0,
            ownship_hz: 5.0,
            traffic_hz: 0.0,
            integrity_hz: 0.0,
        }
    }
}

/// `[bridge.tls]`: PEM files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TlsSection {
    /// CA certificate that signed the peers' certificates (a connecting side verifies the
    /// listener with it).
    pub root_ca_certificate: String,
    /// This side's certificate (required to listen).
    #[serde(default)]
    pub certificate: Option<String>,
    /// This side's private key (required to listen).
    #[serde(default)]
    pub private_key: Option<String>,
}

/// `[bridge.auth]`: Zenoh user/password authentication.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AuthSection {
    /// This side's user name.
    pub user: String,
    /// This side's password.
    pub password: String,
    /// File of `user:password` lines the listener accepts (Zenoh's dictionary file).
    #[serde(default)]
    pub dictionary_file: Option<String>,
}

/// An endpoint's protocol and whether its address is on this host.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Endpoint {
    /// Encrypted (`tls/`).
    pub encrypted: bool,
    /// The address is loopback.
    pub loopback: bool,
}

/// Parses `PROTOCOL/ADDRESS:PORT[?...][#...]` far enough to judge it.
pub fn endpoint(s: &str) -> Option<Endpoint> {
    let (proto, rest) = s.split_once('/')?;
    // The links vigil's Zenoh is built with (see the workspace's Cargo.toml).
    let encrypted = match proto {
        "tcp" => false,
        "tls" => true,
        _ => return None,
    };
    let addr = rest.split(['?', '#']).next()?;
    let (host, port) = addr.rsplit_once(':')?;
    port.parse::<u16>().ok()?;
    let host = host.trim_start_matches('[').trim_end_matches(']');
    let loopback = host == "localhost" || host.parse::<IpAddr>().is_ok_and(|ip| ip.is_loopback());
    Some(Endpoint {
        encrypted,
        loopback,
    })
}

impl BridgeSection {
    /// Checks every value; the first invalid key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let v = &self.vehicle;
        if v.is_empty()
            || v.len() > 64
            || !v
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
        {
            return Err(invalid(
                "bridge.vehicle",
                "1 to 64 letters, digits, '-' or '_' (it is a key expression chunk)",
            ));
        }
        if self.mode == ZenohMode::Client && self.connect.is_empty() {
            return Err(invalid(
                "bridge.connect",
                "a client needs a router to connect to",
            ));
        }
        for (name, list, listening) in [
            ("listen", &self.listen, true),
            ("connect", &self.connect, false),
        ] {
            for (i, s) in list.iter().enumerate() {
                let key = format!("bridge.{name}[{i}]");
                let Some(e) = endpoint(s) else {
                    return Err(invalid(
                        key,
                        format!(
                            "{s:?} is not tcp/ADDRESS:PORT or tls/ADDRESS:PORT (vigil's Zenoh has \
                             no other links)"
                        ),
                    ));
                };
                if !e.loopback && !e.encrypted {
                    return Err(invalid(
                        key,
                        format!(
                            "{s:?} is off this host and not encrypted: use tls/ with [bridge.tls]"
                        ),
                    ));
                }
                if e.encrypted {
                    let tls = self.tls.as_ref().ok_or_else(|| {
                        invalid("bridge.tls", format!("required by {key} ({s:?})"))
                    })?;
                    if listening && (tls.certificate.is_none() || tls.private_key.is_none()) {
                        return Err(invalid(
                            "bridge.tls",
                            format!("certificate and private_key are required to listen on {s:?}"),
                        ));
                    }
                }
                if listening && !e.loopback && self.auth.is_none() {
                    return Err(invalid(
                        key,
                        format!(
                            "{s:?} would accept unauthenticated peers from off this host: add \
                             [bridge.auth] (user, password, dictionary_file)"
                        ),
                    ));
                }
                if listening
                    && !e.loopback
                    && self
                        .auth
                        .as_ref()
                        .is_some_and(|a| a.dictionary_file.is_none())
                {
                    return Err(invalid(
                        "bridge.auth.dictionary_file",
                        format!("required to listen on {s:?} (the peers it accepts)"),
                    ));
                }
            }
        }
        let r = &self.rates;
        for (key, hz) in [
            ("bridge.rates.attitude_hz", r.attitude_hz),
            ("bridge.rates.ownship_hz", r.ownship_hz),
            ("bridge.rates.traffic_hz", r.traffic_hz),
            ("bridge.rates.integrity_hz", r.integrity_hz),
        ] {
            if !(hz.is_finite() && hz >= 0.0) {
                return Err(invalid(
                    key,
                    format!("a rate in Hz, 0 for every sample (got {hz})"),
                ));
            }
        }
        Ok(())
    }

    /// The commented `[bridge]` section of `vigil config --example` (its defaults).
    pub const EXAMPLE: &'static str = r#"
# `vigil bridge` (cargo feature `bridge`): vigil's topics on Zenoh as vigil/<vehicle>/<topic>.
[bridge]
vehicle = "uav1"
mode = "peer"                        # or "client" (connect to a router)
listen = ["tcp/127.0.0.1:7447"]      # loopback only; off the host: tls/, with [bridge.tls] and [bridge.auth]
connect = []
encoding = "json"                    # or "raw" (#[repr(C)] bytes, same-architecture peers)

[bridge.rates]                       # most samples per second per state topic; 0: every sample
attitude_hz = 10.0
ownship_hz = 5.0
traffic_hz = 0.0
integrity_hz = 0.0

# [bridge.tls]
# root_ca_certificate = "/etc/vigil/ca.pem"
# certificate = "/etc/vigil/bridge.pem"
# private_key = "/etc/vigil/bridge.key"
# [bridge.auth]
# user = "uav1"
# password = "..."
# dictionary_file = "/etc/vigil/peers.txt"   # user:password lines this listener accepts
"#;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(text: &str) -> BridgeSection {
        #[derive(Deserialize)]
        struct File {
            bridge: BridgeSection,
        }
        toml::from_str::<File>(text).unwrap().bridge
    }

    #[test]
    fn the_example_is_the_default() {
        assert_eq!(section(BridgeSection::EXAMPLE), BridgeSection::default());
        BridgeSection::default().validate().unwrap();
    }

    #[test]
    fn endpoints_are_judged_by_protocol_and_address() {
        let e = |s| endpoint(s).unwrap();
        let lo = |s| e(s).loopback;
        assert_eq!(
            e("tcp/127.0.0.1:7447"),
            Endpoint {
                encrypted: false,
                loopback: true
            }
        );
        assert!(lo("tcp/127.5.0.1:7447"), "all of 127/8");
        assert!(lo("tcp/[::1]:7447") && lo("tcp/localhost:7447"));
        assert!(!lo("tcp/0.0.0.0:7447"), "every interface");
        assert!(!lo("tcp/[::]:7447"));
        assert_eq!(
            e("tls/192.168.1.20:7447"),
            Endpoint {
                encrypted: true,
                loopback: false
            }
        );
        assert!(e("tls/gcs.local:7447#iface=eth0").encrypted);
        assert!(endpoint("quic/127.0.0.1:7447").is_none(), "not built");
        assert!(endpoint("serial//dev/ttyUSB0").is_none());
        assert!(endpoint("tcp/127.0.0.1").is_none(), "no port");
        assert!(endpoint("tcp/127.0.0.1:99999").is_none());
    }

    #[test]
    fn an_exposed_or_unauthenticated_listener_is_refused_with_its_key() {
        let err = |text: &str| section(text).validate().unwrap_err();
        let e = err("[bridge]\nlisten = [\"tcp/0.0.0.0:7447\"]");
        assert_eq!(e.key, "bridge.listen[0]");
        assert!(e.reason.contains("not encrypted"), "{e}");
        let e = err("[bridge]\nlisten = [\"tcp/127.0.0.1:7447\", \"tls/10.0.0.2:7447\"]");
        assert_eq!(e.key, "bridge.tls");
        let tls = "[bridge.tls]\nroot_ca_certificate = \"ca.pem\"\ncertificate = \"c.pem\"\n\
                   private_key = \"k.pem\"\n";
        let e = err(&format!(
            "[bridge]\nlisten = [\"tls/10.0.0.2:7447\"]\n{tls}"
        ));
        assert_eq!(e.key, "bridge.listen[0]");
        assert!(e.reason.contains("unauthenticated"), "{e}");
        let auth = "[bridge.auth]\nuser = \"u\"\npassword = \"p\"\n";
        let e = err(&format!(
            "[bridge]\nlisten = [\"tls/10.0.0.2:7447\"]\n{tls}{auth}"
        ));
        assert_eq!(e.key, "bridge.auth.dictionary_file");
        let ok = format!(
            "[bridge]\nlisten = [\"tls/10.0.0.2:7447\"]\n{tls}{auth}dictionary_file = \"d.txt\"\n"
        );
        section(&ok).validate().unwrap();
        // TLS on loopback needs certificates but no authentication.
        let ok = format!("[bridge]\nlisten = [\"tls/127.0.0.1:7447\"]\n{tls}");
        section(&ok).validate().unwrap();
        // Connecting out unencrypted off the host is refused too.
        let e = err("[bridge]\nmode = \"client\"\nconnect = [\"tcp/10.0.0.1:7447\"]");
        assert_eq!(e.key, "bridge.connect[0]");
        let e = err("[bridge]\nmode = \"client\"");
        assert_eq!(e.key, "bridge.connect");
        let e = err("[bridge]\nvehicle = \"a/b\"");
        assert_eq!(e.key, "bridge.vehicle");
        let e = err("[bridge.rates]\ntraffic_hz = -1.0");
        assert_eq!(e.key, "bridge.rates.traffic_hz");
    }
}

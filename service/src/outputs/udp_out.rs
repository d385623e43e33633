//! The UDP side of vigil's traffic outputs (MAVLink, GDL90): a non-blocking socket towards one
//! configured address. Off the safety path: a datagram the socket refuses is counted and the
//! first failure logged, never waited on or retried.

use std::net::{SocketAddr, UdpSocket};

/// A non-blocking UDP sender to one address.
pub struct UdpSink {
    /// What it carries, for the log ("MAVLink", "GDL90").
    what: &'static str,
    socket: UdpSocket,
    to: SocketAddr,
    /// Datagrams the socket refused.
    pub send_failures: u64,
}

impl UdpSink {
    /// Opens a socket towards `address` (`IP:PORT`); broadcast is allowed (EFBs and ground
    /// stations often listen on a broadcast address).
    pub fn open(what: &'static str, address: &str) -> std::io::Result<Self> {
        let to: SocketAddr = address
            .parse()
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))?;
        let bind: SocketAddr = if to.is_ipv4() {
            "0.0.0.0:0".parse().expect("literal")
        } else {
            "[::]:0".parse().expect("literal")
        };
        let socket = UdpSocket::bind(bind)?;
        socket.set_nonblocking(true)?;
        if to.is_ipv4() {
            socket.set_broadcast(true)?;
        }
        Ok(Self {
            what,
            socket,
            to,
            send_failures: 0,
        })
    }

    /// Sends each frame as one datagram.
    pub fn send_all(&mut self, frames: &[Vec<u8>]) {
        for frame in frames {
            if let Err(e) = self.socket.send_to(frame, self.to) {
                self.send_failures += 1;
                if self.send_failures == 1 {
                    tracing::warn!(
                        "{} output to {}: {e} (further failures counted)",
                        self.what,
                        self.to
                    );
                }
            }
        }
    }
}

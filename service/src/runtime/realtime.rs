//! `[realtime]`: an optional limit on the CPUs' wake-up latency while `vigil run` runs.
//!
//! An idle CPU sleeps in an idle state; waking it for the next serial read costs its exit
//! latency, and on a virtual machine the hypervisor's halt and resume on top. Every read of a
//! serial port is such a wake-up (thousands per second at full rates), so the idle states show
//! in both the latency and the CPU that `vigil run` is charged with. Linux's PM QoS interface,
//! `/dev/cpu_dma_latency`, lets a process hold a limit on that exit latency for as long as it
//! keeps the file open (the technique of cyclictest and of real-time Linux guides): with 0 the
//! CPUs poll instead of sleeping.
//!
//! Decision: off by default. Polling idle CPUs costs power (and, on a virtual machine, host CPU)
//! all the time the service runs; an integrator chooses it when the attitude latency matters
//! more. A request that cannot be made (not root, no such file) is logged and the service runs
//! without it: it changes timing, never results.

use std::fs::File;
use std::io::Write;

#[cfg(test)]
use crate::config::realtime::MAX_US;
pub use crate::config::realtime::RealtimeSection;

/// PM QoS device of the CPU wake-up latency limit.
pub const PM_QOS_PATH: &str = "/dev/cpu_dma_latency";

impl RealtimeSection {
    /// Makes the request when configured: the returned file holds it until dropped. `None`
    /// when not configured or refused (logged).
    pub fn hold(&self) -> Option<File> {
        let us = self.cpu_wakeup_latency_us?;
        match request(PM_QOS_PATH, us) {
            Ok(f) => {
                tracing::info!("CPU wake-up latency limited to {us} us while running (PM QoS)");
                Some(f)
            }
            Err(e) => {
                tracing::warn!(
                    "realtime.cpu_wakeup_latency_us: {PM_QOS_PATH}: {e}; running without the limit"
                );
                None
            }
        }
    }
}

/// Writes the limit to a PM QoS device: one native-endian 32-bit integer, us (the kernel's
/// binary form; it also accepts hex text).
fn request(path: &str, us: u32) -> std::io::Result<File> {
    let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
    let v = i32::try_from(us).unwrap_or(i32::MAX);
    f.write_all(&v.to_ne_bytes())?;
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_limit_is_written_as_one_native_s32_and_bounds_are_named() {
        let dir = std::env::temp_dir().join(format!("vigil-realtime-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pm_qos");
        std::fs::write(&path, b"").unwrap();
        let f = request(path.to_str().unwrap(), 20).unwrap();
        drop(f);
        assert_eq!(std::fs::read(&path).unwrap(), 20i32.to_ne_bytes());
        let _ = std::fs::remove_dir_all(&dir);

        let s = RealtimeSection {
            cpu_wakeup_latency_us: Some(MAX_US + 1),
        };
        assert_eq!(
            s.validate().unwrap_err().key,
            "realtime.cpu_wakeup_latency_us"
        );
        assert!(RealtimeSection::default().validate().is_ok());
        // Not configured: no request.
        assert!(RealtimeSection::default().hold().is_none());
        // The example section parses to the default (the key is commented out).
        let parsed: RealtimeSection =
            toml::from_str(RealtimeSection::EXAMPLE.trim_start_matches("[realtime]")).unwrap();
        assert_eq!(parsed, RealtimeSection::default());
    }
}

//! The simulation loop: devices produce messages, links turn them into host read chunks, and a
//! [`Sink`] receives the chunks in host-time order together with the truth records.
//!
//! The run advances in 100 ms windows of GPS time. After a window, every chunk whose receive time
//! is before the host time of the window's end is final (later messages are ready later, and
//! latency is never negative), so chunks are released in (receive time, port) order across ports.
//! Each link also ends its open read chunk at the end of a window (a chunk boundary every 100 ms
//! at most, as a USB adapter's latency timer would).

use crate::device::bahrs::BahrsModel;
use crate::device::ttmrf::TtmrfModel;
use crate::device::vn200::Vn200Model;
use crate::device::watson::WatsonModel;
use crate::device::{DeviceModel, Emission, FaultSchedule};
use crate::link::{Chunk, HostClock, Link};
use crate::magnetic::{MagneticModel, Wmm2025};
use crate::rng::Rng;
use crate::scenario::{Scenario, ScenarioError};
use crate::truth::{TruthRecord, World};

/// Error a sink may return (it ends the run).
pub type SinkError = Box<dyn std::error::Error + Send + Sync>;

/// Receiver of a run's output.
pub trait Sink {
    /// Called once before any output with the ports and run parameters.
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError>;
    /// One host read chunk, in (receive time, port) order.
    fn chunk(&mut self, chunk: &Chunk) -> Result<(), SinkError>;
    /// One truth record; `t_host_ns` is the host time of its first byte's start on the wire.
    fn truth(&mut self, record: &TruthRecord, t_host_ns: u64) -> Result<(), SinkError>;
    /// Bytes the host wrote to the ports since the last call, as (port index, bytes); polled
    /// at every window start and handed to the device models (`DeviceModel::receive`) with the
    /// window's start time. Recordings have none (the default); live terminals do.
    fn host_input(&mut self) -> Vec<(u16, Vec<u8>)> {
        Vec::new()
    }
}

/// One simulated serial port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInfo {
    /// Device name, also the port name.
    pub device: &'static str,
    /// Wire protocol.
    pub protocol: &'static str,
    /// Baud rate.
    pub baud: u32,
}

/// Parameters of a run, for the recording's metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// Scenario name.
    pub scenario: String,
    /// Run seed.
    pub seed: u64,
    /// GPS time of the start, ns.
    pub start_gps_ns: i64,
    /// Duration, ns.
    pub duration_ns: i64,
    /// The host clock drawn for this run.
    pub host_clock: HostClock,
    /// Ports in index order.
    pub ports: Vec<PortInfo>,
    /// Scenario devices that have no model yet (configuration carried, no output).
    pub devices_without_model: Vec<&'static str>,
}

/// Window length, ns.
const WINDOW_NS: i64 = 100_000_000;

struct Port {
    model: Box<dyn DeviceModel>,
    link: Link,
    next_index: u64,
}

/// A simulator for one scenario and seed.
pub struct Simulator {
    scenario_name: String,
    seed: u64,
    world: World,
    faults: FaultSchedule,
    clock: HostClock,
    ports: Vec<Port>,
    devices_without_model: Vec<&'static str>,
    ran: bool,
}

impl Simulator {
    /// A simulator with the WMM2025 magnetic model.
    pub fn new(scenario: &Scenario, seed: u64) -> Result<Self, ScenarioError> {
        Self::with_magnetic(scenario, seed, Box::new(Wmm2025))
    }

    /// A simulator with the given magnetic model.
    pub fn with_magnetic(
        scenario: &Scenario,
        seed: u64,
        magnetic: Box<dyn MagneticModel>,
    ) -> Result<Self, ScenarioError> {
        scenario.validate()?;
        let world = World::new(scenario, magnetic)?;
        let faults = FaultSchedule::new(&scenario.faults);
        let mut hc = Rng::stream(seed, "host/clock");
        let clock = HostClock {
            start_gps_ns: world.start_gps_ns,
            offset_ns: (hc.range(100.0, 10_000.0) * 1e9) as u64,
            drift: hc.range(-1.0, 1.0) * scenario.host.clock_drift_ppm_max * 1e-6,
        };
        let d = &scenario.devices;
        let mut models: Vec<Box<dyn DeviceModel>> = Vec::new();
        if let Some(b) = &d.bahrs {
            let pps = d.vn200.as_ref().is_some_and(|v| v.pps);
            models.push(Box::new(BahrsModel::new(b, &world, &faults, seed, pps)));
        }
        if let Some(w) = &d.watson {
            models.push(Box::new(WatsonModel::new(w, &world, seed)));
        }
        if let Some(v) = &d.vn200 {
            models.push(Box::new(Vn200Model::new(v, &world, &faults, seed)));
        }
        if let Some(t) = &d.ttmrf {
            models.push(Box::new(TtmrfModel::new(t, &world, &faults, seed)));
        }
        let devices_without_model = Vec::new();
        let ports = models
            .into_iter()
            .enumerate()
            .map(|(i, model)| Port {
                link: Link::new(
                    model.name(),
                    i as u16,
                    model.baud(),
                    &scenario.host,
                    world.start_gps_ns,
                    seed,
                ),
                model,
                next_index: 0,
            })
            .collect();
        Ok(Self {
            scenario_name: scenario.name.clone(),
            seed,
            world,
            faults,
            clock,
            ports,
            devices_without_model,
            ran: false,
        })
    }

    /// Adds a device model (e.g. the VN-200 model once it exists) on a new port.
    pub fn add_device(&mut self, model: Box<dyn DeviceModel>, host: &crate::scenario::HostConfig) {
        let i = self.ports.len() as u16;
        let link = Link::new(
            model.name(),
            i,
            model.baud(),
            host,
            self.world.start_gps_ns,
            self.seed,
        );
        self.devices_without_model.retain(|d| *d != model.name());
        self.ports.push(Port {
            model,
            link,
            next_index: 0,
        });
    }

    /// The simulated world (truth at any time).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The host clock drawn for this run.
    pub fn host_clock(&self) -> HostClock {
        self.clock
    }

    /// The ports in index order.
    pub fn ports(&self) -> Vec<PortInfo> {
        self.ports
            .iter()
            .map(|p| PortInfo {
                device: p.model.name(),
                protocol: p.model.protocol(),
                baud: p.model.baud(),
            })
            .collect()
    }

    /// Runs `duration_ns` of the scenario from its start into `sink`. A simulator runs once (its
    /// device models keep their state): a second call is an error.
    pub fn run(&mut self, duration_ns: i64, sink: &mut dyn Sink) -> Result<(), SinkError> {
        if std::mem::replace(&mut self.ran, true) {
            return Err("a simulator runs once: build a new one for another run".into());
        }
        let info = RunInfo {
            scenario: self.scenario_name.clone(),
            seed: self.seed,
            start_gps_ns: self.world.start_gps_ns,
            duration_ns,
            host_clock: self.clock,
            ports: self.ports(),
            devices_without_model: self.devices_without_model.clone(),
        };
        sink.start(&info)?;
        let end = self.world.start_gps_ns + duration_ns.max(0);
        let mut t = self.world.start_gps_ns;
        let mut emissions: Vec<Emission> = Vec::new();
        let mut pending: Vec<Chunk> = Vec::new();
        while t < end {
            let until = (t + WINDOW_NS).min(end);
            for (port, bytes) in sink.host_input() {
                if let Some(p) = self.ports.get_mut(usize::from(port)) {
                    p.model.receive(t, &bytes);
                }
            }
            for port in &mut self.ports {
                emissions.clear();
                port.model
                    .advance(&self.world, &self.faults, until, &mut emissions);
                for e in emissions.drain(..) {
                    let tx = port
                        .link
                        .transmit(&e, &self.faults, &self.clock, &mut pending);
                    let record = TruthRecord {
                        device: port.model.name(),
                        index: port.next_index,
                        kind: e.kind,
                        t_gps_ns: e.t_gps_ns,
                        t_tx_gps_ns: tx.t_tx_gps_ns,
                        corrupted: tx.corrupted,
                        rx_offset: tx.rx_offset,
                        values: e.values,
                        wire: e.bytes,
                    };
                    port.next_index += 1;
                    sink.truth(&record, self.clock.host_ns(tx.t_tx_gps_ns))?;
                }
                let until_rel = (until - self.world.start_gps_ns) as f64;
                port.link.end_window(until_rel, &self.clock, &mut pending);
            }
            let horizon = self.clock.host_ns(until);
            release(&mut pending, Some(horizon), sink)?;
            t = until;
        }
        for port in &mut self.ports {
            port.link.finish(&self.clock, &mut pending);
        }
        release(&mut pending, None, sink)
    }
}

/// Sends the pending chunks received before `horizon` (all when `None`) in (time, port) order.
fn release(
    pending: &mut Vec<Chunk>,
    horizon: Option<u64>,
    sink: &mut dyn Sink,
) -> Result<(), SinkError> {
    // Stable sort: chunks of one port keep their order.
    pending.sort_by_key(|c| (c.t_host_ns, c.port));
    let n = match horizon {
        Some(h) => pending.partition_point(|c| c.t_host_ns < h),
        None => pending.len(),
    };
    for c in pending.drain(..n) {
        sink.chunk(&c)?;
    }
    Ok(())
}

/// A sink that keeps everything in memory (tests, small runs).
#[derive(Debug, Default, Clone)]
pub struct MemorySink {
    /// The run parameters.
    pub info: Option<RunInfo>,
    /// Chunks in release order.
    pub chunks: Vec<Chunk>,
    /// Truth records in emission order.
    pub truth: Vec<TruthRecord>,
}

impl Sink for MemorySink {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        self.info = Some(info.clone());
        Ok(())
    }
    fn chunk(&mut self, chunk: &Chunk) -> Result<(), SinkError> {
        self.chunks.push(chunk.clone());
        Ok(())
    }
    fn truth(&mut self, record: &TruthRecord, _t_host_ns: u64) -> Result<(), SinkError> {
        self.truth.push(record.clone());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use serde_json::Map;

    use super::*;
    use crate::device::FaultSchedule;
    use crate::scenario::builtin;

    /// A device that echoes what the host wrote, 1 ms after the window that delivered it.
    struct Echo {
        pending: Vec<(i64, Vec<u8>)>,
    }

    impl DeviceModel for Echo {
        fn name(&self) -> &'static str {
            "echo"
        }
        fn protocol(&self) -> &'static str {
            "echo"
        }
        fn baud(&self) -> u32 {
            115_200
        }
        fn advance(&mut self, _: &World, _: &FaultSchedule, until: i64, out: &mut Vec<Emission>) {
            while self
                .pending
                .first()
                .is_some_and(|p| p.0 + 1_000_000 < until)
            {
                let (t, bytes) = self.pending.remove(0);
                out.push(Emission {
                    t_ready_gps_ns: t + 1_000_000,
                    bytes,
                    kind: "echo",
                    t_gps_ns: t,
                    values: Map::new(),
                });
            }
        }
        fn receive(&mut self, t: i64, bytes: &[u8]) {
            self.pending.push((t, bytes.to_vec()));
        }
    }

    /// A memory sink whose host writes "$VNRRG,01*XX" at the first poll.
    struct Commanding {
        inner: MemorySink,
        sent: bool,
    }

    impl Sink for Commanding {
        fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
            self.inner.start(info)
        }
        fn chunk(&mut self, chunk: &Chunk) -> Result<(), SinkError> {
            self.inner.chunk(chunk)
        }
        fn truth(&mut self, record: &TruthRecord, t: u64) -> Result<(), SinkError> {
            self.inner.truth(record, t)
        }
        fn host_input(&mut self) -> Vec<(u16, Vec<u8>)> {
            if std::mem::replace(&mut self.sent, true) {
                Vec::new()
            } else {
                vec![(0, b"$VNRRG,01*XX\r\n".to_vec())]
            }
        }
    }

    #[test]
    fn host_input_reaches_an_added_device_model() {
        let mut s = builtin("headon").unwrap();
        s.devices.bahrs = None;
        s.devices.watson = None;
        s.devices.vn200 = None;
        s.devices.ttmrf = None;
        let mut sim = Simulator::new(&s, 1).unwrap();
        sim.add_device(
            Box::new(Echo {
                pending: Vec::new(),
            }),
            &s.host,
        );
        let mut sink = Commanding {
            inner: MemorySink::default(),
            sent: false,
        };
        sim.run(300_000_000, &mut sink).unwrap();
        let got: Vec<u8> = sink
            .inner
            .chunks
            .iter()
            .flat_map(|c| c.bytes.clone())
            .collect();
        assert_eq!(got, b"$VNRRG,01*XX\r\n");
        assert_eq!(sink.inner.truth.len(), 1);
        assert_eq!(
            sink.inner.info.unwrap().devices_without_model,
            Vec::<&str>::new()
        );
    }

    /// Issue 25 point 4: the BAHRS reports no pulse while the VN-200 has no fix (ICD Table
    /// 3.22), unless its sync input is miswired to a pulse that does not follow that fix.
    #[test]
    fn bahrs_pulses_stop_without_a_vn200_fix_unless_the_sync_is_miswired() {
        let pulses_in_outage = |miswired: bool| {
            let mut s = builtin("nominal").unwrap();
            s.faults.push(crate::scenario::Fault::GnssOutage {
                from_s: 3.0,
                to_s: Some(8.0),
                device: Some("vn200".into()),
            });
            if miswired {
                s.faults.push(crate::scenario::Fault::BahrsSyncMiswired {
                    from_s: 0.0,
                    to_s: None,
                });
            }
            let mut sim = Simulator::new(&s, 1).unwrap();
            let mut sink = MemorySink::default();
            sim.run(10_000_000_000, &mut sink).unwrap();
            let t0 = sim.world().start_gps_ns;
            let secs = |r: &TruthRecord| (r.t_gps_ns - t0) as f64 / 1e9;
            let pulses: Vec<f64> = sink
                .truth
                .iter()
                .filter(|r| r.device == "bahrs" && r.kind == "sync_pulse_time")
                .map(secs)
                .collect();
            assert!(pulses.iter().any(|&t| t < 3.0), "{pulses:?}");
            assert!(pulses.iter().any(|&t| t >= 8.0), "{pulses:?}");
            // Pulses at whole GPS seconds 3 .. 7 fall inside the outage.
            pulses.iter().filter(|&&t| (3.0..8.0).contains(&t)).count()
        };
        assert_eq!(pulses_in_outage(false), 0);
        assert_eq!(pulses_in_outage(true), 5);
    }
}

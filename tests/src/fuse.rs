//! A scenario simulated in memory whose raw chunks go through the same path as `vigil replay
//! --emit fused` (decoders, [`Ingest`], [`Pipeline`]), without the service's monitor.

use vigil_fusion::ingest::Ingest;
use vigil_fusion::magnetic::Wmm;
use vigil_fusion::pipeline::{Fused, Pipeline, PipelineConfig};
use vigil_sim::{Chunk, PortInfo, RunInfo, Simulator, Sink, SinkError, TruthRecord};

const S: i64 = 1_000_000_000;

/// Feeds every chunk through alignment and fusion and hands each output to `f`.
struct FuseSink<F: FnMut(&Fused)> {
    ports: Vec<PortInfo>,
    replay: Ingest,
    pipeline: Pipeline,
    buf: Vec<Fused>,
    f: F,
}

impl<F: FnMut(&Fused)> FuseSink<F> {
    fn drain(&mut self) {
        for o in self.buf.drain(..) {
            (self.f)(&o);
        }
    }
}

impl<F: FnMut(&Fused)> Sink for FuseSink<F> {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        self.ports = info.ports.clone();
        Ok(())
    }

    fn chunk(&mut self, c: &Chunk) -> Result<(), SinkError> {
        let p = &self.ports[usize::from(c.port)];
        let (pipeline, buf) = (&mut self.pipeline, &mut self.buf);
        self.replay
            .feed(p.device, p.protocol, c.t_host_ns, &c.bytes, &mut |s| {
                pipeline.handle(s, buf);
                Ok::<(), std::convert::Infallible>(())
            })
            .expect("feed");
        self.drain();
        Ok(())
    }

    fn truth(&mut self, _: &TruthRecord, _: u64) -> Result<(), SinkError> {
        Ok(())
    }
}

/// Runs a scenario for `seconds` with `seed` .
pub fn run_scenario(
    scenario: &vigil_sim::Scenario,
    seconds: i64,
    seed: u64,
    f: impl FnMut(&Fused),
) -> (i64, Simulator) {
    let mut sim = Simulator::new(scenario, seed).unwrap();
    let mut sink = FuseSink {
        ports: Vec::new(),
        replay: Ingest::new(),
        pipeline: Pipeline::new(PipelineConfig::default(), Box::new(Wmm)).unwrap(),
        buf: Vec::new(),
        f,
    };
    sim.run(seconds * S, &mut sink).unwrap();
    let (pipeline, buf) = (&mut sink.pipeline, &mut sink.buf);
    sink.replay
        .finish(&mut |s| {
            pipeline.handle(s, buf);
            Ok::<(), std::convert::Infallible>(())
        })
        .unwrap();
    sink.pipeline.finish(&mut sink.buf);
    sink.drain();
    (sim.world().start_gps_ns, sim)
}

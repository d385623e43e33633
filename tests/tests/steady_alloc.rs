//! Heap allocations on the steady-state path of the VN-200 (issue 21): after the warm-up, a
//! VN-200 chunk taken through the service (decode, alignment, attitude fusion, publication to a
//! sink that keeps nothing) allocates nothing. Counted by a global allocator that counts the
//! allocations of the thread that turned counting on.
//!
//! Not covered: the chunk that closes a fusion step (once a second) builds the traffic picture,
//! which allocates per target (its callsign and source list, about two allocations per target);
//! the test counts those chunks apart and bounds them.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use vigil_monitor::MonitorParams;
use vigil_service::config::PipelineSection;
use vigil_service::{Outputs, Service};
use vigil_sim::{MemorySink, Scenario, Simulator};
use vigil_tests::sim_drive::ports_of;

struct Counting;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: every call is forwarded to the system allocator unchanged; the counters are
// thread-local cells with constant initialisers (no allocation to reach them).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        // SAFETY: forwarded as received.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded as received.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.with(Cell::get) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        // SAFETY: forwarded as received.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Publishes nowhere (the bus loans shared memory; nothing on the heap); notes whether a
/// traffic picture was published.
#[derive(Default)]
struct Discard {
    picture: bool,
}

impl Outputs for Discard {
    fn publish<T: vigil_bus::Payload>(&mut self, p: &T) {
        self.picture |= T::TOPIC == vigil_bus::Topic::Traffic;
        std::hint::black_box(p);
    }
}

#[test]
fn a_steady_state_vn200_chunk_allocates_nothing() {
    let sc = Scenario::from_toml(include_str!("../data/full-rates.toml")).unwrap();
    let mut sim = Simulator::new(&sc, 1).unwrap();
    let mut sink = MemorySink::default();
    sim.run(40_000_000_000, &mut sink).unwrap();
    let ports = ports_of(&sink);
    let vn = ports.iter().position(|p| p.device == "vn200").unwrap();
    let cfg = PipelineSection::default().pipeline_config();
    let mut s = Service::new(&ports, cfg, MonitorParams::default(), 2.0).unwrap();
    let t0 = sink.chunks[0].t_host_ns;
    for i in 0..ports.len() {
        s.handle_link(i, true, t0);
    }
    let (mut vn_chunks, mut vn_allocs, mut worst) = (0u64, 0u64, 0u64);
    let (mut steps, mut step_allocs) = (0u64, 0u64);
    let mut out = Discard::default();
    let mut next_tick = t0;
    for c in &sink.chunks {
        while c.t_host_ns >= next_tick {
            s.handle_timeout(next_tick, &mut out);
            next_tick += 100_000_000;
        }
        // Steady state: the clocks locked, every track and window at its size (30 s).
        let counted = usize::from(c.port) == vn && c.t_host_ns > t0 + 30_000_000_000;
        COUNT.with(|n| n.set(0));
        COUNTING.with(|f| f.set(counted));
        out.picture = false;
        s.handle_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
        COUNTING.with(|f| f.set(false));
        let n = COUNT.with(Cell::get);
        if counted && out.picture {
            steps += 1;
            step_allocs += n;
        } else if counted {
            vn_chunks += 1;
            vn_allocs += n;
            worst = worst.max(n);
        }
    }
    // 10 s at 400 Hz, several reads a message; ten fusion steps.
    assert!(vn_chunks > 10_000, "{vn_chunks} VN-200 chunks counted");
    assert_eq!(steps, 10, "fusion steps closed by a VN-200 chunk");
    // 300 intruders: two allocations each and a few for the picture.
    assert!(
        step_allocs <= steps * (2 * 300 + 16),
        "{step_allocs} allocations over {steps} fusion steps"
    );
    assert_eq!(
        vn_allocs, 0,
        "{vn_allocs} allocations over {vn_chunks} VN-200 chunks (worst chunk {worst})"
    );
}

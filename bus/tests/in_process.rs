//! Single-process behaviour of the bus: sequence gaps under each overflow policy, event wake-up,
//! history for late joiners, and the payload layouts (the byte contract with other languages).

mod common;

use std::mem::{align_of, size_of};
use std::time::{Duration, Instant};

use common::*;
use iceoryx2::prelude::ZeroCopySend;
use vigil_bus::payload::SCHEMA_VERSION;
use vigil_bus::{
    AlertPayload, AttitudePayload, ChannelComparison, DeviceIntegrity, Header, IntegrityPayload,
    OwnshipPayload, Target, Topic, TrafficHeader, UnitAttitude,
    payload::integrity::HealthComparison,
};

#[test]
fn alerts_never_overwrite_a_full_buffer_and_the_gap_and_failures_are_counted() {
    let b = bus(&unique_prefix("alert-gap"), "gap");
    let mut publ = b.publisher::<AlertPayload>().unwrap();
    let mut sub = b.subscriber::<AlertPayload>().unwrap();
    let cap = Topic::Alerts.policy().buffer_size; // 256
    // 300 alerts without reading: the first 256 are kept, seq 257..=300 are discarded for this
    // subscriber and each counted as a failed delivery.
    for _ in 0..300 {
        publ.publish(&alert()).unwrap();
    }
    assert_eq!(publ.failed_deliveries(), (300 - cap) as u64);
    for expected in 1..=cap as u64 {
        let r = sub.try_receive().unwrap().expect("kept alert");
        assert_eq!((r.header.seq, r.missed_before), (expected, 0));
        assert_eq!(r.reason(), alert().reason());
    }
    assert!(sub.try_receive().unwrap().is_none());
    // The next one (seq 301) shows the 44 lost ones as a gap.
    publ.publish(&alert()).unwrap();
    let r = sub.try_receive().unwrap().unwrap();
    assert_eq!((r.header.seq, r.missed_before), (301, 300 - cap as u64));
    drop(r);
    assert_eq!((sub.received(), sub.missed()), (cap as u64 + 1, 44));
}

#[test]
fn state_topics_keep_the_latest_and_show_the_overwritten_as_a_gap() {
    let b = bus(&unique_prefix("state-gap"), "gap");
    let mut publ = b.publisher::<AttitudePayload>().unwrap();
    let mut sub = b.subscriber::<AttitudePayload>().unwrap();
    let cap = Topic::Attitude.policy().buffer_size as u64; // 8
    publ.publish(&attitude()).unwrap();
    assert_eq!(sub.try_receive().unwrap().unwrap().header.seq, 1);
    // seq 2..=21 without reading: the buffer keeps the newest 8 (14..=21); 2..=13 overwritten.
    for _ in 0..20 {
        publ.publish(&attitude()).unwrap();
    }
    assert_eq!(publ.failed_deliveries(), 0, "overflow is not a failure");
    let first = sub.try_receive().unwrap().unwrap();
    assert_eq!(first.header.seq, 21 - cap + 1);
    assert_eq!(first.missed_before, 12);
    drop(first);
    let mut last = 0;
    while let Some(r) = sub.try_receive().unwrap() {
        assert_eq!(r.missed_before, 0);
        last = r.header.seq;
    }
    assert_eq!(last, 21);
    assert_eq!(sub.missed(), 12);
}

#[test]
fn a_waiting_subscriber_is_woken_by_the_publisher() {
    let prefix = unique_prefix("wake");
    let b = bus(&prefix, "waiter");
    let mut sub = b.subscriber::<OwnshipPayload>().unwrap();
    // Nothing published: the wait times out.
    let t0 = Instant::now();
    assert!(!sub.wait(Duration::from_millis(50)).unwrap());
    assert!(t0.elapsed() >= Duration::from_millis(45));
    // A publisher on another thread (own node) sends after 100 ms; the wait returns on the
    // wake-up long before its 10 s timeout.
    let p = prefix.clone();
    let t = std::thread::spawn(move || {
        let b = bus(&p, "waker");
        let mut publ = b.publisher::<OwnshipPayload>().unwrap();
        std::thread::sleep(Duration::from_millis(100));
        publ.publish(&ownship()).unwrap();
        std::thread::sleep(Duration::from_millis(200));
    });
    let t0 = Instant::now();
    let r = sub
        .receive_timeout(Duration::from_secs(10))
        .unwrap()
        .unwrap();
    assert!(t0.elapsed() < Duration::from_secs(5));
    assert_eq!(content(r.payload()), content(&ownship()));
    assert_eq!(r.header.schema_version, SCHEMA_VERSION);
    drop(r);
    t.join().unwrap();
}

#[test]
fn deferred_samples_are_delivered_at_once_and_wake_once_when_notified() {
    let prefix = unique_prefix("deferred");
    let b = bus(&prefix, "deferred");
    let mut sub = b.subscriber::<OwnshipPayload>().unwrap();
    let mut publ = b.publisher::<OwnshipPayload>().unwrap();
    for _ in 0..3 {
        publ.publish_deferred(&ownship()).unwrap();
    }
    // No wake-up yet, but the samples are there for a subscriber that looks.
    assert!(!sub.wait(Duration::from_millis(30)).unwrap());
    let mut n = 0;
    while let Some(r) = sub.try_receive().unwrap() {
        assert_eq!(content(r.payload()), content(&ownship()));
        n += 1;
    }
    assert_eq!(n, 3);
    // One wake-up for the three; none when nothing was sent since.
    publ.notify_pending();
    assert!(sub.wait(Duration::from_millis(500)).unwrap());
    publ.notify_pending();
    assert!(!sub.wait(Duration::from_millis(30)).unwrap());
    // An ordinary publication still wakes at once.
    publ.publish(&ownship()).unwrap();
    assert!(sub.wait(Duration::from_millis(500)).unwrap());
}

#[test]
fn a_late_subscriber_gets_the_current_state_from_the_history() {
    let b = bus(&unique_prefix("history"), "history");
    let mut publ = b.publisher::<IntegrityPayload>().unwrap();
    for _ in 0..5 {
        publ.publish(&integrity()).unwrap();
    }
    // History size 1: the late joiner receives exactly the latest state, seq 5.
    let mut sub = b.subscriber::<IntegrityPayload>().unwrap();
    publ.publish_with(|p| *p = integrity()).unwrap(); // connects the subscriber, delivers seq 6
    let a = sub.try_receive().unwrap().unwrap();
    assert_eq!(a.header.seq, 5);
    assert_eq!(a.devices().len(), 3);
    // JSON lists only the 3 valid devices, names as text, an unknown age as null.
    let v = serde_json::to_value(a.payload()).unwrap();
    assert_eq!(v["devices"].as_array().unwrap().len(), 3);
    assert_eq!(v["devices"][2]["name"], "watson");
    assert!(v["devices"][2]["last_message_age_s"].is_null());
    // Issue 25 point 4 (v3): the health fields, unknown as the documented sentinels (health
    // 0xFF, VN-200 status 0xFF, ages null) and every combination "not compared".
    assert_eq!(
        v["bahrs_navigation_health"],
        serde_json::json!([255u8; 5].to_vec())
    );
    assert_eq!(
        v["bahrs_inertial_health"],
        serde_json::json!([255u8; 6].to_vec())
    );
    assert_eq!(
        (v["vn200_ins_mode"].clone(), v["vn200_gnss_fix"].clone()),
        (255.into(), 255.into())
    );
    assert!(v["vn200_status_age_s"].is_null() && v["bahrs_pulse_age_s"].is_null());
    let checks = v["health_checks"].as_array().unwrap();
    assert_eq!(checks.len(), 4);
    assert!(
        checks
            .iter()
            .all(|c| c["state"] == 2 && c["disagree_s"].is_null())
    );
    drop(a);
    assert_eq!(sub.try_receive().unwrap().unwrap().header.seq, 6);
}

#[test]
fn traffic_travels_as_a_slice_of_its_count() {
    let b = bus(&unique_prefix("traffic"), "traffic");
    let mut publ = b.traffic_publisher().unwrap();
    let mut sub = b.traffic_subscriber().unwrap();
    // A full picture (the capacity) arrives whole.
    let t = traffic();
    publ.publish(&t).unwrap();
    let r = sub.try_receive().unwrap().unwrap();
    assert_eq!(r.wire_header().count as usize, vigil_bus::MAX_TARGETS);
    assert_eq!(r.targets().len(), vigil_bus::MAX_TARGETS);
    assert_eq!(format!("{:?}", r.targets()), format!("{:?}", t.targets()));
    assert_eq!(r.header().gps_time_ns, 7);
    // JSON: the targets, NaN as null, callsign as text.
    let v = serde_json::to_value(r.to_payload()).unwrap();
    assert_eq!(
        v["targets"].as_array().unwrap().len(),
        vigil_bus::MAX_TARGETS
    );
    assert_eq!(v["count"], vigil_bus::MAX_TARGETS);
    assert_eq!(v["targets"][1]["callsign"], "T00001");
    assert!(v["targets"][1]["tau_mod_s"].is_null());
    assert_eq!(v["targets"][2]["tau_mod_s"], 22.0);
    assert_eq!(v["header"]["seq"], 1);
    drop(r);
    // A 10-target picture is a slice of 10: the iceoryx2 sample holds exactly the 10 targets.
    let mut ten = traffic();
    ten.set_targets(&t.targets()[..10]);
    publ.publish(&ten).unwrap();
    let r = sub.try_receive().unwrap().unwrap();
    assert_eq!(r.targets().len(), 10);
    assert_eq!(r.wire_header().count, 10);
    assert_eq!(r.targets()[9].address, t.targets()[9].address);
    assert_eq!(r.header().seq, 2);
    drop(r);
    // An empty picture is a slice of 0 and still carries its header.
    publ.publish(&vigil_bus::TrafficPayload::default()).unwrap();
    let r = sub.try_receive().unwrap().unwrap();
    assert!(r.targets().is_empty());
    assert_eq!(r.header().seq, 3);
}

#[test]
fn payload_layouts_are_fixed() {
    // Sizes derived by hand from the field lists (every field naturally aligned, explicit
    // padding, so there are no implicit holes):
    // Header: u32 + u32 + u64 + i64 + u64 = 32.
    assert_eq!(size_of::<Header>(), 32);
    // UnitAttitude: i64 + 6 f64 + 2 u8 + 6 pad = 64; Attitude: 32 + 6*8 + 3*64 + 9 + 3 + 4 = 288.
    assert_eq!(size_of::<UnitAttitude>(), 64);
    // Issue 25 adds 3 + 4 u8 + 1 pad + 7 f64 = 64: 352.
    // Issue 25 points 5 and 6 (v3): ChannelComparison 5 f64 + 2 u8 + 6 pad = 48; 2 vertical +
    // 6 inertial = 384, then 2 + 6 health u8 = 8: 352 + 384 + 8 = 744.
    assert_eq!(size_of::<ChannelComparison>(), 48);
    // Issue 25 point 6 (v4): f64 + 2 ChannelComparison + 2 u8 + 6 pad = 8 + 96 + 8: 856.
    assert_eq!(size_of::<AttitudePayload>(), 856);
    // Ownship: 32 + 12 f64 + 3 u8 + 5 pad = 136.
    assert_eq!(size_of::<OwnshipPayload>(), 136);
    // Target (v3, issue 26): u32 + 4 u8 + 8 callsign = 16; 8 f64 of reported state = 64;
    // 5 u8 + 3 pad = 8; 14 f64 of relative geometry = 112; u64 flags = 8: 208. The traffic
    // header: 32 + 2 u32 = 40. A 10-target picture is 40 + 10 * 208 = 2120 bytes of payload
    // (schema 2: 139304 whatever the count).
    assert_eq!(size_of::<Target>(), 208);
    assert_eq!(size_of::<TrafficHeader>(), 40);
    // DeviceIntegrity: 16 + 2 u8 + 6 pad + f64 + 9 u64 = 104; Integrity: 32 + 8 + 2 f64 +
    // 8*104 = 888, + issue 18's u8 + 7 pad = 896, + issue 25's 2 u32 and 32 active alerts of
    // (u32 + 2 u8 + 2 pad + i64 + 160) = 176: 896 + 8 + 5632 = 6536.
    assert_eq!(size_of::<DeviceIntegrity>(), 104);
    // Issue 25 point 4 (v3): 5 + 6 health u8 + 2 u8 + 1 pad + u16 = 16, 2 f64 = 16, and 4
    // health comparisons of (2 u8 + 6 pad + f64) = 16: 6536 + 96 = 6632.
    assert_eq!(size_of::<HealthComparison>(), 16);
    assert_eq!(size_of::<IntegrityPayload>(), 6632);
    // Alert: 32 + u32 + 2 u8 + 2 pad + i64 + 160 = 208.
    assert_eq!(size_of::<AlertPayload>(), 208);
    assert_eq!(align_of::<Target>(), 8);
    assert_eq!(align_of::<TrafficHeader>(), 8);
}

#[test]
fn type_names_are_explicit_and_versioned() {
    // SAFETY: `type_name` is an unsafe fn in iceoryx2 0.10 because a wrong implementation is
    // unsound; calling it only reads a static string.
    let names = unsafe {
        [
            <AttitudePayload as ZeroCopySend>::type_name(),
            <OwnshipPayload as ZeroCopySend>::type_name(),
            <Target as ZeroCopySend>::type_name(),
            <TrafficHeader as ZeroCopySend>::type_name(),
            <IntegrityPayload as ZeroCopySend>::type_name(),
            <AlertPayload as ZeroCopySend>::type_name(),
        ]
    };
    assert_eq!(
        names,
        [
            "vigil.Attitude.v4",
            "vigil.Ownship.v2",
            "vigil.Target.v3",
            "vigil.TrafficHeader.v1",
            "vigil.Integrity.v4",
            "vigil.Alert.v1"
        ]
    );
    assert_eq!(SCHEMA_VERSION, 3);
}

#[test]
fn lossless_mode_waits_for_a_slow_subscriber_and_loses_nothing() {
    let prefix = unique_prefix("lossless");
    let b = lossless_bus(&prefix, "lossless-pub", 5.0);
    let mut publ = b.publisher::<AttitudePayload>().unwrap();
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let p2 = prefix.clone();
    let reader = std::thread::spawn(move || {
        let b = lossless_bus(&p2, "lossless-sub", 5.0);
        let mut sub = b.subscriber::<AttitudePayload>().unwrap();
        ready_tx.send(()).unwrap();
        let mut seqs = Vec::new();
        while seqs.len() < 150 {
            // A slow consumer: 1 ms per sample, while the publisher sends as fast as it can.
            std::thread::sleep(std::time::Duration::from_millis(1));
            if let Some(r) = sub.try_receive().unwrap() {
                seqs.push(r.header.seq);
            }
        }
        (seqs, sub.missed())
    });
    ready_rx.recv().unwrap();
    for _ in 0..150 {
        publ.publish(&attitude()).unwrap();
    }
    let (seqs, missed) = reader.join().unwrap();
    // 150 samples through a buffer of 64: every one arrives, in order, none overwritten.
    assert_eq!(seqs, (1..=150).collect::<Vec<u64>>());
    assert_eq!(missed, 0);
    assert_eq!(publ.failed_deliveries(), 0);
}

#[test]
fn lossless_mode_gives_up_on_a_subscriber_that_never_reads() {
    let b = lossless_bus(&unique_prefix("lossless-dead"), "lossless-dead", 0.1);
    let mut publ = b.publisher::<AttitudePayload>().unwrap();
    let _sub = b.subscriber::<AttitudePayload>().unwrap();
    let cap = vigil_bus::LOSSLESS_BUFFER;
    for _ in 0..cap {
        publ.publish(&attitude()).unwrap();
    }
    assert_eq!(publ.failed_deliveries(), 0);
    // The buffer is full: each further sample waits 0.1 s, then is discarded and counted.
    let t = std::time::Instant::now();
    publ.publish(&attitude()).unwrap();
    publ.publish(&attitude()).unwrap();
    assert!(t.elapsed() >= std::time::Duration::from_millis(200));
    assert_eq!(publ.failed_deliveries(), 2);
}

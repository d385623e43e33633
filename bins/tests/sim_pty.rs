//! `vigil sim --pty-dir`: the simulator live on pseudo-terminals, read with tokio-serial exactly as
//! vigil reads real serial ports, decoded with the drivers' decoders.
#![cfg(target_os = "linux")]

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_serial::SerialPortBuilderExt;
use vigil_drivers::{bahrs, decode_slice, watson};

async fn read_for(path: String, baud: u32, d: Duration) -> Vec<u8> {
    let mut port = tokio_serial::new(&path, baud)
        .open_native_async()
        .expect("open pty with tokio-serial");
    // The host may write too (commands); the models that do not listen ignore it.
    port.write_all(b"\r\n").await.expect("write to the pty");
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    let deadline = tokio::time::Instant::now() + d;
    loop {
        match tokio::time::timeout_at(deadline, port.read(&mut buf)).await {
            Ok(Ok(0)) | Err(_) => break,
            Ok(Ok(n)) => out.extend_from_slice(&buf[..n]),
            Ok(Err(e)) => panic!("read {path}: {e}"),
        }
    }
    out
}

#[test]
fn live_ptys_are_read_with_tokio_serial() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_pty");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args([
            "sim",
            "--scenario",
            "nominal",
            "--duration",
            "5",
            "--seed",
            "3",
            "--pty-dir",
        ])
        .arg(&dir)
        .stdout(Stdio::piped())
        .spawn()
        .expect("start vigil sim");
    // One line per port: device, terminal path, baud.
    let mut ports = Vec::new();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    // Read every port line (bahrs, watson, vn200, ttmrf) even though only the first two are
    // used: the simulator exits when a port line cannot be written.
    for _ in 0..4 {
        let l = lines.next().expect("port line").unwrap();
        let f: Vec<&str> = l.split(' ').collect();
        ports.push((
            f[0].to_string(),
            f[1].to_string(),
            f[2].parse::<u32>().unwrap(),
        ));
    }
    assert_eq!(ports[0].0, "bahrs");
    assert_eq!(ports[1].0, "watson");
    assert_eq!(ports[2].0, "vn200");
    assert_eq!(ports[3].0, "ttmrf");
    ports.truncate(2);
    assert_eq!(
        std::fs::read_link(dir.join("bahrs")).unwrap(),
        PathBuf::from(&ports[0].1)
    );
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let (b, w) = rt.block_on(async {
        tokio::join!(
            read_for(ports[0].1.clone(), ports[0].2, Duration::from_millis(2500)),
            read_for(ports[1].1.clone(), ports[1].2, Duration::from_millis(2500)),
        )
    });
    let status = child.wait().unwrap();
    assert!(status.success());

    let mut bd = bahrs::Decoder::new();
    let msgs = decode_slice(&mut bd, &b);
    let inertial: Vec<u8> = msgs
        .iter()
        .filter_map(|m| match m {
            bahrs::Message::Inertial(i) => Some(i.seq),
            _ => None,
        })
        .collect();
    // 100 Hz for about 2.5 s (less what was sent before the port was opened).
    assert!(inertial.len() > 150, "{} inertial messages", inertial.len());
    // Consecutive sequence counters: nothing lost or reordered on the way. One gap is allowed:
    // bytes written before the port was opened may have overflowed the terminal's buffer.
    let gaps = inertial
        .windows(2)
        .filter(|p| p[1] != p[0].wrapping_add(1))
        .count();
    assert!(gaps <= 1, "{gaps} sequence gaps");
    assert_eq!(bd.stats().checksum_failures, 0);

    let lines = decode_slice(&mut watson::Decoder::new(), &w);
    // 11.85 lines per second at 9600 baud.
    assert!(lines.len() >= 20, "{} watson lines", lines.len());
}

/// Starts a live simulation and returns it with its (device, path, baud) lines.
fn start_live(
    dir: &std::path::Path,
    seconds: &str,
) -> (std::process::Child, Vec<(String, String, u32)>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args([
            "sim",
            "--scenario",
            "nominal",
            "--duration",
            seconds,
            "--seed",
            "4",
            "--pty-dir",
        ])
        .arg(dir)
        .stdout(Stdio::piped())
        .spawn()
        .expect("start vigil sim");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    // All four port lines are read (the simulator exits when one cannot be written); the
    // recordings use the first two.
    let mut ports: Vec<(String, String, u32)> = (0..4)
        .map(|_| {
            let l = lines.next().expect("port line").unwrap();
            let f: Vec<&str> = l.split(' ').collect();
            (
                f[0].to_string(),
                f[1].to_string(),
                f[2].parse::<u32>().unwrap(),
            )
        })
        .collect();
    ports.truncate(2);
    (child, ports)
}

#[test]
fn record_live_ports_then_replay() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_record");
    std::fs::create_dir_all(&dir).unwrap();
    let (mut sim, ports) = start_live(&dir.join("ports"), "10");
    let config = dir.join("record.toml");
    let mut text = String::new();
    for (device, path, baud) in &ports {
        text += &format!("[[ports]]\ndevice = \"{device}\"\npath = \"{path}\"\nbaud = {baud}\n\n");
    }
    std::fs::write(&config, text).unwrap();
    let vigil = env!("CARGO_BIN_EXE_vigil");
    // 1: a fixed duration.
    let a = dir.join("a.mcap");
    let o = Command::new(vigil)
        .args(["record", "--duration", "2"])
        .arg("--config")
        .arg(&config)
        .arg("--out")
        .arg(&a)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // 2: ended by Ctrl-C (SIGINT).
    let b = dir.join("b.mcap");
    let rec = Command::new(vigil)
        .arg("record")
        .arg("--config")
        .arg(&config)
        .arg("--out")
        .arg(&b)
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(2000));
    let kill = Command::new("kill")
        .args(["-INT", &rec.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = rec.wait_with_output().unwrap();
    assert!(o.status.success());
    // 3: killed (SIGKILL) after 2.5 s: readable up to its last flush (at most a second lost).
    let c = dir.join("c.mcap");
    let mut rec = Command::new(vigil)
        .arg("record")
        .arg("--config")
        .arg(&config)
        .arg("--out")
        .arg(&c)
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(2500));
    rec.kill().unwrap();
    let _ = rec.wait();
    assert!(sim.wait().unwrap().success());
    let o = Command::new(vigil).arg("replay").arg(&c).output().unwrap();
    assert!(o.status.success());
    let summary: serde_json::Value = serde_json::from_slice(o.stderr.trim_ascii()).unwrap();
    assert!(summary["damage"].is_string(), "{summary}");
    assert!(
        summary["devices"]["bahrs"]["frames_decoded"]
            .as_u64()
            .unwrap()
            > 200,
        "{summary}"
    );

    for file in [&a, &b] {
        let o = Command::new(vigil)
            .arg("replay")
            .arg(file)
            .output()
            .unwrap();
        assert!(o.status.success());
        let summary: serde_json::Value = serde_json::from_slice(o.stderr.trim_ascii()).unwrap();
        assert_eq!(
            summary["damage"],
            serde_json::Value::Null,
            "{}",
            file.display()
        );
        // About 1.5 s or more of 300 BAHRS messages per second, none damaged on the way.
        let bahrs = &summary["devices"]["bahrs"];
        assert!(bahrs["frames_decoded"].as_u64().unwrap() > 300, "{summary}");
        assert_eq!(bahrs["checksum_failures"], 0);
        assert!(
            summary["devices"]["watson"]["frames_decoded"]
                .as_u64()
                .unwrap()
                > 10,
            "{summary}"
        );
        // Host receive times are CLOCK_MONOTONIC ns and increase.
        let lines: Vec<serde_json::Value> = o
            .stdout
            .split(|&c| c == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| serde_json::from_slice(l).unwrap())
            .collect();
        let t: Vec<u64> = lines
            .iter()
            .filter(|l| l["device"] == "bahrs")
            .map(|l| l["t_host_ns"].as_u64().unwrap())
            .collect();
        assert!(t.windows(2).all(|w| w[0] <= w[1]));
    }
}

/// Issue 26: `vigil decode --port` opens a serial port in raw mode itself. The terminal is put
/// in cooked mode first (`stty sane`: line editing, CR-to-NL translation, signal characters), as
/// a freshly plugged USB adapter often is; `cat` on it would mangle the binary BAHRS stream. The
/// decoder then sees every frame intact (no checksum failure, consecutive sequence counters) at
/// the BAHRS's 100 Hz inertial rate, and it ends when the port goes away (the simulator exits).
#[test]
fn decode_port_reads_a_cooked_terminal_in_raw_mode() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("decode_port");
    let (mut sim, ports) = start_live(&dir.join("ports"), "4");
    let (device, path, baud) = &ports[0];
    assert_eq!(device, "bahrs");
    let stty = Command::new("stty")
        .args(["-F", path, "sane"])
        .status()
        .expect("stty");
    assert!(stty.success());
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["decode", "--device", "bahrs", "--port", path])
        .args(["--baud", &baud.to_string()])
        .output()
        .expect("vigil decode --port");
    assert!(sim.wait().unwrap().success());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value = serde_json::from_str(
        String::from_utf8_lossy(&out.stderr)
            .lines()
            .last()
            .expect("a summary line"),
    )
    .unwrap();
    assert_eq!(summary["checksum_failures"], 0, "{summary}");
    // The port is opened while the simulator is already sending: only the partial frame it
    // joins in the middle of may be skipped (the longest BAHRS frame is well under 64 bytes).
    let skipped = summary["bytes_skipped"].as_u64().unwrap();
    assert!(skipped < 64, "{summary}");
    let seqs: Vec<u64> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .filter(|m| m["type"] == "inertial")
        .map(|m| m["seq"].as_u64().unwrap())
        .collect();
    // About 4 s at 100 Hz, less the start-up.
    assert!(seqs.len() > 250, "{} inertial messages", seqs.len());
    let gaps = seqs.windows(2).filter(|p| p[1] != (p[0] + 1) % 256).count();
    assert!(gaps <= 1, "{gaps} sequence gaps");
}

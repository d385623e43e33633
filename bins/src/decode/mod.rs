//! `vigil decode`: raw device bytes in, JSON Lines out, counters on stderr.
//!
//! Every device shares the same runner ([`run_decoder`]): it reads the input in chunks, feeds the
//! device's sans-IO decoder, writes one JSON object per decoded message to stdout and, at the end,
//! one JSON summary of the counters to stderr. Bad frames only show in the counters; the exit code
//! is 0 whenever the input could be read.

mod bahrs;
mod modes;
mod ttmrf;
mod ttmrf_binary;
mod ttmrf_text;
mod vn200;
mod watson;

use std::fs::File;
use std::io::{self, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use bytes::BytesMut;
use clap::{Args, ValueEnum};
use serde::Serialize;
use vigil_drivers::{DecodeStats, DeviceDecoder};

/// Devices `vigil decode` understands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Device {
    /// BAHRS baro-inertial AHRS (binary protocol 2.0).
    Bahrs,
    /// Watson AHRS-E304 (ASCII attitude string).
    Watson,
    /// VectorNav VN-200 (binary outputs and ASCII sentences).
    Vn200,
    /// Aerobits TT-Multi-RF (choose the protocol with --format).
    Ttmrf,
}

/// Output protocols of the TT-Multi-RF.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TtFormat {
    /// Detect per line/frame where unambiguous.
    Auto,
    /// AERO CSV lines.
    Csv,
    /// JSON objects.
    Json,
    /// MAVLink 1/2 frames.
    Mavlink,
    /// GDL90 frames.
    Gdl90,
    /// ASTERIX CAT021/CAT023 data blocks.
    Asterix,
    /// NMEA sentences from the GNSS.
    Nmea,
    /// AT command responses and state messages.
    At,
    /// Raw Mode S, HEX with extended fields.
    Hex,
    /// Raw Mode S, HEX without extended fields (AVR).
    Hexd,
    /// Raw Mode S, Beast binary.
    Beast,
}

/// Arguments of `vigil decode`.
#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// Device whose byte stream the input is.
    #[arg(long, value_enum)]
    pub device: Device,
    /// TT-Multi-RF output protocol (only with --device ttmrf).
    #[arg(long, value_enum, default_value = "auto")]
    pub format: TtFormat,
    /// Receiver position `LAT,LON` in degrees for Mode S surface and local CPR decoding
    /// (south and west negative: `--ref -33.9,151.2`).
    #[arg(long = "ref", value_name = "LAT,LON", allow_hyphen_values = true)]
    pub reference: Option<String>,
    /// Input file, or `-` for standard input.
    #[arg(default_value = "-")]
    pub input: PathBuf,
    /// Serial port to read instead of a file (e.g. /dev/ttyUSB0). vigil opens it in raw mode
    /// (8N1, no flow control, no echo, no line editing, no CR/LF translation), which `cat` on a
    /// port does not do and which binary streams need; it reads until Ctrl-C or the port goes
    /// away, and prints each message as it arrives.
    #[arg(long, value_name = "DEVICE", conflicts_with = "input")]
    pub port: Option<PathBuf>,
    /// Baud rate of `--port`, bit/s (default: the device's usual rate: BAHRS 115200, Watson
    /// 9600, VN-200 and TT-Multi-RF 921600).
    #[arg(long, requires = "port")]
    pub baud: Option<u32>,
}

/// Runs `vigil decode`.
pub fn run(args: &DecodeArgs) -> Result<()> {
    if args.device != Device::Ttmrf && args.format != TtFormat::Auto {
        bail!("--format applies to --device ttmrf only");
    }
    if args.device != Device::Ttmrf && args.reference.is_some() {
        bail!("--ref applies to --device ttmrf with a raw Mode S format only");
    }
    let mut input = match &args.port {
        Some(port) => open_port(port, args.baud.unwrap_or(default_baud(args.device)))?,
        None => open_input(&args.input)?,
    };
    let stdout = io::stdout();
    let mut out = JsonLines::new(stdout.lock());
    let result = match args.device {
        Device::Bahrs => bahrs::decode(&mut input, &mut out),
        Device::Watson => watson::decode(&mut input, &mut out),
        Device::Vn200 => vn200::decode(&mut input, &mut out),
        Device::Ttmrf => ttmrf::decode(args, &mut input, &mut out),
    };
    match result {
        Ok(summary) => {
            // A closed stdout (e.g. `| head`) is not an error of the input.
            if let Err(e) = out.flush()
                && e.kind() != io::ErrorKind::BrokenPipe
            {
                return Err(e).context("writing standard output");
            }
            eprintln!("{}", serde_json::to_string(&summary)?);
            Ok(())
        }
        Err(e) if is_broken_pipe(&e) => Ok(()),
        Err(e) => Err(e),
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.downcast_ref::<io::Error>()
        .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe)
}

fn open_input(path: &PathBuf) -> Result<Box<dyn Read>> {
    if path.as_os_str() == "-" {
        return Ok(Box::new(io::stdin().lock()));
    }
    let file = File::open(path).with_context(|| format!("cannot open input {}", path.display()))?;
    Ok(Box::new(file))
}

/// The device's usual baud rate (the rate the simulator and the default configuration use).
fn default_baud(device: Device) -> u32 {
    match device {
        Device::Bahrs => 115_200,
        Device::Watson => 9600,
        Device::Vn200 | Device::Ttmrf => 921_600,
    }
}

/// Opens serial port `path` at `baud` in raw mode (serialport's open: 8N1, no flow control,
/// raw termios).
fn open_port(path: &Path, baud: u32) -> Result<Box<dyn Read>> {
    let port = tokio_serial::new(path.to_string_lossy(), baud)
        .timeout(std::time::Duration::from_millis(200))
        .open()
        .with_context(|| format!("cannot open serial port {} at {baud} baud", path.display()))?;
    Ok(Box::new(PortInput(port)))
}

/// A serial port as an input stream: a read timeout means "nothing yet" (read again), and a
/// port that goes away (a USB adapter unplugged, a pseudo-terminal whose other side closed:
/// serialport reports the hang-up as BrokenPipe, a read as EIO) is the end of the input, with
/// the summary, not a silent exit.
struct PortInput(Box<dyn tokio_serial::SerialPort>);

impl Read for PortInput {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            match self.0.read(buf) {
                Err(e) if e.kind() == io::ErrorKind::TimedOut => continue,
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => return Ok(0),
                Err(e) if e.raw_os_error() == Some(5) => return Ok(0), // EIO
                other => return other,
            }
        }
    }
}

/// The summary written to stderr at the end of a decode.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Always "summary", so a reader can tell it from message lines.
    pub kind: &'static str,
    /// Device name as given on the command line.
    pub device: &'static str,
    /// The decoder's counters.
    #[serde(flatten)]
    pub stats: DecodeStats,
    /// Device-specific counters (may be null).
    #[serde(skip_serializing_if = "serde_json::Value::is_null")]
    pub extra: serde_json::Value,
}

impl Summary {
    /// A summary without device-specific counters.
    pub fn new(device: &'static str, stats: DecodeStats) -> Self {
        Self {
            kind: "summary",
            device,
            stats,
            extra: serde_json::Value::Null,
        }
    }
}

/// JSON Lines writer over a buffered output.
pub struct JsonLines<W: Write> {
    out: BufWriter<W>,
}

impl<W: Write> JsonLines<W> {
    fn new(out: W) -> Self {
        Self {
            out: BufWriter::with_capacity(1 << 16, out),
        }
    }

    /// Writes one value as one line, with vigil's JSON names (`vigil_service::json_names`: addresses as
    /// hex, codes as words, UTC beside GPS times).
    pub fn write<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<()> {
        let v = vigil_service::json_names::named_value(value)?;
        serde_json::to_writer(&mut self.out, &v)?;
        self.out.write_all(b"\n")?;
        Ok(())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

/// Feeds all of `input` through `decoder`, handing each message to `emit`, and returns the
/// decoder's final counters.
pub fn run_decoder<D, W, F>(
    decoder: &mut D,
    input: &mut dyn Read,
    out: &mut JsonLines<W>,
    mut emit: F,
) -> Result<DecodeStats>
where
    D: DeviceDecoder,
    W: Write,
    F: FnMut(D::Message, &mut JsonLines<W>) -> Result<()>,
{
    let mut buf = BytesMut::with_capacity(1 << 17);
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = match input.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e).context("reading input"),
        };
        buf.extend_from_slice(&chunk[..n]);
        while let Some(m) = decoder.decode(&mut buf) {
            emit(m, out)?;
        }
        // Each read's messages go out at once: a live port's reader sees them as they come
        // (a file is read 64 KiB at a time, so this costs it nothing).
        out.flush()?;
    }
    while let Some(m) = decoder.decode_eof(&mut buf) {
        emit(m, out)?;
    }
    Ok(*decoder.stats())
}

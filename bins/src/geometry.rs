//! `vigil geometry`: the DO-365 geometry calculator for integrators, and an independent way to
//! check vigil's geometry. JSON Lines in (`{"ownship": {...}, "intruder": {...}}`), one JSON object
//! out per input line, with vigil's JSON names (`vigil_service::json_names`): `lowc_interval_s` (the
//! interval [start, end] of predicted loss of well clear, s), `time_to_lowc_s` (its start, s, the
//! traffic payload's name) and `alert_level` as a word (`none`, `preventive`, `corrective`,
//! `warning`).

use std::io::{self, BufRead, BufWriter, Write};

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::{Deserialize, Serialize};
use vigil_fusion::geometry::{AircraftState, relative};
use vigil_fusion::units::{M_PER_FT, MPS_PER_FPM, MPS_PER_KT};

/// Arguments of `vigil geometry`.
#[derive(Debug, Args)]
pub struct GeometryArgs {
    /// Input file of JSON Lines, or `-` for standard input.
    #[arg(default_value = "-")]
    pub input: std::path::PathBuf,
}

/// One aircraft state as an integrator writes it.
#[derive(Debug, Deserialize)]
struct InState {
    lat_deg: f64,
    lon_deg: f64,
    alt_ft: f64,
    /// Track over ground, deg true.
    trk_deg: f64,
    gs_kt: f64,
    vs_fpm: f64,
}

#[derive(Debug, Deserialize)]
struct InLine {
    ownship: InState,
    intruder: InState,
}

#[derive(Debug, Serialize)]
struct OutLine {
    horizontal_distance_m: f64,
    vertical_separation_ft: Option<f64>,
    range_rate_mps: Option<f64>,
    tcpa_s: Option<f64>,
    hmd_at_cpa_m: Option<f64>,
    tau_mod_s: Option<f64>,
    well_clear_violated_now: bool,
    lowc_interval_s: Option<[f64; 2]>,
    time_to_lowc_s: Option<f64>,
    alert_level: u8,
}

impl InState {
    fn to_state(&self, which: &str) -> Result<AircraftState> {
        let fields = [
            ("lat_deg", self.lat_deg),
            ("lon_deg", self.lon_deg),
            ("alt_ft", self.alt_ft),
            ("trk_deg", self.trk_deg),
            ("gs_kt", self.gs_kt),
            ("vs_fpm", self.vs_fpm),
        ];
        if let Some((name, _)) = fields.iter().find(|(_, v)| !v.is_finite()) {
            bail!("{which}.{name} is not a finite number");
        }
        if !(-90.0..=90.0).contains(&self.lat_deg) {
            bail!("{which}.lat_deg {} is outside -90..90", self.lat_deg);
        }
        if !(-180.0..=360.0).contains(&self.lon_deg) {
            bail!("{which}.lon_deg {} is outside -180..360", self.lon_deg);
        }
        if self.gs_kt < 0.0 {
            bail!("{which}.gs_kt {} is negative", self.gs_kt);
        }
        Ok(AircraftState {
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_m: self.alt_ft * M_PER_FT,
            track_deg: self.trk_deg,
            ground_speed_mps: self.gs_kt * MPS_PER_KT,
            vertical_rate_mps: self.vs_fpm * MPS_PER_FPM,
        })
    }
}

/// Computes the geometry of one input line.
fn compute(line: &str) -> Result<OutLine> {
    let input: InLine = serde_json::from_str(line).context("not a {ownship, intruder} object")?;
    let own = input.ownship.to_state("ownship")?;
    let int = input.intruder.to_state("intruder")?;
    let g = relative(&own, &int).geometry();
    Ok(OutLine {
        horizontal_distance_m: g.horizontal_distance_m,
        // Every input here is known, so these are always present (`None` would print null).
        vertical_separation_ft: g.vertical_separation_m.map(|v| v / M_PER_FT),
        range_rate_mps: g.range_rate_mps,
        tcpa_s: g.tcpa_s,
        hmd_at_cpa_m: g.hmd_m,
        tau_mod_s: g.tau_mod_s,
        well_clear_violated_now: g.well_clear_violated_now,
        lowc_interval_s: g.loss_of_well_clear_interval_s.map(|(a, b)| [a, b]),
        time_to_lowc_s: g.loss_of_well_clear_interval_s.map(|(a, _)| a),
        alert_level: g.alert_level,
    })
}

/// Runs `vigil geometry`. A bad line gives `{"error": "..."}` in its place (so outputs stay
/// aligned with inputs) and a message on stderr; the exit code is then non-zero.
pub fn run(args: &GeometryArgs) -> Result<()> {
    let reader: Box<dyn BufRead> = if args.input.as_os_str() == "-" {
        Box::new(io::stdin().lock())
    } else {
        let f = std::fs::File::open(&args.input)
            .with_context(|| format!("cannot open input {}", args.input.display()))?;
        Box::new(io::BufReader::new(f))
    };
    let mut out = BufWriter::new(io::stdout().lock());
    let mut errors = 0usize;
    for (n, line) in reader.lines().enumerate() {
        let line = line.context("reading input")?;
        if line.trim().is_empty() {
            continue;
        }
        match compute(&line) {
            Ok(o) => {
                let v = vigil_service::json_names::named_value(&o)?;
                serde_json::to_writer(&mut out, &v)?
            }
            Err(e) => {
                errors += 1;
                let msg = format!("line {}: {e:#}", n + 1);
                eprintln!("vigil geometry: {msg}");
                serde_json::to_writer(&mut out, &serde_json::json!({ "error": msg }))?;
            }
        }
        out.write_all(b"\n")?;
    }
    out.flush()?;
    if errors > 0 {
        bail!("{errors} input line(s) could not be computed");
    }
    Ok(())
}

//! Statistics lines: `#S` system (manual 6.7.1), `#AS` ADS-B (7.2.3), `#FS` FLARM (8.2.2).
//!
//! ```text
//! #S:CPL,UPT,CRC
//! #AS:FPSS,FPSAC,CALIB,CRC
//! #FS:FPS,VFR,ERD,ERI,ERW,ERR,FTX        (documented without a CRC)
//! ```

use serde::Serialize;

use super::CsvError;
use super::fields::{Fields, push_opt};

/// `#S`: system statistics.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct SystemStats {
    /// CPL: CPU load, percent.
    pub cpu_load_pct: Option<f64>,
    /// UPT: time since the statistics were enabled. The manual gives no unit; kept as sent.
    pub uptime_raw: Option<f64>,
    /// Later fields before the CRC, verbatim.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_fields: Vec<String>,
}

impl SystemStats {
    /// Parses the data fields.
    pub fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        need(f, "S", 2)?;
        Ok(Self {
            cpu_load_pct: f.f64(0, "CPL")?,
            uptime_raw: f.f64(1, "UPT")?,
            extra_fields: f.rest(2),
        })
    }

    /// Appends the data fields.
    pub fn write_fields(&self, line: &mut String) {
        if let Some(v) = self.cpu_load_pct {
            line.push_str(&v.to_string());
        }
        push_opt(line, self.uptime_raw);
        push_extra(line, &self.extra_fields);
    }
}

/// `#AS`: ADS-B receiver statistics.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct AdsbStats {
    /// FPSS: Mode S frames received per second.
    pub mode_s_fps: Option<u32>,
    /// FPSAC: Mode A/C frames received per second.
    pub mode_ac_fps: Option<u32>,
    /// CALIB: real microcontroller frequency measured against the GNSS PPS, Hz (used to calibrate
    /// the raw-frame time stamps for multilateration).
    pub calib_hz: Option<f64>,
    /// Later fields before the CRC, verbatim.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_fields: Vec<String>,
}

impl AdsbStats {
    /// Parses the data fields.
    pub fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        need(f, "AS", 3)?;
        Ok(Self {
            mode_s_fps: f.uint(0, "FPSS")?,
            mode_ac_fps: f.uint(1, "FPSAC")?,
            calib_hz: f.f64(2, "CALIB")?,
            extra_fields: f.rest(3),
        })
    }

    /// Appends the data fields.
    pub fn write_fields(&self, line: &mut String) {
        if let Some(v) = self.mode_s_fps {
            line.push_str(&v.to_string());
        }
        push_opt(line, self.mode_ac_fps);
        push_opt(line, self.calib_hz);
        push_extra(line, &self.extra_fields);
    }
}

/// `#FS`: FLARM transceiver statistics.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct FlarmStats {
    /// FPS: frames received per second.
    pub rx_fps: Option<u32>,
    /// VFR: valid frames received per second.
    pub valid_fps: Option<u32>,
    /// ERD (developer counter).
    pub erd: Option<i64>,
    /// ERI (developer counter).
    pub eri: Option<i64>,
    /// ERW (developer counter).
    pub erw: Option<i64>,
    /// ERR (developer counter).
    pub err: Option<i64>,
    /// FTX: frames sent per second.
    pub tx_fps: Option<u32>,
    /// Later fields, verbatim.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_fields: Vec<String>,
}

impl FlarmStats {
    /// Parses the data fields.
    pub fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        need(f, "FS", 7)?;
        Ok(Self {
            rx_fps: f.uint(0, "FPS")?,
            valid_fps: f.uint(1, "VFR")?,
            erd: f.i64(2, "ERD")?,
            eri: f.i64(3, "ERI")?,
            erw: f.i64(4, "ERW")?,
            err: f.i64(5, "ERR")?,
            tx_fps: f.uint(6, "FTX")?,
            extra_fields: f.rest(7),
        })
    }

    /// Appends the data fields.
    pub fn write_fields(&self, line: &mut String) {
        if let Some(v) = self.rx_fps {
            line.push_str(&v.to_string());
        }
        push_opt(line, self.valid_fps);
        push_opt(line, self.erd);
        push_opt(line, self.eri);
        push_opt(line, self.erw);
        push_opt(line, self.err);
        push_opt(line, self.tx_fps);
        push_extra(line, &self.extra_fields);
    }
}

fn need(f: &Fields<'_>, tag: &'static str, n: usize) -> Result<(), CsvError> {
    if f.len() < n {
        return Err(CsvError::FieldCount {
            tag,
            expected: n,
            got: f.len(),
        });
    }
    Ok(())
}

fn push_extra(line: &mut String, extra: &[String]) {
    for x in extra {
        line.push(',');
        line.push_str(x);
    }
}

//! Field-level parsing and formatting shared by the CSV message types (manual 6.4).
//!
//! Every field may be empty, which means "unknown" (manual 7.2.1: "If data of any field of frame is
//! not available, then it is transmitted as empty"), so every parser returns `Option`. Spaces
//! around a value are tolerated (they never occur on the wire but cost nothing to accept).

use std::fmt::Write as _;

use serde::Serializer;

use super::CsvError;

/// The comma-separated data fields of one line (after `#TAG:`, before the CRC if any).
#[derive(Debug, Clone, Copy)]
pub struct Fields<'a> {
    fields: &'a [&'a str],
}

impl<'a> Fields<'a> {
    /// Wraps the split fields.
    pub fn new(fields: &'a [&'a str]) -> Self {
        Self { fields }
    }

    /// Number of fields.
    pub fn len(&self) -> usize {
        self.fields.len()
    }

    /// Whether there is no field.
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }

    /// The raw (trimmed) text of field `i`, empty when absent.
    pub fn raw(&self, i: usize) -> &'a str {
        self.fields
            .get(i)
            .map_or("", |s| s.trim_matches([' ', '\t']))
    }

    /// Fields from `start` on, as owned strings (the "future fields" the manual promises).
    pub fn rest(&self, start: usize) -> Vec<String> {
        self.fields
            .get(start..)
            .unwrap_or(&[])
            .iter()
            .map(|s| (*s).to_owned())
            .collect()
    }

    /// A decimal number, `None` when empty.
    pub fn f64(&self, i: usize, name: &'static str) -> Result<Option<f64>, CsvError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => Err(CsvError::field(name, s)),
        }
    }

    /// A decimal number that must lie in `lo..=hi`.
    pub fn f64_in(
        &self,
        i: usize,
        name: &'static str,
        lo: f64,
        hi: f64,
    ) -> Result<Option<f64>, CsvError> {
        match self.f64(i, name)? {
            Some(v) if !(lo..=hi).contains(&v) => Err(CsvError::field(name, self.raw(i))),
            v => Ok(v),
        }
    }

    /// A signed decimal integer, `None` when empty.
    pub fn i64(&self, i: usize, name: &'static str) -> Result<Option<i64>, CsvError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        s.parse::<i64>()
            .map(Some)
            .map_err(|_| CsvError::field(name, s))
    }

    /// An unsigned decimal integer that fits `T`, `None` when empty.
    pub fn uint<T: TryFrom<u64>>(
        &self,
        i: usize,
        name: &'static str,
    ) -> Result<Option<T>, CsvError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        let v = s.parse::<u64>().map_err(|_| CsvError::field(name, s))?;
        T::try_from(v)
            .map(Some)
            .map_err(|_| CsvError::field(name, s))
    }

    /// An unsigned integer in `0..=max`.
    pub fn u8_max(&self, i: usize, name: &'static str, max: u8) -> Result<Option<u8>, CsvError> {
        match self.uint::<u8>(i, name)? {
            Some(v) if v > max => Err(CsvError::field(name, self.raw(i))),
            v => Ok(v),
        }
    }

    /// A hexadecimal number of at most `digits` digits (no prefix), `None` when empty.
    pub fn hex(
        &self,
        i: usize,
        name: &'static str,
        digits: usize,
    ) -> Result<Option<u32>, CsvError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        parse_hex(s, digits)
            .map(Some)
            .ok_or_else(|| CsvError::field(name, s))
    }

    /// A 0/1 flag, `None` when empty.
    pub fn flag(&self, i: usize, name: &'static str) -> Result<Option<bool>, CsvError> {
        Ok(self.u8_max(i, name, 1)?.map(|v| v == 1))
    }

    /// A squawk: one to four octal digits, returned in "decimal form" (7700 for 7700).
    pub fn squawk(&self, i: usize, name: &'static str) -> Result<Option<u16>, CsvError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        parse_squawk(s)
            .map(Some)
            .ok_or_else(|| CsvError::field(name, s))
    }

    /// A text field (callsign), `None` when empty.
    pub fn text(&self, i: usize) -> Option<String> {
        let s = self.raw(i);
        (!s.is_empty()).then(|| s.to_owned())
    }
}

/// Parses 1..=`digits` hexadecimal digits (either case) into a `u32`.
pub fn parse_hex(s: &str, digits: usize) -> Option<u32> {
    if s.is_empty() || s.len() > digits.min(8) || !s.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(s, 16).ok()
}

/// Parses one to four octal digits into the squawk's decimal form.
pub fn parse_squawk(s: &str) -> Option<u16> {
    if s.is_empty() || s.len() > 4 || !s.bytes().all(|b| (b'0'..=b'7').contains(&b)) {
        return None;
    }
    s.parse().ok()
}

/// Appends `,value` (or `,` alone when unknown) to a line being built.
pub fn push_opt<T: std::fmt::Display>(line: &mut String, v: Option<T>) {
    line.push(',');
    if let Some(v) = v {
        let _ = write!(line, "{v}");
    }
}

/// Appends `,HEX` (upper case, no leading zeros) or `,` when unknown.
pub fn push_hex(line: &mut String, v: Option<u32>) {
    line.push(',');
    if let Some(v) = v {
        let _ = write!(line, "{v:X}");
    }
}

/// Serialises a 24-bit address as six upper-case hex digits (how every tool prints it).
pub fn ser_hex24<S: Serializer>(v: &u32, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{:06X}", v & 0xFF_FFFF))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_is_unknown_not_zero() {
        let raw = ["", " ", "0", "x"];
        let f = Fields::new(&raw);
        assert_eq!(f.f64(0, "a").unwrap(), None);
        assert_eq!(f.f64(1, "a").unwrap(), None);
        assert_eq!(f.f64(2, "a").unwrap(), Some(0.0));
        assert!(f.f64(3, "a").is_err());
        assert_eq!(f.f64(9, "absent").unwrap(), None);
    }

    #[test]
    fn hex_and_squawk_rules() {
        assert_eq!(parse_hex("3F00", 4), Some(0x3F00));
        assert_eq!(parse_hex("3f00", 4), Some(0x3F00));
        assert_eq!(parse_hex("13F00", 4), None);
        assert_eq!(parse_hex("+1", 4), None);
        assert_eq!(parse_squawk("7700"), Some(7700));
        assert_eq!(parse_squawk("0363"), Some(363));
        assert_eq!(parse_squawk("7800"), None, "8 is not an octal digit");
        assert_eq!(parse_squawk("77001"), None);
    }

    #[test]
    fn nan_and_inf_are_rejected() {
        let raw = ["NaN", "inf"];
        let f = Fields::new(&raw);
        assert!(f.f64(0, "a").is_err());
        assert!(f.f64(1, "a").is_err());
    }
}

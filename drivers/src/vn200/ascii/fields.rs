//! Comma-separated field reading and writing for ASCII sentences.

use super::AsciiError;
use crate::vn200::binary::{GnssFix, Lla, Quaternion, Ypr};
use crate::vn200::status::InsStatus;

/// A cursor over the comma-separated fields after a sentence header.
#[derive(Debug)]
pub(crate) struct Fields<'a> {
    header: &'a str,
    items: Vec<&'a str>,
    pos: usize,
}

impl<'a> Fields<'a> {
    /// Fields of `rest` (the text after the first comma), for sentence `header`.
    pub(crate) fn new(header: &'a str, rest: Option<&'a str>) -> Self {
        let items = rest.map(|r| r.split(',').collect()).unwrap_or_default();
        Self {
            header,
            items,
            pos: 0,
        }
    }

    /// An error naming this sentence.
    pub(crate) fn bad(&self, reason: &str) -> AsciiError {
        AsciiError::Malformed {
            header: self.header.to_string(),
            reason: format!("{reason} (field {})", self.pos),
        }
    }

    /// Whether no field is left.
    pub(crate) fn is_empty(&self) -> bool {
        self.pos >= self.items.len()
    }

    /// Fields left.
    pub(crate) fn remaining(&self) -> usize {
        self.items.len().saturating_sub(self.pos)
    }

    /// The next field, trimmed of spaces.
    pub(crate) fn next_str(&mut self) -> Result<&'a str, AsciiError> {
        let s = self
            .items
            .get(self.pos)
            .ok_or_else(|| self.bad("missing field"))?;
        self.pos += 1;
        Ok(s.trim())
    }

    /// The rest of the fields joined back with commas (for strings and unknown registers).
    pub(crate) fn rest(&mut self) -> Vec<&'a str> {
        let r = self.items.get(self.pos..).unwrap_or(&[]).to_vec();
        self.pos = self.items.len();
        r
    }

    fn parse<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, AsciiError> {
        let s = self.next_str()?;
        s.parse().map_err(|_| self.bad(what))
    }

    /// A decimal u8.
    pub(crate) fn u8(&mut self) -> Result<u8, AsciiError> {
        self.parse("u8")
    }
    /// A decimal u16.
    pub(crate) fn u16(&mut self) -> Result<u16, AsciiError> {
        self.parse("u16")
    }
    /// A decimal u32.
    pub(crate) fn u32(&mut self) -> Result<u32, AsciiError> {
        self.parse("u32")
    }
    /// A float.
    pub(crate) fn f32(&mut self) -> Result<f32, AsciiError> {
        self.parse("float")
    }
    /// A double.
    pub(crate) fn f64(&mut self) -> Result<f64, AsciiError> {
        self.parse("double")
    }
    /// A hexadecimal value of at most `digits` digits.
    pub(crate) fn hex(&mut self, digits: usize) -> Result<u32, AsciiError> {
        let s = self.next_str()?;
        parse_hex(s, digits).ok_or_else(|| self.bad("hex"))
    }

    /// Appended status (`S` + 4 hex) and count (`T` + u32) of async outputs (Register 30), in
    /// either order. The ICD's text puts the status first, its example (`...,T1162704,S0000*50`)
    /// the count first: both are accepted.
    pub(crate) fn appended(&mut self) -> Result<(Option<u16>, Option<u32>), AsciiError> {
        let (mut status, mut count) = (None, None);
        while let Some(s) = self.items.get(self.pos).map(|s| s.trim()) {
            if let Some(h) = s.strip_prefix('S')
                && status.is_none()
                && h.len() == 4
            {
                status = Some(u16::from_str_radix(h, 16).map_err(|_| self.bad("status"))?);
            } else if let Some(t) = s.strip_prefix('T')
                && count.is_none()
            {
                count = Some(t.parse().map_err(|_| self.bad("count"))?);
            } else {
                return Err(self.bad("unexpected appended field"));
            }
            self.pos += 1;
        }
        Ok((status, count))
    }

    /// Checks that every field was used.
    pub(crate) fn finish(&self) -> Result<(), AsciiError> {
        if self.is_empty() {
            Ok(())
        } else {
            Err(self.bad("too many fields"))
        }
    }
}

/// A value written as one or more comma-separated ASCII fields.
/// A field of 1 to `max_digits` (at most 8) hexadecimal digits and nothing else: no sign, no
/// space, which `from_str_radix` alone would take or refuse by value rather than by form.
pub(crate) fn parse_hex(s: &str, max_digits: usize) -> Option<u32> {
    if s.is_empty() || s.len() > max_digits || !s.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(s, 16).ok()
}

pub(crate) trait AsciiRecord: Sized {
    /// Reads the value's fields.
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError>;
    /// Appends the value's fields, each preceded by a comma.
    fn format(&self, out: &mut String);
}

impl AsciiRecord for f32 {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        f.f32()
    }
    fn format(&self, out: &mut String) {
        out.push_str(&format!(",{self}"));
    }
}

impl AsciiRecord for f64 {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        f.f64()
    }
    fn format(&self, out: &mut String) {
        out.push_str(&format!(",{self}"));
    }
}

macro_rules! ascii_uint {
    ($($t:ident),*) => {$(
        impl AsciiRecord for $t {
            fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
                f.$t()
            }
            fn format(&self, out: &mut String) {
                out.push_str(&format!(",{self}"));
            }
        }
    )*};
}
ascii_uint!(u8, u16, u32);

/// A fixed number of consecutive fields of one kind (vectors, matrices).
impl<T: AsciiRecord + Copy + Default, const N: usize> AsciiRecord for [T; N] {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        let mut a = [T::default(); N];
        for x in &mut a {
            *x = T::parse(f)?;
        }
        Ok(a)
    }
    fn format(&self, out: &mut String) {
        for x in self {
            x.format(out);
        }
    }
}

impl AsciiRecord for InsStatus {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(InsStatus(f.hex(4)? as u16))
    }
    fn format(&self, out: &mut String) {
        out.push_str(&format!(",{:04X}", self.0));
    }
}

impl AsciiRecord for GnssFix {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(GnssFix(f.u8()?))
    }
    fn format(&self, out: &mut String) {
        self.0.format(out);
    }
}

impl AsciiRecord for Ypr {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(Ypr {
            yaw_deg: f.f32()?,
            pitch_deg: f.f32()?,
            roll_deg: f.f32()?,
        })
    }
    fn format(&self, out: &mut String) {
        [self.yaw_deg, self.pitch_deg, self.roll_deg].format(out);
    }
}

impl AsciiRecord for Quaternion {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(Quaternion {
            x: f.f32()?,
            y: f.f32()?,
            z: f.f32()?,
            s: f.f32()?,
        })
    }
    fn format(&self, out: &mut String) {
        [self.x, self.y, self.z, self.s].format(out);
    }
}

impl AsciiRecord for Lla {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(Lla {
            lat_deg: f.f64()?,
            lon_deg: f.f64()?,
            alt_m: f.f64()?,
        })
    }
    fn format(&self, out: &mut String) {
        [self.lat_deg, self.lon_deg, self.alt_m].format(out);
    }
}

/// Declares a struct of ASCII fields, read and written in declaration order.
macro_rules! ascii_record {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty,)* }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
        pub struct $name { $($(#[$fm])* pub $f: $t,)* }

        impl $crate::vn200::ascii::fields::AsciiRecord for $name {
            fn parse(
                f: &mut $crate::vn200::ascii::fields::Fields<'_>,
            ) -> Result<Self, $crate::vn200::ascii::AsciiError> {
                Ok(Self { $($f: <$t as $crate::vn200::ascii::fields::AsciiRecord>::parse(f)?,)* })
            }
            fn format(&self, out: &mut String) {
                $($crate::vn200::ascii::fields::AsciiRecord::format(&self.$f, out);)*
            }
        }
    };
}
pub(crate) use ascii_record;

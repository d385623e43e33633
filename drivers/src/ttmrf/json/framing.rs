//! Finding one JSON object in a byte stream (manual 6.6: "Each message is encoded as separate
//! JSON object, without any excess whitespace").
//!
//! The framer matches braces outside strings. Because messages carry no excess whitespace, a raw
//! line feed can never occur inside a message (a JSON string cannot hold one unescaped): a line
//! feed inside an open object means the object was cut (lost bytes, a reset) and the framer gives
//! it up there, so one damaged message never swallows the next. A `\r\n` or `\n` right after the
//! closing brace belongs to the message. The scan position is kept between calls, so feeding a
//! large object byte by byte stays linear.

/// Largest JSON message accepted, bytes. A message with a few dozen targets is about 20 KiB.
pub const MAX_OBJECT: usize = 64 * 1024;

/// What the framer found at the front of a buffer that starts with `{`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObjectStep {
    /// A complete object: `object_len` bytes of JSON, `frame_len` including a trailing line end.
    Complete {
        /// Bytes of the object itself.
        object_len: usize,
        /// Bytes to consume (object plus a following `\r\n` / `\n`).
        frame_len: usize,
    },
    /// The object was cut by a line feed: drop `skip_len` bytes (through the line feed).
    Cut {
        /// Bytes to drop.
        skip_len: usize,
    },
    /// Longer than [`MAX_OBJECT`]: drop `skip_len` bytes and discard up to the next line feed.
    TooLong {
        /// Bytes to drop.
        skip_len: usize,
    },
    /// Need more bytes.
    NeedMore,
}

/// Incremental brace matcher.
#[derive(Debug, Clone, Default)]
pub struct ObjectFramer {
    pos: usize,
    depth: u32,
    in_string: bool,
    escape: bool,
    /// Set once the closing brace was seen at `pos - 1`.
    closed: bool,
    /// Accept line feeds inside an object (pretty-printed input such as the manual's examples).
    multiline: bool,
}

impl ObjectFramer {
    /// A framer for pretty-printed input: line feeds inside an object are whitespace. A cut
    /// object is then only given up at [`MAX_OBJECT`] bytes, so resynchronisation is slower;
    /// use it for files, not for the module's port.
    pub fn multiline() -> Self {
        Self {
            multiline: true,
            ..Self::default()
        }
    }

    /// Scans `buf` (which starts with `{`). With `eof`, a complete object needs no look-ahead.
    pub fn step(&mut self, buf: &[u8], eof: bool) -> ObjectStep {
        if !self.closed {
            let limit = buf.len().min(MAX_OBJECT);
            while self.pos < limit {
                let b = buf[self.pos];
                self.pos += 1;
                if b == b'\n' && !self.multiline {
                    let skip_len = self.pos;
                    self.reset();
                    return ObjectStep::Cut { skip_len };
                }
                if self.in_string {
                    if self.escape {
                        self.escape = false;
                    } else if b == b'\\' {
                        self.escape = true;
                    } else if b == b'"' {
                        self.in_string = false;
                    }
                    continue;
                }
                match b {
                    b'"' => self.in_string = true,
                    b'{' | b'[' => self.depth += 1,
                    b'}' | b']' => {
                        self.depth = self.depth.saturating_sub(1);
                        if self.depth == 0 {
                            self.closed = true;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            if !self.closed {
                if self.pos >= MAX_OBJECT {
                    let skip_len = self.pos;
                    self.reset();
                    return ObjectStep::TooLong { skip_len };
                }
                return ObjectStep::NeedMore;
            }
        }
        // Closed: take a directly following line end with the object.
        let end = self.pos;
        let frame_len = match (buf.get(end), buf.get(end + 1)) {
            (Some(b'\n'), _) => end + 1,
            (Some(b'\r'), Some(b'\n')) => end + 2,
            (Some(b'\r'), None) if !eof => return ObjectStep::NeedMore,
            (None, _) if !eof => return ObjectStep::NeedMore,
            _ => end,
        };
        self.reset();
        ObjectStep::Complete {
            object_len: end,
            frame_len,
        }
    }

    /// Forgets the scan state (after the caller consumed or skipped the object).
    pub fn reset(&mut self) {
        *self = Self {
            multiline: self.multiline,
            ..Self::default()
        };
    }

    /// Whether the framer is inside an object.
    pub fn in_progress(&self) -> bool {
        self.pos > 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn braces_inside_strings_do_not_count() {
        let mut f = ObjectFramer::default();
        let s = br#"{"a":"}{\"","b":[{}]}"#;
        assert_eq!(
            f.step(s, true),
            ObjectStep::Complete {
                object_len: s.len(),
                frame_len: s.len()
            }
        );
    }

    #[test]
    fn waits_for_the_line_end_and_takes_it() {
        let mut f = ObjectFramer::default();
        assert_eq!(f.step(b"{}", false), ObjectStep::NeedMore);
        assert_eq!(f.step(b"{}\r", false), ObjectStep::NeedMore);
        assert_eq!(
            f.step(b"{}\r\n{", false),
            ObjectStep::Complete {
                object_len: 2,
                frame_len: 4
            }
        );
        assert_eq!(
            f.step(b"{}{}", false),
            ObjectStep::Complete {
                object_len: 2,
                frame_len: 2
            }
        );
    }

    #[test]
    fn a_line_feed_cuts_an_open_object() {
        let mut f = ObjectFramer::default();
        assert_eq!(
            f.step(b"{\"a\":[1,\n{}", false),
            ObjectStep::Cut { skip_len: 9 }
        );
    }
}

//! A byte cursor for mesh files that mix ASCII and binary (Gmsh's binary
//! formats keep their section headers in ASCII): whitespace-separated
//! tokens with line numbers, and little-endian binary values, never
//! reading past the end and never allocating more than the file can hold.

use super::error::ImportError;

pub struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// 1-based line of `pos`.
    line: usize,
    file: &'a str,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], file: &'a str) -> Cursor<'a> {
        Cursor {
            bytes,
            pos: 0,
            line: 1,
            file,
        }
    }

    pub fn line(&self) -> usize {
        self.line
    }

    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    pub fn at_end(&mut self) -> bool {
        self.skip_space();
        self.pos >= self.bytes.len()
    }

    /// An error at the current line.
    pub fn error(&self, message: impl Into<String>) -> ImportError {
        ImportError::at(self.file, Some(self.line), message)
    }

    /// An error at the current byte offset (binary data has no lines).
    pub fn binary_error(&self, message: impl Into<String>) -> ImportError {
        ImportError::at(
            self.file,
            None,
            format!(
                "at byte {} (after line {}): {}",
                self.pos,
                self.line,
                message.into()
            ),
        )
    }

    fn skip_space(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if b == b'\n' {
                self.line += 1;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
    }

    /// The next whitespace-separated token, or `None` at the end.
    pub fn token(&mut self) -> Option<&'a str> {
        self.skip_space();
        let start = self.pos;
        while let Some(&b) = self.bytes.get(self.pos) {
            if b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
        if start == self.pos {
            return None;
        }
        // Non-UTF-8 bytes make a token no number parses from.
        Some(std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("\u{fffd}"))
    }

    /// The next token, which must exist; `what` names it in the error.
    pub fn expect_token(&mut self, what: &str) -> Result<&'a str, ImportError> {
        self.token()
            .ok_or_else(|| self.error(format!("the file ends where {what} should be (truncated?)")))
    }

    pub fn expect_keyword(&mut self, keyword: &str) -> Result<(), ImportError> {
        let t = self.expect_token(keyword)?;
        if t != keyword {
            return Err(self.error(format!("expected {keyword}, found {t:?}")));
        }
        Ok(())
    }

    /// A section marker (`$EndNodes`) where data was expected.
    fn early_end(&self, what: &str, t: &str) -> Option<ImportError> {
        t.starts_with('$').then(|| {
            self.error(format!(
                "found {t} where {what} should be: the section ended early (a wrong count?)"
            ))
        })
    }

    pub fn usize(&mut self, what: &str) -> Result<usize, ImportError> {
        let t = self.expect_token(what)?;
        if let Some(e) = self.early_end(what, t) {
            return Err(e);
        }
        t.parse::<usize>()
            .map_err(|_| self.error(format!("{what}: {t:?} is not a whole number")))
    }

    pub fn i64(&mut self, what: &str) -> Result<i64, ImportError> {
        let t = self.expect_token(what)?;
        if let Some(e) = self.early_end(what, t) {
            return Err(e);
        }
        t.parse::<i64>()
            .map_err(|_| self.error(format!("{what}: {t:?} is not a whole number")))
    }

    /// A finite floating-point number.
    pub fn f64(&mut self, what: &str) -> Result<f64, ImportError> {
        let t = self.expect_token(what)?;
        if let Some(e) = self.early_end(what, t) {
            return Err(e);
        }
        let v = t
            .parse::<f64>()
            .map_err(|_| self.error(format!("{what}: {t:?} is not a number")))?;
        if !v.is_finite() {
            return Err(self.error(format!("{what} is {t}: coordinates must be finite")));
        }
        Ok(v)
    }

    /// The rest of the current line (without its newline), consumed.
    pub fn rest_of_line(&mut self) -> &'a str {
        let start = self.pos;
        while let Some(&b) = self.bytes.get(self.pos) {
            if b == b'\n' {
                break;
            }
            self.pos += 1;
        }
        let text = std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("");
        if self.pos < self.bytes.len() {
            self.pos += 1;
            self.line += 1;
        }
        text.trim_end_matches('\r')
    }

    /// Skips to just after the next line that is exactly `marker` (e.g.
    /// `$EndNodes`), through ASCII or binary data.
    pub fn skip_past_line(&mut self, marker: &str) -> Result<(), ImportError> {
        let start_line = self.line;
        loop {
            if self.pos >= self.bytes.len() {
                return Err(ImportError::at(
                    self.file,
                    Some(start_line),
                    format!("no {marker} after this line (truncated?)"),
                ));
            }
            let line = self.rest_of_line();
            if line.trim() == marker {
                return Ok(());
            }
        }
    }

    /// Consumes the newline (`\n` or `\r\n`) that ends an ASCII header
    /// line before binary data, and nothing else: the binary data may
    /// begin with bytes that look like white space.
    pub fn end_of_header_line(&mut self) {
        if self.bytes.get(self.pos) == Some(&b'\r') {
            self.pos += 1;
        }
        if self.bytes.get(self.pos) == Some(&b'\n') {
            self.pos += 1;
            self.line += 1;
        }
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], ImportError> {
        if self.remaining() < n {
            return Err(self.binary_error(format!(
                "the file ends inside {what} ({n} bytes needed, {} left: truncated?)",
                self.remaining()
            )));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        for &b in s {
            if b == b'\n' {
                self.line += 1;
            }
        }
        self.pos += n;
        Ok(s)
    }

    pub fn bin_i32(&mut self, what: &str) -> Result<i32, ImportError> {
        let b = self.take(4, what)?;
        Ok(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub fn bin_u64(&mut self, what: &str) -> Result<u64, ImportError> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }

    pub fn bin_f64(&mut self, what: &str) -> Result<f64, ImportError> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        let v = f64::from_le_bytes(a);
        if !v.is_finite() {
            return Err(self.binary_error(format!("{what} is {v}: coordinates must be finite")));
        }
        Ok(v)
    }

    /// A count read from the file, checked against what the rest of the
    /// file can hold (`min_bytes` per item), so that a corrupt count is an
    /// error rather than a huge allocation.
    pub fn check_count(
        &self,
        count: usize,
        min_bytes: usize,
        what: &str,
    ) -> Result<usize, ImportError> {
        if count.saturating_mul(min_bytes.max(1)) > self.remaining() {
            return Err(self.error(format!(
                "{what}: {count} announced, but the file has only {} bytes left (wrong count or truncated file)",
                self.remaining()
            )));
        }
        Ok(count)
    }
}

/// Big-endian reads (VTK legacy binary).
impl Cursor<'_> {
    pub fn be_f64(&mut self, what: &str) -> Result<f64, ImportError> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(f64::from_be_bytes(a))
    }

    pub fn be_f32(&mut self, what: &str) -> Result<f64, ImportError> {
        let b = self.take(4, what)?;
        Ok(f64::from(f32::from_be_bytes([b[0], b[1], b[2], b[3]])))
    }

    pub fn be_i32(&mut self, what: &str) -> Result<i64, ImportError> {
        let b = self.take(4, what)?;
        Ok(i64::from(i32::from_be_bytes([b[0], b[1], b[2], b[3]])))
    }

    pub fn be_i64(&mut self, what: &str) -> Result<i64, ImportError> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(i64::from_be_bytes(a))
    }
}

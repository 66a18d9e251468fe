//! Where a CSV quote opens a field that is never closed. The `csv` crate reads such a field
//! to the end of the input without an error, so that a stray quote in a parameter table made
//! the rest of the file one value ("`0.08,85\n0.1,90` is not a number"), or silently its last
//! value. [`QuoteScan`] passes the bytes on to the reader unchanged and follows RFC 4180's
//! quoting as they go by, so that the table's reader can say which line opened the quote.

use std::io::Read;

/// A reader that notes, as its bytes pass, whether a quoted field is open and on which line
/// it opened.
pub(super) struct QuoteScan<R> {
    inner: R,
    line: usize,
    in_quote: bool,
    /// A quote met inside a quoted field: it closes the field unless another follows (`""`).
    quote_pending: bool,
    at_field_start: bool,
    opened_on: usize,
}

impl<R: Read> QuoteScan<R> {
    pub(super) fn new(inner: R) -> Self {
        QuoteScan {
            inner,
            line: 1,
            in_quote: false,
            quote_pending: false,
            at_field_start: true,
            opened_on: 0,
        }
    }

    fn scan(&mut self, bytes: &[u8]) {
        for &c in bytes {
            if self.in_quote {
                if self.quote_pending {
                    self.quote_pending = false;
                    if c == b'"' {
                        continue;
                    }
                    self.in_quote = false;
                } else {
                    match c {
                        b'"' => self.quote_pending = true,
                        b'\n' => self.line += 1,
                        _ => {}
                    }
                    continue;
                }
            }
            match c {
                b'"' if self.at_field_start => {
                    self.in_quote = true;
                    self.opened_on = self.line;
                    self.at_field_start = false;
                }
                b',' => self.at_field_start = true,
                b'\n' => {
                    self.line += 1;
                    self.at_field_start = true;
                }
                b'\r' => {}
                _ => self.at_field_start = false,
            }
        }
    }

    /// Reads the rest of the input and returns the line whose quote is never closed, if one
    /// is not.
    pub(super) fn unclosed(&mut self) -> Option<usize> {
        let mut buffer = [0u8; 8192];
        while let Ok(n) = self.read(&mut buffer) {
            if n == 0 {
                break;
            }
        }
        (self.in_quote && !self.quote_pending).then_some(self.opened_on)
    }
}

impl<R: Read> Read for QuoteScan<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.scan(&buf[..n]);
        Ok(n)
    }
}

/// The problem of a quote never closed.
pub(super) const UNCLOSED: &str = "a quote opens a field here that is never closed: the rest of \
     the file was read as this one value; close the quote (a quote inside a quoted field is \
     written twice, `\"\"`)";

#[cfg(test)]
mod tests {
    use super::*;

    fn unclosed(text: &str) -> Option<usize> {
        let mut scan = QuoteScan::new(text.as_bytes());
        scan.unclosed()
    }

    #[test]
    fn quotes_are_followed_as_rfc_4180_writes_them() {
        assert_eq!(unclosed("a,b\n1,2\n"), None);
        assert_eq!(unclosed("a,b\n\"1\",\"x \"\"y\"\"\nz\"\n"), None);
        assert_eq!(unclosed("a,b\n1,\"x\"\n"), None);
        // A quote inside an unquoted field is a character of it.
        assert_eq!(unclosed("a,b\n1,x\"y\n"), None);
        assert_eq!(unclosed("a,b\n\"0.08,85\n0.1,90\n"), Some(2));
        assert_eq!(unclosed("a,b\n1,2\n3,\"4\n"), Some(3));
        assert_eq!(unclosed("a,b\n1,\"x\"\"\n"), Some(2));
    }
}

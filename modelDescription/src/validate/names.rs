//! Name rules: C identifiers (modelIdentifier) and the `structured` variable naming
//! convention.

/// Whether `s` is a C identifier (as a modelIdentifier must be: it prefixes symbols and
/// names the shared library).
pub(super) fn is_c_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic())
        && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
}

/// A recursive-descent check of the `structured` naming convention (FMI 2.0, 2.2.9).
pub(super) struct NameParser<'a> {
    s: &'a [u8],
    pos: usize,
}

impl NameParser<'_> {
    pub(super) fn check(name: &str) -> Result<(), String> {
        let mut p = NameParser {
            s: name.as_bytes(),
            pos: 0,
        };
        p.name()?;
        if p.pos != p.s.len() {
            return Err(format!("unexpected character at position {}", p.pos + 1));
        }
        Ok(())
    }
    fn peek(&self) -> Option<u8> {
        self.s.get(self.pos).copied()
    }
    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }
    fn expect(&mut self, c: u8) -> Result<(), String> {
        if self.eat(c) {
            Ok(())
        } else {
            Err(format!(
                "expected '{}' at position {}",
                c as char,
                self.pos + 1
            ))
        }
    }
    fn name(&mut self) -> Result<(), String> {
        if self.s.starts_with(b"der(") {
            self.pos = 4;
            self.identifier()?;
            if self.eat(b',') {
                self.unsigned()?;
            }
            return self.expect(b')');
        }
        self.identifier()
    }
    fn identifier(&mut self) -> Result<(), String> {
        loop {
            self.bname()?;
            if self.peek() == Some(b'[') {
                self.array_indices()?;
            }
            if !self.eat(b'.') {
                return Ok(());
            }
        }
    }
    fn bname(&mut self) -> Result<(), String> {
        match self.peek() {
            Some(c) if c == b'_' || c.is_ascii_alphabetic() => {
                while matches!(self.peek(), Some(c) if c == b'_' || c.is_ascii_alphanumeric()) {
                    self.pos += 1;
                }
                Ok(())
            }
            Some(b'\'') => {
                self.pos += 1;
                let start = self.pos;
                loop {
                    match self.peek() {
                        None => return Err("unterminated quoted name".into()),
                        Some(b'\'') => break,
                        Some(b'\\') => {
                            self.pos += 1;
                            match self.peek() {
                                Some(
                                    b'\'' | b'"' | b'?' | b'\\' | b'a' | b'b' | b'f' | b'n' | b'r'
                                    | b't' | b'v',
                                ) => self.pos += 1,
                                _ => {
                                    return Err(format!(
                                        "illegal escape sequence at position {}",
                                        self.pos
                                    ))
                                }
                            }
                        }
                        Some(c)
                            if c.is_ascii_alphanumeric()
                                || b"_!#$%&()*+,-./:;<>=?@[]^{}|~ ".contains(&c) =>
                        {
                            self.pos += 1
                        }
                        Some(_) => {
                            return Err(format!(
                                "illegal character in quoted name at position {}",
                                self.pos + 1
                            ))
                        }
                    }
                }
                if self.pos == start {
                    return Err("empty quoted name".into());
                }
                self.pos += 1;
                Ok(())
            }
            _ => Err(format!(
                "expected a name (letter, '_' or quote) at position {}",
                self.pos + 1
            )),
        }
    }
    fn array_indices(&mut self) -> Result<(), String> {
        self.expect(b'[')?;
        self.unsigned()?;
        while self.eat(b',') {
            self.unsigned()?;
        }
        self.expect(b']')
    }
    fn unsigned(&mut self) -> Result<(), String> {
        let start = self.pos;
        while matches!(self.peek(), Some(c) if c.is_ascii_digit()) {
            self.pos += 1;
        }
        if self.pos == start {
            Err(format!(
                "expected an unsigned integer at position {}",
                self.pos + 1
            ))
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_names() {
        for ok in [
            "a",
            "a.b[1].c",
            "der(x)",
            "der(body.v,2)",
            "'quoted name!'",
            "a[1,2]",
            "'it\\'s'",
            "_x1",
        ] {
            assert!(NameParser::check(ok).is_ok(), "{ok}");
        }
        for bad in [
            "", "1a", "a..b", "a[", "a[]", "der(x", "a b", "''", "a[1, 2]", "'a\\q'",
        ] {
            assert!(NameParser::check(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn c_identifiers() {
        assert!(is_c_identifier("bridge_fmu"));
        assert!(is_c_identifier("_B2"));
        assert!(!is_c_identifier("2b"));
        assert!(!is_c_identifier("a-b"));
        assert!(!is_c_identifier(""));
    }
}

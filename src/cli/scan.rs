//! A hand-written scanner for the common shape of a batch line, the batch's fast path.
//!
//! It reads an object whose keys are plain strings and whose values are plain strings, JSON numbers,
//! or flat arrays of those, and hands back each value's raw text, exactly as serde_json's `RawValue`
//! would give it. Anything else (escapes, `null`, nested values, any syntax error) makes it give up
//! with `None`, and the caller reads the line with serde_json instead: the fast path never decides
//! an error, so every message stays serde_json's.

/// JSON's whitespace (not Unicode's).
fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r')
}

/// A cursor over a line's bytes.
struct Cursor<'a> {
    text: &'a str,
    at: usize,
}

impl<'a> Cursor<'a> {
    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.at).copied()
    }

    fn skip_space(&mut self) {
        let rest = &self.text.as_bytes()[self.at..];
        self.at += rest.iter().take_while(|&&b| is_space(b)).count();
    }

    /// Consumes `b` (after whitespace), or gives up.
    fn expect(&mut self, b: u8) -> Option<()> {
        self.skip_space();
        (self.peek()? == b).then(|| self.at += 1)
    }

    /// A string without escapes or control characters, quotes included.
    fn plain_string(&mut self) -> Option<&'a str> {
        let start = self.at;
        let bytes = self.text.as_bytes();
        if bytes.get(start) != Some(&b'"') {
            return None;
        }
        let len = bytes[start + 1..]
            .iter()
            .position(|&b| b == b'"' || b == b'\\' || b < 0x20)?;
        let end = start + 1 + len;
        if bytes[end] != b'"' {
            return None;
        }
        self.at = end + 1;
        Some(&self.text[start..self.at])
    }

    /// A JSON number: `-? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`.
    fn number(&mut self) -> Option<&'a str> {
        let start = self.at;
        if self.peek() == Some(b'-') {
            self.at += 1;
        }
        match self.peek()? {
            b'0' => self.at += 1,
            b'1'..=b'9' => self.digits(),
            _ => return None,
        }
        if self.peek() == Some(b'.') {
            self.at += 1;
            self.some_digits()?;
        }
        if matches!(self.peek(), Some(b'e' | b'E')) {
            self.at += 1;
            if matches!(self.peek(), Some(b'+' | b'-')) {
                self.at += 1;
            }
            self.some_digits()?;
        }
        Some(&self.text[start..self.at])
    }

    fn digits(&mut self) {
        let rest = &self.text.as_bytes()[self.at..];
        self.at += rest.iter().take_while(|b| b.is_ascii_digit()).count();
    }

    fn some_digits(&mut self) -> Option<()> {
        let start = self.at;
        self.digits();
        (self.at > start).then_some(())
    }

    /// A plain string or a number.
    fn scalar(&mut self) -> Option<&'a str> {
        self.skip_space();
        match self.peek()? {
            b'"' => self.plain_string(),
            _ => self.number(),
        }
    }

    /// A scalar, or a flat array of scalars.
    fn value(&mut self) -> Option<&'a str> {
        self.skip_space();
        if self.peek()? != b'[' {
            return self.scalar();
        }
        let start = self.at;
        self.list([b'[', b']'], |cursor| cursor.scalar().map(|_| ()))?;
        Some(&self.text[start..self.at])
    }

    /// `open`, then items (each read by `item`) separated by commas, then `close`; or gives up.
    fn list(
        &mut self,
        [open, close]: [u8; 2],
        mut item: impl FnMut(&mut Self) -> Option<()>,
    ) -> Option<()> {
        self.expect(open)?;
        self.skip_space();
        if self.peek()? != close {
            loop {
                item(self)?;
                self.skip_space();
                match self.peek()? {
                    b',' => self.at += 1,
                    b if b == close => break,
                    _ => return None,
                }
            }
        }
        self.at += 1;
        Some(())
    }
}

/// Scans a line holding one object, calling `field(key, raw value)` for each of its members in order
/// (the key without its quotes). `None` if the line is not of the simple shape (the caller then reads
/// it with serde_json, which also reports any error); `field` may have been called by then.
pub fn object<'a>(line: &'a str, mut field: impl FnMut(&'a str, &'a str)) -> Option<()> {
    let mut cursor = Cursor { text: line, at: 0 };
    cursor.list([b'{', b'}'], |cursor| {
        cursor.skip_space();
        let key = cursor.plain_string()?;
        cursor.expect(b':')?;
        let value = cursor.value()?;
        field(&key[1..key.len() - 1], value);
        Some(())
    })?;
    cursor.skip_space();
    (cursor.at == line.len()).then_some(())
}

/// The items of a flat array's raw text (as [`object`] hands it over): at most `N` of them, and how
/// many there are in all. `None` if it is not a flat array of plain strings and numbers.
pub fn array<const N: usize>(raw: &str) -> Option<([Option<&str>; N], usize)> {
    let mut items = [None; N];
    let mut count = 0;
    let mut cursor = Cursor { text: raw, at: 0 };
    cursor.list([b'[', b']'], |cursor| {
        let item = cursor.scalar()?;
        if count < N {
            items[count] = Some(item);
        }
        count += 1;
        Some(())
    })?;
    cursor.skip_space();
    (cursor.at == raw.len()).then_some((items, count))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::value::RawValue;

    /// The members as the fast path reads them, or `None` where it gives up.
    fn fast(line: &str) -> Option<Vec<(String, String)>> {
        let mut members = Vec::new();
        object(line, |k, v| members.push((k.to_string(), v.to_string())))?;
        Some(members)
    }

    /// The members as serde_json reads them.
    fn slow(line: &str) -> Option<Vec<(String, String)>> {
        let map: serde_json::Map<String, serde_json::Value> = serde_json::from_str(line).ok()?;
        let raw: std::collections::BTreeMap<String, &RawValue> = serde_json::from_str(line).ok()?;
        Some(
            map.keys()
                .map(|k| (k.clone(), raw[k].get().to_string()))
                .collect(),
        )
    }

    #[test]
    fn reads_what_serde_json_reads_or_gives_up() {
        let lines = [
            r#"{"kind":"triangle","a":[3,0,0],"b":"0,3,0","tmin":-1.5e-3}"#,
            r#" { "kind" : "segments" , "a1" : [ 1 , "2" ] } "#,
            r#"{}"#,
            r#"{"a":[]}"#,
            r#"{"a":[1,]}"#,
            r#"{"a":01}"#,
            r#"{"a":1.}"#,
            r#"{"a":-}"#,
            r#"{"a":1e}"#,
            r#"{"a":"x\"y"}"#,
            r#"{"a":null}"#,
            r#"{"a":[[1]]}"#,
            r#"{"a":1} x"#,
            r#"{"a":1,}"#,
            r#"{"a" 1}"#,
            "{\"a\":\"\u{1}\"}",
            r#"{"a":"é,1"}"#,
            r#"{"a":1"#,
            r#"{"#,
        ];
        for line in lines {
            if let Some(members) = fast(line) {
                let mut expected = slow(line).unwrap_or_else(|| panic!("{line}: serde refuses"));
                let mut members = members;
                members.sort();
                expected.sort();
                assert_eq!(members, expected, "{line}");
            }
        }
        assert!(fast(lines[0]).is_some() && fast(lines[1]).is_some());
        assert!(fast(r#"{"a":"x\"y"}"#).is_none());
        assert!(fast(r#"{"a":01}"#).is_none());
    }

    #[test]
    fn arrays_count_every_item() {
        let (items, count) = array::<2>(r#"[ 1 , "2", 3 ]"#).unwrap();
        assert_eq!((items, count), ([Some("1"), Some("\"2\"")], 3));
        assert!(array::<2>("[1,null]").is_none());
    }
}

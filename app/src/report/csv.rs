//! CSV fields as RFC 4180 has them (issue 37, item 15): a field holding a comma, a double
//! quote or a line break is written between double quotes, its quotes doubled; any other is
//! written as it is. A method named `lio (v2, tuned)` made rows a column longer than their
//! header before. The runs CSV a report reads is split the same way, so what a spreadsheet
//! saves (quoted names, a byte-order mark) reads back.

use std::borrow::Cow;

/// `s` as one CSV field.
pub fn field(s: &str) -> Cow<'_, str> {
    if s.contains([',', '"', '\n', '\r']) {
        Cow::Owned(format!("\"{}\"", s.replace('"', "\"\"")))
    } else {
        Cow::Borrowed(s)
    }
}

/// The fields of one CSV line (a record on one line: a quoted field may hold commas and
/// doubled quotes); `Err` says what is malformed.
pub fn split(line: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        let mut f = String::new();
        if chars.peek() == Some(&'"') {
            chars.next();
            loop {
                match chars.next() {
                    Some('"') if chars.peek() == Some(&'"') => {
                        chars.next();
                        f.push('"');
                    }
                    Some('"') => break,
                    Some(c) => f.push(c),
                    None => return Err("a quoted field is not closed".to_owned()),
                }
            }
            match chars.next() {
                None => {
                    out.push(f);
                    return Ok(out);
                }
                Some(',') => out.push(f),
                Some(c) => {
                    return Err(format!(
                        "`{c}` after a quoted field's closing quote (a quote inside a field is written twice)"
                    ));
                }
            }
        } else {
            loop {
                match chars.next() {
                    None => {
                        out.push(f);
                        return Ok(out);
                    }
                    Some(',') => break,
                    Some(c) => f.push(c),
                }
            }
            out.push(f);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_quoted_only_when_they_must_be_and_read_back() {
        for s in [
            "lio",
            "lio (v2, tuned)",
            "say \"hi\"",
            "a\nb",
            "",
            ",",
            "\"",
        ] {
            let line = format!("{},x,{}", field(s), field(s));
            assert_eq!(split(&line).unwrap(), [s, "x", s], "{line}");
        }
        assert_eq!(field("plain"), "plain");
        assert_eq!(field("a,b"), "\"a,b\"");
        assert_eq!(split("a,,b").unwrap(), ["a", "", "b"]);
        assert!(split("\"open,b").is_err());
        assert!(split("\"a\"b,c").is_err());
    }
}

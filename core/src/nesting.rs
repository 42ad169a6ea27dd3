//! Where a TOML file nests deeper than its reader allows, and what to say about it.
//!
//! The `toml` reader stops at 80 levels: a dotted key or table header of more than 80 names
//! (`a.a.a...`) and arrays or inline tables inside each other more than 80 deep. For a value
//! it says where ("cannot recurse further; max recursion depth met", with a span); for a key
//! it says only "recursion limit", with no place, so a 100,000-name key under `[extra]` was
//! reported at line 1, column 1, under whatever table the file began with. [`deep_key`]
//! finds the key by reading the text itself, and [`explain`] turns both messages into one
//! that says where, what the limit is and what to do.

/// How many names a dotted key or table header may have, and how deep arrays and inline
/// tables may nest: the `toml` reader's limit.
pub const TOML_LIMIT: usize = 80;

/// The first dotted key or table header with more than [`TOML_LIMIT`] names: its byte offset
/// in `source` and its number of names. Strings and comments are skipped, so a dotted word
/// inside a value is not taken for a key. Best effort (it reads tokens, not the grammar):
/// only called once the reader has already refused the file.
pub fn deep_key(source: &str) -> Option<(usize, usize)> {
    let b = source.as_bytes();
    let mut i = 0;
    // The chain being read (its start and names so far), and whether a dot ended it.
    let mut chain: Option<(usize, usize)> = None;
    let mut after_dot = false;
    while i < b.len() {
        let c = b[i];
        let part_end = match c {
            b'"' | b'\'' => Some(skip_string(b, i)),
            c if c.is_ascii_alphanumeric() || c == b'_' || c == b'-' => Some(
                b[i..]
                    .iter()
                    .position(|&x| !(x.is_ascii_alphanumeric() || x == b'_' || x == b'-'))
                    .map_or(b.len(), |p| i + p),
            ),
            _ => None,
        };
        match (part_end, c) {
            (Some(end), _) => {
                chain = match chain {
                    Some((start, names)) if after_dot => Some((start, names + 1)),
                    _ => Some((i, 1)),
                };
                after_dot = false;
                i = end;
            }
            (None, b'.') if chain.is_some() && !after_dot => {
                after_dot = true;
                i += 1;
            }
            (None, b' ' | b'\t') => i += 1,
            (None, b'#') => {
                chain = None;
                i = b[i..]
                    .iter()
                    .position(|&x| x == b'\n')
                    .map_or(b.len(), |p| i + p);
            }
            _ => {
                chain = None;
                i += 1;
            }
        }
        if let Some((start, names)) = chain {
            if names > TOML_LIMIT && !after_dot && !continues(b, i) {
                return Some((start, names));
            }
        }
    }
    None
}

/// Whether a dotted chain goes on after byte `i` (spaces, then a dot).
fn continues(b: &[u8], i: usize) -> bool {
    b[i..]
        .iter()
        .find(|&&x| x != b' ' && x != b'\t')
        .is_some_and(|&x| x == b'.')
}

/// The byte after the string starting at `i` (basic or literal, one line or three quotes).
fn skip_string(b: &[u8], i: usize) -> usize {
    let q = b[i];
    let triple = b.len() >= i + 3 && b[i + 1] == q && b[i + 2] == q;
    let mut j = i + if triple { 3 } else { 1 };
    while j < b.len() {
        match b[j] {
            b'\\' if q == b'"' => j += 2,
            b'\n' if !triple => return j,
            x if x == q && (!triple || b[j..].starts_with(&[q, q, q])) => {
                return j + if triple { 3 } else { 1 };
            }
            _ => j += 1,
        }
    }
    b.len()
}

/// The offset and message to report for a `toml` error: `offset` where the reader stopped
/// (`None` when it said nowhere), its `message`; a nesting limit is placed and explained.
pub fn explain(source: &str, offset: Option<usize>, message: &str) -> (usize, String) {
    let message = message.trim();
    if message.contains("max recursion depth") {
        return (
            offset.unwrap_or(0),
            format!(
                "arrays and inline tables nest more than {TOML_LIMIT} deep here (the TOML \
                 reader's limit), where no value subtgraph reads nests more than two deep \
                 (pillars = [[2, 4], 3]): shorten it"
            ),
        );
    }
    if offset.is_none() && message.contains("recursion limit") {
        if let Some((at, names)) = deep_key(source) {
            return (
                at,
                format!(
                    "a dotted key or table header of {names} names, where the TOML reader \
                     stops at {TOML_LIMIT} and no key subtgraph reads has more than four \
                     (topology.structure[0].pillars): shorten it"
                ),
            );
        }
    }
    (offset.unwrap_or(0), message.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(n: usize) -> String {
        vec!["a"; n].join(".")
    }

    #[test]
    fn the_first_key_past_the_limit_is_found() {
        let deep = key(100_000);
        let src = format!("[world]\nseed = 1.5\n[extra]\nb.c = 2\n{deep} = 1\nx = 3\n");
        let at = src.find(&deep).unwrap();
        assert_eq!(deep_key(&src), Some((at, 100_000)));
        // A header, with spaces around the dots and quoted names.
        let header = format!("[ {} . \"q.q\" . 'r' ]", key(90));
        let src = format!("[world]\nseed = 1\n{header}\n");
        assert_eq!(deep_key(&src), Some((src.find("a.").unwrap(), 92)));
        // Dots in strings and comments are no keys; a long chain in one is skipped.
        let src = format!(
            "s = \"{}\"\nt = '''\n{}\n'''\n# {}\nu.v = 1\n",
            key(200),
            key(200),
            key(200)
        );
        assert_eq!(deep_key(&src), None);
        let src = format!("{}{}\n", src, key(81));
        assert_eq!(deep_key(&src), Some((src.len() - 1 - key(81).len(), 81)));
    }

    #[test]
    fn the_readers_messages_are_placed_and_explained() {
        let deep = key(81);
        let src = format!("[world]\nseed = 1\n[route]\n{deep} = 1\n");
        let e = toml::from_str::<toml::Table>(&src).unwrap_err();
        assert!(e.span().is_none(), "the reader placed it after all: {e}");
        let (at, message) = explain(&src, e.span().map(|s| s.start), e.message());
        assert_eq!(at, src.find(&deep).unwrap());
        assert!(message.contains("81 names"), "{message}");
        // Just below the limit the reader accepts it.
        let src = format!("[route]\n{} = 1\n", key(80));
        assert!(toml::from_str::<toml::Table>(&src).is_ok());
        let src = format!("x = {}1{}\n", "[".repeat(100), "]".repeat(100));
        let e = toml::from_str::<toml::Table>(&src).unwrap_err();
        let (at, message) = explain(&src, e.span().map(|s| s.start), e.message());
        assert!(
            at > 0 && message.contains("nest more than 80 deep"),
            "{message}"
        );
    }
}

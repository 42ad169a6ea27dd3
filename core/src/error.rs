//! Errors of the core library. Each says what went wrong and what to change.

use std::borrow::Cow;
use std::fmt;
use std::sync::Arc;

/// The most characters of a user's value that a message quotes.
///
/// Messages quote what the user wrote so they can find it, but a value can be anything a file
/// holds (a 50 MB string as `route.type`): past this length a message shows its start and how
/// long it was, so an error stays readable and cheap to print.
pub const QUOTE_LIMIT: usize = 80;

/// A user's value as messages quote it: whole up to [`QUOTE_LIMIT`] characters, else its
/// first [`QUOTE_LIMIT`] characters, `...` and its length.
pub fn excerpt(value: &str) -> Cow<'_, str> {
    excerpt_to(value, QUOTE_LIMIT)
}

/// [`excerpt`] with another length: for lists of names, which may be longer than one value.
pub fn excerpt_to(value: &str, max: usize) -> Cow<'_, str> {
    match value.char_indices().nth(max) {
        None => Cow::Borrowed(value),
        Some((cut, _)) => Cow::Owned(format!(
            "{}... ({} bytes in all)",
            &value[..cut],
            value.len()
        )),
    }
}

/// A computed number as messages show it: at most six decimals, without trailing zeros.
///
/// The default level height of 12 m tiles is `0.8 * 12.0`, which is 9.600000000000001 in
/// binary and was shown so; this shows 9.6 (and 12.0 as 12). A value the user wrote is
/// shown the same way, so a message quotes it as it was written (short of seven decimals).
/// From 1e15 on a number is shown in scientific notation with at most seven significant
/// digits (`1e308`, `1.5e20`): a bound such as `f64::MAX` was printed as 309 digits.
pub fn number(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x.abs() >= 1e15 {
        let s = format!("{x:.6e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// A message with every quoted span (between `"`, `'` or backticks, as serde, TOML and our
/// own messages quote values) longer than [`QUOTE_LIMIT`] characters cut with [`excerpt`],
/// and any line still longer than ten times that cut in its middle. Applied where messages
/// are shown, so that no path that echoes a value can print it whole.
pub fn shorten(message: &str) -> Cow<'_, str> {
    if message.len() <= QUOTE_LIMIT {
        return Cow::Borrowed(message);
    }
    let mut out = String::with_capacity(message.len().min(4096));
    let mut rest = message;
    let mut changed = false;
    let word = |b: Option<&u8>| b.is_some_and(|b| b.is_ascii_alphanumeric());
    // An apostrophe inside a word (`machine's`) is not a quote: a quote opens after a
    // non-word character and closes before one.
    let opens = |s: &str, i: usize| {
        let b = s.as_bytes();
        b[i] != b'\'' || i == 0 || !word(b.get(i - 1))
    };
    while let Some(open) = rest
        .char_indices()
        .find(|&(i, c)| matches!(c, '"' | '\'' | '`') && opens(rest, i))
        .map(|(i, _)| i)
    {
        let q = rest.as_bytes()[open];
        let inner_start = open + 1;
        // The closing quote: the next unescaped one of the same kind.
        let bytes = rest.as_bytes();
        let mut close = None;
        let mut i = inner_start;
        while i < bytes.len() {
            match bytes[i] {
                b'\\' => i += 2,
                b if b == q && (q != b'\'' || !word(bytes.get(i + 1))) => {
                    close = Some(i);
                    break;
                }
                _ => i += 1,
            }
        }
        let Some(close) = close else { break };
        let inner = &rest[inner_start..close];
        out.push_str(&rest[..inner_start]);
        let cut = excerpt(inner);
        changed |= matches!(cut, Cow::Owned(_));
        out.push_str(&cut);
        out.push(char::from(q));
        rest = &rest[close + 1..];
    }
    out.push_str(rest);
    let long = QUOTE_LIMIT * 10;
    if out.lines().any(|l| l.len() > long) {
        changed = true;
        out = out
            .split('\n')
            .map(|l| match l.char_indices().nth(long) {
                None => l.to_owned(),
                Some((cut, _)) => format!("{}... ({} bytes in all)", &l[..cut], l.len()),
            })
            .collect::<Vec<_>>()
            .join("\n");
    }
    if changed {
        Cow::Owned(out)
    } else {
        Cow::Borrowed(message)
    }
}

/// The dotted key whose value or name starts at `offset` in a TOML document (best effort).
pub(crate) fn key_at(source: &str, offset: usize) -> String {
    let offset = offset.min(source.len());
    let line_start = source[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line_end = source[offset..]
        .find('\n')
        .map_or(source.len(), |i| offset + i);
    let line = &source[line_start..line_end];
    let key = line
        .split('=')
        .next()
        .filter(|_| line.contains('='))
        .map(|k| k.trim().trim_matches('"').to_owned())
        .unwrap_or_default();
    let section = source[..line_start]
        .lines()
        .rev()
        .find_map(|l| {
            let l = l.trim();
            l.starts_with('[')
                .then(|| l.trim_matches(|c| c == '[' || c == ']').trim().to_owned())
        })
        .unwrap_or_default();
    match (section.is_empty(), key.is_empty()) {
        (_, true) if line.trim_start().starts_with('[') => line
            .trim()
            .trim_matches(|c| c == '[' || c == ']')
            .to_owned(),
        (true, _) => key,
        (false, true) => section,
        (false, false) => format!("{section}.{key}"),
    }
}

/// A place in a pipeline file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file name as the user gave it (or `<preset NAME>`).
    pub file: Arc<str>,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
}

impl Location {
    /// The location of byte `offset` in `source`.
    pub fn of_offset(file: &Arc<str>, source: &str, offset: usize) -> Location {
        let offset = offset.min(source.len());
        let before = &source[..offset];
        let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = source[line_start..offset].chars().count() + 1;
        Location {
            file: file.clone(),
            line,
            column,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// `key: ` for a message about a key, nothing for one about the whole file.
fn key_prefix(key: &str) -> String {
    if key.is_empty() {
        String::new()
    } else {
        format!("{}: ", excerpt(key))
    }
}

/// A pipeline configuration that cannot be used as written.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{location}: {}{}", key_prefix(.key), shorten(.message))]
pub struct ConfigError {
    /// Where in the file.
    pub location: Location,
    /// The key, dotted from the top (`world.min_length`, `route.amplitude`).
    pub key: String,
    /// What is wrong and what to write instead.
    pub message: String,
}

/// Why a world could not be generated.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The pipeline file is malformed or names something unknown.
    #[error(transparent)]
    Config(#[from] ConfigError),

    /// A requested structure did not fit, or its routes could not be laid, within the retry
    /// bound. Use a larger grid (`world.min_length`, `world.rows`/`world.cols`), fewer
    /// structures, or `exact = false`.
    #[error(
        "level {level}: {what} (after {attempts} attempts with derived seeds on a {rows} x {cols} grid). \
         To fix: {advice}"
    )]
    Unsatisfiable {
        /// Level index.
        level: usize,
        /// Which constraint failed on the last attempt.
        what: String,
        /// How many attempts were made.
        attempts: u32,
        /// Grid rows.
        rows: usize,
        /// Grid columns.
        cols: usize,
        /// What to change.
        advice: String,
    },

    /// An imported occupancy grid has a shape, type or value the tool cannot read.
    #[error("{source_name}: {}", shorten(.message))]
    Import {
        /// The file or array name.
        source_name: String,
        /// What is wrong and what the tool accepts.
        message: String,
    },

    /// The world would need more memory than the budget allows (see [`crate::budget`]): the
    /// message gives the estimate and what to change.
    #[error("{0}")]
    TooLarge(crate::budget::OverBudget),

    /// A component (route descriptor, shape, tile set, exporter) failed.
    #[error("{component} '{}': {}", excerpt(.name), shorten(.message))]
    Component {
        /// What kind of component.
        component: &'static str,
        /// Its `type` name.
        name: String,
        /// What went wrong.
        message: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_shown_rounded_without_trailing_zeros() {
        for (x, shown) in [
            (0.8 * 12.0, "9.6"),
            (12.0, "12"),
            (0.125, "0.125"),
            (-0.0000001, "0"),
            (1e14, "100000000000000"),
            (1e20, "1e20"),
            (-1.5e20, "-1.5e20"),
            (f64::MAX, "1.797693e308"),
            (1e308, "1e308"),
            (f64::INFINITY, "inf"),
            (2.0 / 3.0, "0.666667"),
        ] {
            assert_eq!(number(x), shown, "{x}");
        }
    }

    #[test]
    fn long_values_are_cut_where_messages_quote_them() {
        assert_eq!(excerpt("short"), "short");
        let huge = "x".repeat(50_000_000);
        let e = excerpt(&huge);
        assert!(e.len() < 200 && e.contains("50000000 bytes"), "{e}");
        let m = format!("unknown route descriptor '{huge}' (known: linear, sine)");
        let s = shorten(&m);
        assert!(s.len() < 200, "{} bytes", s.len());
        assert!(s.ends_with("(known: linear, sine)"), "{s}");
        let m = format!("invalid type: string \"{huge}\\\"{huge}\", expected f64");
        let s = shorten(&m);
        assert!(s.len() < 300 && s.ends_with(", expected f64"), "{s}");
        // Unquoted, still cut.
        let m = format!("bad shape ({huge}, 4)");
        assert!(shorten(&m).len() < 1000);
        // Apostrophes in words are not quotes.
        let m = format!(
            "tile set 'cave': this world's meshes need {}; raise --max-memory (this machine's 25 GB)",
            "y".repeat(200)
        );
        assert_eq!(shorten(&m), m);
        // Short messages are untouched.
        assert_eq!(shorten("key: unknown field `x`"), "key: unknown field `x`");
        // Multibyte characters are cut on a character boundary.
        let wide = "é".repeat(100);
        assert!(excerpt(&wide).starts_with(&"é".repeat(80)));
        let c = ConfigError {
            location: Location {
                file: Arc::from("p.toml"),
                line: 1,
                column: 1,
            },
            key: huge.clone(),
            message: format!("unknown field `{huge}`"),
        };
        assert!(c.to_string().len() < 400);
    }
}

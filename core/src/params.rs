//! A component's table from the pipeline file (`[route]`, `[tileset]`, `[[export]]`, ...),
//! keeping where each key was written so that a factory's complaint points at the right line.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::error::{ConfigError, Location};

/// A component section: its `type` name and its other keys.
#[derive(Clone, Debug, Default)]
pub struct ComponentSpec {
    /// The `type` key: the registered name of the component.
    pub type_name: String,
    /// The other keys.
    pub params: Params,
}

impl ComponentSpec {
    /// A spec with no parameters, for defaults and the command line.
    pub fn named(type_name: &str) -> Self {
        Self {
            type_name: type_name.to_owned(),
            params: Params::default(),
        }
    }
}

/// The keys of a component section other than `type`.
#[derive(Clone, Debug, Default)]
pub struct Params {
    values: BTreeMap<String, toml::Value>,
    spans: BTreeMap<String, std::ops::Range<usize>>,
    locations: BTreeMap<String, Location>,
    section: Option<Location>,
    section_span: Option<std::ops::Range<usize>>,
    /// Dotted name of the section (`route`, `export[1]`), for messages.
    pub section_name: String,
}

impl Params {
    /// Parameters from plain values (no file locations), for code that builds pipelines.
    pub fn from_table(section_name: &str, table: toml::Table) -> Self {
        Self {
            values: table.into_iter().collect(),
            section_name: section_name.to_owned(),
            ..Self::default()
        }
    }

    /// The values as a TOML table.
    pub fn to_table(&self) -> toml::Table {
        self.values
            .iter()
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect()
    }

    /// Whether there are no parameters.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// One raw value.
    pub fn raw(&self, key: &str) -> Option<&toml::Value> {
        self.values.get(key)
    }

    /// Replaces a value, keeping where it was written.
    pub fn set(&mut self, key: &str, value: toml::Value) {
        self.values.insert(key.to_owned(), value);
    }

    /// Removes a key the host consumes itself (like a structure's `count`).
    pub fn take(&mut self, key: &str) -> Option<(toml::Value, Option<Location>)> {
        self.spans.remove(key);
        let loc = self.locations.remove(key);
        self.values.remove(key).map(|v| (v, loc))
    }

    /// Resolves byte spans to lines and columns once the source text is known.
    pub(crate) fn locate(&mut self, file: &Arc<str>, source: &str, section_name: String) {
        self.section_name = section_name;
        for (k, span) in &self.spans {
            self.locations
                .insert(k.clone(), Location::of_offset(file, source, span.start));
        }
        if let Some(span) = &self.section_span {
            self.section = Some(Location::of_offset(file, source, span.start));
        }
    }

    /// A path written in the pipeline file, relative to that file's folder (absolute paths as
    /// they are).
    pub fn resolve_path(&self, written: &str) -> std::path::PathBuf {
        let p = std::path::Path::new(written);
        if p.is_absolute() {
            return p.to_owned();
        }
        let file = self
            .section
            .as_ref()
            .map(|l| l.file.to_string())
            .unwrap_or_default();
        match std::path::Path::new(&file).parent() {
            Some(dir) if !file.starts_with('<') => dir.join(p),
            _ => p.to_owned(),
        }
    }

    /// An error about `key` (or about the whole section when `key` is not present).
    pub fn error(&self, key: &str, message: impl Into<String>) -> ConfigError {
        // A key inside a value (`pillars[0]`, `shape.depth`) is where its top-level key is.
        let top = key.split(['.', '[']).next().unwrap_or(key);
        let location = self
            .locations
            .get(key)
            .or_else(|| self.locations.get(top))
            .or(self.section.as_ref())
            .cloned()
            .unwrap_or_else(|| Location {
                file: Arc::from("<pipeline>"),
                line: 0,
                column: 0,
            });
        let key = match (self.section_name.is_empty(), key.is_empty()) {
            (true, _) => key.to_owned(),
            (false, true) => self.section_name.clone(),
            (false, false) => format!("{}.{key}", self.section_name),
        };
        ConfigError {
            location,
            key,
            message: message.into(),
        }
    }

    /// Deserializes all parameters into `T`. Put `#[serde(deny_unknown_fields)]` on `T` so a
    /// misspelt key is an error, not a silently ignored setting.
    ///
    /// The key an error is about comes from where deserialization stopped
    /// (`serde_path_to_error`): `amplitude` for a value of the wrong type, `shape.depth` inside a
    /// nested table, the misspelt key itself for an unknown one. Only a missing key has no
    /// place to stop at: serde reports it at its table, naming the field in its message
    /// (`missing field `x``, `serde::de::Error::missing_field`), which is appended.
    pub fn deserialize<T: DeserializeOwned>(&self) -> Result<T, ConfigError> {
        let value = toml::Value::Table(self.to_table());
        serde_path_to_error::deserialize(value).map_err(|e| {
            // The reader's message alone: its `Display` adds "in `key`" on a line of its own,
            // which the key in front of the message already says.
            let message = e.inner().message().trim().to_owned();
            let mut key: Vec<String> = Vec::new();
            for segment in e.path().iter() {
                match segment {
                    serde_path_to_error::Segment::Map { key: k }
                    | serde_path_to_error::Segment::Enum { variant: k } => key.push(k.clone()),
                    serde_path_to_error::Segment::Seq { index } => match key.last_mut() {
                        Some(last) => last.push_str(&format!("[{index}]")),
                        None => key.push(format!("[{index}]")),
                    },
                    serde_path_to_error::Segment::Unknown => {}
                }
            }
            if let Some(field) = message
                .lines()
                .next()
                .and_then(|m| m.strip_prefix("missing field `"))
                .and_then(|m| m.strip_suffix('`'))
            {
                key.push(field.to_owned());
            }
            self.error(&key.join("."), message)
        })
    }

    /// Fails on the first key not in `known`, listing the known ones.
    pub fn expect_known(&self, known: &[&str]) -> Result<(), ConfigError> {
        match self.values.keys().find(|k| !known.contains(&k.as_str())) {
            None => Ok(()),
            Some(k) => Err(self.error(
                k,
                format!(
                    "unknown key `{k}`; this component takes: {}",
                    known.join(", ")
                ),
            )),
        }
    }

    /// Fails when any parameter is present: for components that take none.
    pub fn expect_none(&self) -> Result<(), ConfigError> {
        match self.values.keys().next() {
            None => Ok(()),
            Some(k) => Err(self.error(k, "this component takes no parameters; remove the key")),
        }
    }
}

impl<'de> Deserialize<'de> for ComponentSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let table: toml::Spanned<BTreeMap<toml::Spanned<String>, toml::Spanned<toml::Value>>> =
            toml::Spanned::deserialize(d)?;
        let section_span = table.span();
        let mut type_name = None;
        let mut params = Params {
            section_span: Some(section_span),
            ..Params::default()
        };
        for (k, v) in table.into_inner() {
            let key_span = k.span();
            let key = k.into_inner();
            if key == "type" {
                match v.into_inner() {
                    toml::Value::String(s) => type_name = Some(s),
                    _ => {
                        return Err(D::Error::custom(
                            "`type` must be a string naming a component",
                        ));
                    }
                }
            } else {
                params.spans.insert(key.clone(), key_span);
                params.values.insert(key, v.into_inner());
            }
        }
        let type_name = type_name.ok_or_else(|| {
            D::Error::custom("missing `type`: name the component, e.g. type = \"parabolic\"")
        })?;
        Ok(ComponentSpec { type_name, params })
    }
}

impl Serialize for ComponentSpec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut table = toml::Table::new();
        table.insert("type".into(), toml::Value::String(self.type_name.clone()));
        table.extend(self.params.to_table());
        table.serialize(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct P {
        amplitude: f64,
    }

    #[derive(Debug, Deserialize)]
    struct Doc {
        route: ComponentSpec,
    }

    #[test]
    fn misspelt_keys_point_at_their_line() {
        let src = "[route]\ntype = \"sine\"\n\namplitud = 3.0\n";
        let mut doc: Doc = toml::from_str(src).unwrap();
        doc.route
            .params
            .locate(&Arc::from("p.toml"), src, "route".into());
        assert_eq!(doc.route.type_name, "sine");
        let err = doc.route.params.deserialize::<P>().unwrap_err();
        assert_eq!(err.location.line, 4, "{err}");
        assert_eq!(err.key, "route.amplitud");
        assert!(err.message.contains("unknown field"), "{err}");
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Wave {
        wavelength: f64,
        #[serde(default)]
        amplitude: f64,
        #[serde(default)]
        shape: Option<Inner>,
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Inner {
        depth: u32,
    }

    fn route(src: &str) -> Params {
        let mut doc: Doc = toml::from_str(src).unwrap();
        doc.route
            .params
            .locate(&Arc::from("p.toml"), src, "route".into());
        doc.route.params
    }

    #[test]
    fn every_parameter_error_names_its_key() {
        // A missing field is named, not left as `route.` (issue 10, item 13).
        let err = route("[route]\ntype = \"meander\"\n")
            .deserialize::<Wave>()
            .unwrap_err();
        assert_eq!(err.key, "route.wavelength", "{err}");
        assert!(err.message.contains("missing field"), "{err}");
        // A value of the wrong type names its key and points at its line.
        let err = route("[route]\ntype = \"meander\"\nwavelength = 6.0\namplitude = \"big\"\n")
            .deserialize::<Wave>()
            .unwrap_err();
        assert_eq!(err.key, "route.amplitude", "{err}");
        assert_eq!(err.location.line, 4, "{err}");
        // Inside a nested table too.
        let err = route("[route]\ntype = \"m\"\nwavelength = 6.0\nshape = { depth = -1 }\n")
            .deserialize::<Wave>()
            .unwrap_err();
        assert_eq!(err.key, "route.shape.depth", "{err}");
        assert_eq!(err.location.line, 4, "where `shape` is: {err}");
        assert!(!err.message.contains('\n'), "one line: {err}");
        let err = route("[route]\ntype = \"m\"\nwavelength = 6.0\nshape = {}\n")
            .deserialize::<Wave>()
            .unwrap_err();
        assert_eq!(err.key, "route.shape.depth", "{err}");
        // Never a dangling dot, even when no key can be told.
        let p = Params::from_table("route", toml::Table::new());
        assert_eq!(p.error("", "x").key, "route");
    }

    #[test]
    fn a_missing_type_is_refused() {
        let err = toml::from_str::<Doc>("[route]\namplitude = 1.0\n").unwrap_err();
        assert!(err.to_string().contains("missing `type`"), "{err}");
    }
}

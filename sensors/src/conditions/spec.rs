//! A conditions file (`[[conditions]]` tables) read and checked: every key known, every
//! number within what the physics is written for, every place in the world's graph. Each
//! error names the table and says what to write instead.

use serde::Serialize;

use super::place::Place;
use super::{Kind, dust, fog, medium::Particles, wet_rock};
use crate::error::SenseError;
use crate::graph::RouteGraph;

/// A condition's type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ConditionKind {
    /// Dust in the air.
    Dust,
    /// A fog bank.
    Fog,
    /// A mist bank (finer droplets).
    Mist,
    /// Wet, darker rock, with puddles on its floor.
    WetRock,
    /// Water dripping from the roof.
    Drips,
}

impl ConditionKind {
    /// The debug field's value for its returns.
    pub fn return_kind(self) -> Kind {
        match self {
            ConditionKind::Dust => Kind::Dust,
            ConditionKind::Fog | ConditionKind::Mist => Kind::Fog,
            ConditionKind::WetRock => Kind::Wet,
            ConditionKind::Drips => Kind::Drip,
        }
    }
}

/// One `[[conditions]]` table, every value resolved (defaults filled in).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Condition {
    /// Its type.
    #[serde(rename = "type")]
    pub kind: ConditionKind,
    /// Where.
    #[serde(serialize_with = "place_name")]
    pub at: Place,
    /// An edge's or node's reach, metres.
    pub radius_m: f64,
    /// Particles a cubic metre, mg (dust, fog, mist).
    pub density_mg_m3: f64,
    /// Particle radius, micrometres (dust, fog, mist).
    pub particle_um: f64,
    /// Wet rock's reflectivity factor.
    pub reflectance_factor: f64,
    /// The share of a wet floor under water.
    pub puddles: f64,
    /// Drip lines per 10 m of passage.
    pub lines_per_10m: f64,
    /// Seconds between a line's drops.
    pub interval_s: f64,
}

fn place_name<S: serde::Serializer>(p: &Place, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&p.name())
}

impl Condition {
    /// Its particles, for the kinds that have them.
    pub fn particles(&self) -> Option<Particles> {
        let (g_cm3, ratio) = match self.kind {
            ConditionKind::Dust => (dust::G_CM3, dust::LIDAR_RATIO_SR),
            ConditionKind::Fog | ConditionKind::Mist => (fog::G_CM3, fog::lidar_ratio_sr()),
            _ => return None,
        };
        Some(Particles::of_mass(
            self.density_mg_m3,
            self.particle_um,
            g_cm3,
            ratio,
        ))
    }
}

/// The conditions of a sequence.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Conditions {
    /// In the file's order.
    pub list: Vec<Condition>,
}

/// The keys each type takes (besides `type`, `at`).
fn keys(kind: ConditionKind) -> &'static [&'static str] {
    match kind {
        ConditionKind::Dust | ConditionKind::Fog | ConditionKind::Mist => {
            &["density_mg_m3", "particle_um", "radius_m"]
        }
        ConditionKind::WetRock => &["reflectance_factor", "puddles", "radius_m"],
        ConditionKind::Drips => &["lines_per_10m", "interval_s", "radius_m"],
    }
}

impl Conditions {
    /// Reads a conditions file's text (`path` names it in errors) and checks it against the
    /// world's `graph`.
    pub fn parse(text: &str, path: &str, graph: &RouteGraph) -> Result<Conditions, SenseError> {
        let bad = |why: String| SenseError::BadConditions {
            path: path.to_owned(),
            why,
        };
        let table: toml::Table = toml::from_str(text).map_err(|e| bad(e.message().to_owned()))?;
        if let Some(k) = table.keys().find(|k| *k != "conditions") {
            return Err(bad(format!(
                "unknown key '{k}': the file holds [[conditions]] tables only"
            )));
        }
        let Some(items) = table.get("conditions") else {
            return Err(bad(
                "no [[conditions]] table: add one, or pass --conditions none for clear air".into(),
            ));
        };
        let items = items
            .as_array()
            .ok_or_else(|| bad("'conditions' must be [[conditions]] tables".into()))?;
        let mut list = Vec::new();
        for (i, item) in items.iter().enumerate() {
            let c =
                one(item, graph).map_err(|why| bad(format!("[[conditions]] {}: {why}", i + 1)))?;
            list.push(c);
        }
        Ok(Conditions { list })
    }
}

/// One table, checked.
fn one(item: &toml::Value, graph: &RouteGraph) -> Result<Condition, String> {
    let t = item
        .as_table()
        .ok_or_else(|| "is not a table".to_string())?;
    let kind = match t.get("type").and_then(|v| v.as_str()) {
        Some("dust") => ConditionKind::Dust,
        Some("fog") => ConditionKind::Fog,
        Some("mist") => ConditionKind::Mist,
        Some("wet-rock") => ConditionKind::WetRock,
        Some("drips") => ConditionKind::Drips,
        Some(other) => {
            return Err(format!(
                "type '{other}' is not one of dust, fog, mist, wet-rock, drips"
            ));
        }
        None => {
            return Err(
                "has no type: write type = \"dust\" (or fog, mist, wet-rock, drips)".into(),
            );
        }
    };
    let allowed = keys(kind);
    for k in t.keys() {
        if k != "type" && k != "at" && !allowed.contains(&k.as_str()) {
            return Err(format!(
                "unknown key '{k}' for {kind:?}: its keys are type, at, {}",
                allowed.join(", ")
            ));
        }
    }
    let at = t.get("at").and_then(|v| v.as_str()).ok_or_else(|| {
        "has no at: write at = \"route\", \"platform\", \"edge N\", \"node N\" or \"level N\""
            .to_string()
    })?;
    let at = Place::parse(at)?;
    at.check(graph)?;
    if at == Place::Platform && kind != ConditionKind::Dust {
        return Err(format!(
            "only dust is raised by the platform: put {kind:?} at \"route\", \"edge N\", \"node N\" or \"level N\""
        ));
    }
    let number = |key: &str, default: Option<f64>, lo: f64, hi: f64| -> Result<f64, String> {
        let v = match t.get(key) {
            None => default.ok_or_else(|| format!("needs {key}"))?,
            Some(v) => v
                .as_float()
                .or_else(|| v.as_integer().map(|i| i as f64))
                .ok_or_else(|| format!("{key} must be a number"))?,
        };
        if !(v >= lo && v <= hi) {
            return Err(format!(
                "{key} = {v} is out of bounds: it must be {lo} to {hi}"
            ));
        }
        Ok(v)
    };
    let particle_default = match kind {
        ConditionKind::Fog => fog::FOG_RADIUS_UM,
        ConditionKind::Mist => fog::MIST_RADIUS_UM,
        _ => dust::RADIUS_UM,
    };
    let media = matches!(
        kind,
        ConditionKind::Dust | ConditionKind::Fog | ConditionKind::Mist
    );
    Ok(Condition {
        kind,
        at,
        radius_m: number("radius_m", Some(4.0), 0.5, 100.0)?,
        // 0 to 50 g/m^3: beyond that dust is a solid wall (and explosive).
        density_mg_m3: if media {
            number("density_mg_m3", None, 0.0, 50_000.0)?
        } else {
            0.0
        },
        particle_um: if media {
            number("particle_um", Some(particle_default), 0.5, 100.0)?
        } else {
            0.0
        },
        reflectance_factor: number("reflectance_factor", Some(wet_rock::FACTOR), 0.01, 1.0)?,
        puddles: number("puddles", Some(wet_rock::PUDDLES), 0.0, 1.0)?,
        lines_per_10m: number(
            "lines_per_10m",
            Some(super::drips::LINES_PER_10M),
            0.01,
            50.0,
        )?,
        interval_s: number("interval_s", Some(super::drips::INTERVAL_S), 0.02, 600.0)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph() -> RouteGraph {
        RouteGraph::from_json(
            r#"{"format": "subtgraph-graph/1", "start": 0,
            "nodes": [{"id": 0, "kind": "dead-end", "level": 0, "position": [0, 0, 0]},
                      {"id": 1, "kind": "dead-end", "level": 0, "position": [10, 0, 0]}],
            "edges": [{"id": 0, "kind": "corridor", "from": 0, "to": 1, "length_m": 10,
                       "polyline": [[0, 0, 0], [10, 0, 0]]}]}"#,
            "g",
        )
        .unwrap()
    }

    fn err(text: &str) -> String {
        Conditions::parse(text, "c.toml", &graph())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn a_file_reads_with_its_defaults() {
        let c = Conditions::parse(
            "[[conditions]]\ntype = \"fog\"\nat = \"edge 0\"\ndensity_mg_m3 = 300\n\n[[conditions]]\ntype = \"drips\"\nat = \"route\"\n",
            "c.toml",
            &graph(),
        )
        .unwrap();
        assert_eq!(c.list.len(), 2);
        assert_eq!(c.list[0].particle_um, fog::FOG_RADIUS_UM);
        assert_eq!(c.list[1].interval_s, super::super::drips::INTERVAL_S);
    }

    #[test]
    fn bad_tables_say_what_to_change() {
        let e = err("[[conditions]]\ntype = \"dust\"\nat = \"route\"\ndensity_mg_m3 = -5\n");
        assert!(
            e.contains("c.toml") && e.contains("density_mg_m3 = -5") && e.contains("0 to"),
            "{e}"
        );
        let e = err("[[conditions]]\ntype = \"dust\"\nat = \"edge 3\"\ndensity_mg_m3 = 5\n");
        assert!(
            e.contains("edge 3 does not exist") && e.contains("0 to 0"),
            "{e}"
        );
        let e = err("[[conditions]]\ntype = \"dust\"\nat = \"route\"\ndensity = 5\n");
        assert!(
            e.contains("unknown key 'density'") && e.contains("density_mg_m3"),
            "{e}"
        );
        let e = err("[[conditions]]\ntype = \"fog\"\nat = \"platform\"\ndensity_mg_m3 = 5\n");
        assert!(e.contains("only dust"), "{e}");
        let e = err("[[conditions]]\ntype = \"smoke\"\nat = \"route\"\n");
        assert!(e.contains("'smoke'"), "{e}");
        let e = err("[[conditions]]\ntype = \"dust\"\nat = \"level 4\"\ndensity_mg_m3 = 5\n");
        assert!(e.contains("level 4 does not exist"), "{e}");
        let e = err("[[conditions]]\ntype = \"dust\"\nat = \"route\"\n");
        assert!(e.contains("needs density_mg_m3"), "{e}");
        let e = err("seed = 3\n");
        assert!(e.contains("unknown key 'seed'"), "{e}");
        let e = err("[[conditions]]\ntype = \"wet-rock\"\nat = \"route\"\ndensity_mg_m3 = 5\n");
        assert!(e.contains("unknown key 'density_mg_m3'"), "{e}");
    }
}

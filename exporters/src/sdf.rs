//! `gazebo/world.sdf`: an SDFormat 1.9 world for Gazebo (gz-sim, Fortress and later; libsdformat
//! 12+). One static model per part, each with a visual mesh and a separate, lighter collision
//! mesh, plus lighting suited to a dark cave.
//!
//! Meshes are the shared per-part OBJs (`mesh/parts/<split>/`), referenced by paths relative to
//! the SDF file (`../mesh/parts/level/level-0.obj`). gz-sim resolves such a path against the
//! directory of the file that names it, so the world loads with `gz sim gazebo/world.sdf` from
//! anywhere and without `GZ_SIM_RESOURCE_PATH`; `model://` URIs would need that variable to
//! point at a model folder. Gazebo classic (11) reads the same relative paths, but its
//! libsdformat 9 only knows SDFormat up to 1.7 and refuses this file.
//!
//! With floor patches (`[hazards] friction`) a part's collision is split: the patched tiles'
//! floors go to `mesh/hazards/<split>/<part>-collision-<material>.obj`, each a `<collision>`
//! with the material's `<surface><friction>` (ODE `mu`/`mu2`, Bullet `friction`), and the rest
//! to `<part>-collision-rock.obj` with the default surface.
//!
//! A world with fixtures (a mine's services) has a static model `subt-services` whose one
//! visual is `mesh/services.obj` (shared with the OBJ exporter, written here when the OBJ is
//! not asked for), and no collision: they are mounted above a robot.
//!
//! Colours come from the OBJ's material library (one `usemtl` per tile set material). An SDF
//! `<material>` on a visual replaces every colour of its mesh in gz-sim, so it is written only
//! when the tile set has a single material, as a fallback for viewers that ignore MTL files.
//!
//! ```toml
//! [[export]]
//! type = "sdf"
//! lights = "dim"       # "dim" (default), "dark" (robots bring their own lights) or "lamps"
//! lamps_every = 2      # tiles between lamps along corridors, for lights = "lamps"
//! lamp_height = 2.0    # metres above the floor, for lights = "lamps"
//! split = "level"      # parts: "level" (default), "region" or "whole" (see `parts`)
//! ```

use std::collections::BTreeSet;
use std::fmt::Write as _;

use subtgraph_core::World;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::graph::EdgeKind;
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

use crate::parts::{Split, parts, write_part_meshes};
use crate::text::{push_fixed, xml_escape};

/// How the world is lit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lights {
    /// Weak ambient light and a faint directional light: the cave is visible but dark.
    Dim,
    /// No sun and almost no ambient light, for robots that carry their own lights.
    Dark,
    /// Point lights along the corridors, `every` tiles apart, `height` metres above the floor.
    Lamps {
        /// Tiles between lamps.
        every: usize,
        /// Metres above the floor.
        height: f64,
    },
}

/// Writes `gazebo/world.sdf` and the shared per-part meshes it references.
#[derive(Clone, Copy, Debug)]
pub struct Sdf {
    /// How the world is cut into models.
    pub split: Split,
    /// The lighting.
    pub lights: Lights,
}

impl Sdf {
    /// The keys of an `[[export]] type = "sdf"` table.
    pub const KEYS: [&'static str; 5] = [
        "split",
        "region_tiles",
        "lights",
        "lamps_every",
        "lamp_height",
    ];

    /// From an `[[export]] type = "sdf"` table.
    pub fn from_params(params: &Params) -> Result<Sdf, ConfigError> {
        params.expect_known(&Self::KEYS)?;
        let split = Split::from_params(params)?;
        let every = match params.raw("lamps_every") {
            None => 2,
            Some(toml::Value::Integer(n)) if (1..=1000).contains(n) => *n as usize,
            Some(_) => {
                return Err(params.error(
                    "lamps_every",
                    "lamps_every must be a whole number of tiles from 1 to 1000, like 2",
                ));
            }
        };
        let height = match params.raw("lamp_height") {
            None => 2.0,
            Some(toml::Value::Float(h)) if h.is_finite() && *h >= 0.0 => *h,
            Some(toml::Value::Integer(h)) if *h >= 0 => *h as f64,
            Some(_) => {
                return Err(params.error(
                    "lamp_height",
                    "lamp_height must be metres above the floor, zero or more, like 2.0",
                ));
            }
        };
        let lights = match params.raw("lights") {
            None => Lights::Dim,
            Some(toml::Value::String(s)) => match s.as_str() {
                "dim" => Lights::Dim,
                "dark" => Lights::Dark,
                "lamps" => Lights::Lamps { every, height },
                other => {
                    return Err(params.error(
                        "lights",
                        format!(
                            "unknown lights '{other}'; use \"dim\" (faint ambient and sun), \"dark\" (robots bring their own lights) or \"lamps\" (point lights along corridors)"
                        ),
                    ));
                }
            },
            Some(_) => {
                return Err(params.error(
                    "lights",
                    "lights must be a string: \"dim\", \"dark\" or \"lamps\"",
                ));
            }
        };
        Ok(Sdf { split, lights })
    }
}

/// `x y z` with four decimals.
fn triple(s: &mut String, v: [f64; 3]) {
    let mut b = Vec::new();
    for (i, x) in v.into_iter().enumerate() {
        if i > 0 {
            b.push(b' ');
        }
        push_fixed(&mut b, x as f32);
    }
    s.push_str(std::str::from_utf8(&b).expect("digits are ASCII"));
}

/// Where the lamps go: every `every`-th cell along each corridor (its ends included), each
/// cell once, in the order of the graph's corridors.
pub(crate) fn lamp_positions(world: &World, every: usize, height: f64) -> Vec<[f64; 3]> {
    let mut seen = BTreeSet::new();
    let mut out = Vec::new();
    for e in world
        .graph
        .edges
        .iter()
        .filter(|e| e.kind == EdgeKind::Corridor)
    {
        let last = e.cells.len().saturating_sub(1);
        for (i, &c) in e.cells.iter().enumerate() {
            if (i % every == 0 || i == last) && seen.insert(c) {
                let p = world.cell_position(c);
                out.push([p[0], p[1], p[2] + height]);
            }
        }
    }
    out
}

fn lights_xml(s: &mut String, world: &World, lights: Lights) {
    let (ambient, background) = match lights {
        Lights::Dim => ("0.15 0.15 0.15 1", "0.02 0.02 0.02 1"),
        Lights::Dark | Lights::Lamps { .. } => ("0.01 0.01 0.01 1", "0 0 0 1"),
    };
    let _ = write!(
        s,
        "    <scene>\n      <ambient>{ambient}</ambient>\n      <background>{background}</background>\n      <shadows>false</shadows>\n      <grid>false</grid>\n    </scene>\n"
    );
    match lights {
        Lights::Dim => s.push_str(
            "    <light type=\"directional\" name=\"sun\">\n      <cast_shadows>false</cast_shadows>\n      <pose>0 0 100 0 0 0</pose>\n      <diffuse>0.25 0.25 0.25 1</diffuse>\n      <specular>0.05 0.05 0.05 1</specular>\n      <direction>-0.3 0.2 -0.9</direction>\n    </light>\n",
        ),
        Lights::Dark => {}
        Lights::Lamps { every, height } => {
            let range = world.resolved.tile_pitch * every as f64 * 1.5;
            for (i, p) in lamp_positions(world, every, height).into_iter().enumerate() {
                let _ = write!(
                    s,
                    "    <light type=\"point\" name=\"lamp-{i}\">\n      <cast_shadows>false</cast_shadows>\n      <pose>"
                );
                triple(s, p);
                let _ = write!(
                    s,
                    " 0 0 0</pose>\n      <diffuse>0.9 0.8 0.6 1</diffuse>\n      <specular>0.1 0.1 0.1 1</specular>\n      <attenuation>\n        <range>{range:.1}</range>\n        <constant>0.5</constant>\n        <linear>0.05</linear>\n        <quadratic>0.005</quadratic>\n      </attenuation>\n    </light>\n"
                );
            }
        }
    }
}

/// The artifacts as movable models (a box each, resting on the floor at its recorded pose),
/// named `artifact-<name>`, each on its pad, a static model `artifact-pad-<name>`
/// ([`Artifact::pad`](subtgraph_core::artifacts::Artifact::pad)).
fn artifact_models(s: &mut String, artifacts: &[subtgraph_core::artifacts::Artifact]) {
    for a in artifacts {
        let [x, y, z] = a.position;
        let [l, w, h] = a.size;
        let [r, g, b] = a.class.colour();
        let m = a.class.mass();
        let (ixx, iyy, izz) = (
            m / 12.0 * (w * w + h * h),
            m / 12.0 * (l * l + h * h),
            m / 12.0 * (l * l + w * w),
        );
        let hz = 0.5 * h;
        let ([px, py, pz], [pl, pw, ph]) = a.pad();
        let _ = write!(
            s,
            "    <model name=\"artifact-pad-{n}\">\n      <static>true</static>\n      <pose>{px:.4} {py:.4} {pz:.4} 0 0 {yaw:.6}</pose>\n      <link name=\"link\">\n        <collision name=\"collision\">\n          <geometry>\n            <box>\n              <size>{pl:.4} {pw:.4} {ph:.4}</size>\n            </box>\n          </geometry>\n        </collision>\n        <visual name=\"visual\">\n          <geometry>\n            <box>\n              <size>{pl:.4} {pw:.4} {ph:.4}</size>\n            </box>\n          </geometry>\n        </visual>\n      </link>\n    </model>\n",
            n = a.name,
            yaw = a.yaw,
        );
        let _ = write!(
            s,
            "    <model name=\"artifact-{n}\">\n      <pose>{x:.4} {y:.4} {z:.4} 0 0 {yaw:.6}</pose>\n      <link name=\"link\">\n        <inertial>\n          <pose>0 0 {hz:.4} 0 0 0</pose>\n          <mass>{m}</mass>\n          <inertia>\n            <ixx>{ixx:.6}</ixx>\n            <ixy>0</ixy>\n            <ixz>0</ixz>\n            <iyy>{iyy:.6}</iyy>\n            <iyz>0</iyz>\n            <izz>{izz:.6}</izz>\n          </inertia>\n        </inertial>\n        <collision name=\"collision\">\n          <pose>0 0 {hz:.4} 0 0 0</pose>\n          <geometry>\n            <box>\n              <size>{l:.4} {w:.4} {h:.4}</size>\n            </box>\n          </geometry>\n        </collision>\n        <visual name=\"visual\">\n          <pose>0 0 {hz:.4} 0 0 0</pose>\n          <geometry>\n            <box>\n              <size>{l:.4} {w:.4} {h:.4}</size>\n            </box>\n          </geometry>\n          <material>\n            <ambient>{r:.3} {g:.3} {b:.3} 1</ambient>\n            <diffuse>{r:.3} {g:.3} {b:.3} 1</diffuse>\n          </material>\n        </visual>\n      </link>\n    </model>\n",
            n = a.name,
            yaw = a.yaw,
        );
    }
}

/// A `<collision>` with a mesh (`path` relative to the world folder) and, for a floor patch,
/// its friction (ODE's `mu` and `mu2`, and Bullet's `friction`).
/// A material's maps as SDFormat's `<pbr><metal>` (paths relative to the SDF file, as the
/// meshes'), when it has any.
fn pbr_xml(s: &mut String, m: &subtgraph_core::mesh::Material) {
    if m.texture.is_none() && m.normal_map.is_none() && m.roughness_map.is_none() {
        return;
    }
    s.push_str("            <pbr>\n              <metal>\n");
    for (tag, map) in [
        ("albedo_map", &m.texture),
        ("normal_map", &m.normal_map),
        ("roughness_map", &m.roughness_map),
    ] {
        if let Some(f) = map {
            let _ = writeln!(
                s,
                "                <{tag}>../mesh/{}</{tag}>",
                xml_escape(f)
            );
        }
    }
    s.push_str(
        "                <metalness>0</metalness>\n              </metal>\n            </pbr>\n",
    );
}

fn collision_xml(s: &mut String, name: &str, path: &str, friction: Option<f64>) {
    let _ = write!(
        s,
        "        <collision name=\"{name}\">\n          <geometry>\n            <mesh>\n              <uri>../{path}</uri>\n            </mesh>\n          </geometry>\n",
        path = xml_escape(path),
    );
    if let Some(mu) = friction {
        let _ = write!(
            s,
            "          <surface>\n            <friction>\n              <ode>\n                <mu>{mu}</mu>\n                <mu2>{mu}</mu2>\n              </ode>\n              <bullet>\n                <friction>{mu}</friction>\n                <friction2>{mu}</friction2>\n              </bullet>\n            </friction>\n          </surface>\n"
        );
    }
    s.push_str("        </collision>\n");
}

impl Exporter for Sdf {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the SDF exporter needs geometry: add a [tileset] to the pipeline (or drop --no-mesh)".into(),
            ));
        };
        let ps = parts(world, mesh, self.split);
        let files = write_part_meshes(out, mesh, self.split, &ps)?;
        let mut s = String::from("<?xml version=\"1.0\"?>\n");
        s.push_str("<!-- subtgraph world: metres, x east, y north, z up. Meshes are relative to this file. -->\n");
        s.push_str("<sdf version=\"1.9\">\n  <world name=\"subtgraph\">\n");
        s.push_str(
            "    <gravity>0 0 -9.8</gravity>\n    <physics name=\"default\" type=\"ode\">\n      <max_step_size>0.001</max_step_size>\n      <real_time_factor>1</real_time_factor>\n      <real_time_update_rate>1000</real_time_update_rate>\n    </physics>\n",
        );
        lights_xml(&mut s, world, self.lights);
        if let Some(start) = world.start {
            // Classic's user camera, inside the passage at the start, looking east.
            let p = world.cell_position(start);
            s.push_str("    <gui>\n      <camera name=\"user_camera\">\n        <pose>");
            triple(&mut s, [p[0], p[1], p[2] + 1.5]);
            s.push_str(" 0 0.1 0</pose>\n      </camera>\n    </gui>\n");
        }
        // One material: stated on the visual (with its maps as `<pbr>`); several: the part
        // meshes' MTL names them per face (colours and maps), which Gazebo reads.
        let single = match mesh.materials.as_slice() {
            [m] => Some(m),
            _ => None,
        };
        let patches = survey.patches().unwrap_or(&[]);
        // Models are named `subt-<part>`: SDFormat reserves the name `world`.
        for (part, f) in ps.iter().zip(&files) {
            let _ = write!(
                s,
                "    <model name=\"subt-{name}\">\n      <static>true</static>\n      <link name=\"link\">\n        <visual name=\"visual\">\n          <geometry>\n            <mesh>\n              <uri>../{visual}</uri>\n            </mesh>\n          </geometry>\n",
                name = xml_escape(&f.name),
                visual = xml_escape(&f.visual),
            );
            if let Some(m) = single {
                let [r, g, b] = m.colour;
                let _ = write!(
                    s,
                    "          <material>\n            <ambient>{r:.4} {g:.4} {b:.4} 1</ambient>\n            <diffuse>{r:.4} {g:.4} {b:.4} 1</diffuse>\n            <specular>0.05 0.05 0.05 1</specular>\n"
                );
                pbr_xml(&mut s, m);
                s.push_str("          </material>\n");
            }
            s.push_str("        </visual>\n");
            match crate::hazards::split_collision(patches, mesh, part) {
                None => collision_xml(&mut s, "collision", &f.collision, None),
                Some(groups) => {
                    // Floor patches: the patched floors as collisions of their own, with
                    // the material's friction; the rest of the rock as before.
                    let split =
                        crate::hazards::write_split_meshes(out, mesh, self.split, part, groups)?;
                    for (m, path) in split {
                        let name = match m {
                            None => "collision".to_owned(),
                            Some(m) => format!("collision-{}", m.name()),
                        };
                        collision_xml(&mut s, &name, &path, m.map(|m| m.friction()));
                    }
                }
            }
            s.push_str("      </link>\n    </model>\n");
        }
        if let Some(services) = crate::services::write_services_obj(out, mesh)? {
            // The services: seen, not touched (mounted above a robot), so a visual alone;
            // their colours and maps per face from the OBJ's material library.
            let _ = write!(
                s,
                "    <model name=\"subt-services\">\n      <static>true</static>\n      <link name=\"link\">\n        <visual name=\"visual\">\n          <geometry>\n            <mesh>\n              <uri>../{services}</uri>\n            </mesh>\n          </geometry>\n        </visual>\n      </link>\n    </model>\n"
            );
        }
        artifact_models(&mut s, crate::artifacts_of(survey));
        s.push_str("  </world>\n</sdf>\n");
        write_file(out, "gazebo/world.sdf", s.as_bytes())
    }

    fn needs_geometry(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn lamps_light_every_corridor() {
        let world = crate::test_world_with_mesh();
        let sdf = Sdf {
            split: Split::Level,
            lights: Lights::Lamps {
                every: 2,
                height: 2.0,
            },
        };
        let mut out = MemoryWriter::default();
        sdf.export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let text = String::from_utf8(out.get("gazebo/world.sdf").unwrap().to_vec()).unwrap();
        let lamps = text.matches("type=\"point\"").count();
        assert_eq!(lamps, lamp_positions(&world, 2, 2.0).len());
        let corridors = world
            .graph
            .edges
            .iter()
            .filter(|e| e.kind == EdgeKind::Corridor)
            .count();
        assert!(lamps > corridors, "{lamps} lamps for {corridors} corridors");
        assert!(!text.contains("name=\"sun\""));
    }
}

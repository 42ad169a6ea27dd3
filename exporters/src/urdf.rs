//! URDF for PyBullet: `urdf/world.urdf`, one fixed link named `world` with a `<visual>` and a
//! `<collision>` per part, referencing the shared per-part OBJs by paths relative to the URDF
//! file (`../mesh/parts/level/level-0.obj`), as PyBullet and ROS tools resolve them.
//!
//! PyBullet collides a mesh as its convex hull unless told otherwise, which would fill the
//! tunnels. Its URDF reader takes a non-standard `concave="yes"` on the `<link>` and on each
//! `<collision>`: the mesh is then kept as a static triangle mesh (a BVH), which is right for a
//! world that never moves. The link has zero mass (static); load it with
//! `loadURDF("urdf/world.urdf", useFixedBase=True)`. Other URDF readers ignore the attribute.
//!
//! A world with fixtures (a mine's services) has one more `<visual>` per material on `world`,
//! `mesh/services/<material>.obj` in the material's colour, and no collision for them: they
//! are mounted above a robot.
//!
//! Floor patches (`[hazards] friction`): PyBullet's friction (`<contact><lateral_friction>`)
//! is per link, so each part's patched floors of one material are a link of their own
//! (`hazard-<part>-<material>`, fixed to `world`), and `world` collides with the rest.
//!
//! ```toml
//! [[export]]
//! type = "urdf"
//! split = "level"    # or "region" (with region_tiles) or "whole"
//! ```

use subtgraph_core::World;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

use crate::mjcf::part_colour;
use crate::parts::{Split, parts, write_part_meshes};
use crate::text::xml_escape;

/// Writes the world as a URDF with one static link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Urdf {
    /// How the world is cut into visual/collision pairs.
    pub split: Split,
}

impl Default for Urdf {
    fn default() -> Self {
        Urdf {
            split: Split::Level,
        }
    }
}

impl Urdf {
    /// From an `[[export]] type = "urdf"` table: `split` and `region_tiles`.
    pub fn from_params(params: &Params) -> Result<Urdf, ConfigError> {
        params.expect_known(&Split::KEYS)?;
        Ok(Urdf {
            split: Split::from_params(params)?,
        })
    }
}

/// An artifact as a link (a box resting on the floor at its recorded pose) fixed to the
/// world: a URDF is one articulated body, so the artifacts cannot move in it. Their pads
/// ([`Artifact::pad`](subtgraph_core::artifacts::Artifact::pad)) are collision boxes of the world link.
fn artifact_link(s: &mut String, a: &subtgraph_core::artifacts::Artifact) {
    let [x, y, z] = a.position;
    let [l, w, h] = a.size;
    let [r, g, b] = a.class.colour();
    let m = a.class.mass();
    let hz = 0.5 * h;
    s.push_str(&format!(
        "  <link name=\"artifact-{n}\">\n    <inertial>\n      <origin xyz=\"0 0 {hz:.4}\"/>\n      <mass value=\"{m}\"/>\n      <inertia ixx=\"{:.6}\" ixy=\"0\" ixz=\"0\" iyy=\"{:.6}\" iyz=\"0\" izz=\"{:.6}\"/>\n    </inertial>\n    <visual>\n      <origin xyz=\"0 0 {hz:.4}\"/>\n      <geometry>\n        <box size=\"{l:.4} {w:.4} {h:.4}\"/>\n      </geometry>\n      <material name=\"artifact-{class}\">\n        <color rgba=\"{r:.3} {g:.3} {b:.3} 1\"/>\n      </material>\n    </visual>\n    <collision>\n      <origin xyz=\"0 0 {hz:.4}\"/>\n      <geometry>\n        <box size=\"{l:.4} {w:.4} {h:.4}\"/>\n      </geometry>\n    </collision>\n  </link>\n  <joint name=\"artifact-{n}\" type=\"fixed\">\n    <parent link=\"world\"/>\n    <child link=\"artifact-{n}\"/>\n    <origin xyz=\"{x:.4} {y:.4} {z:.4}\" rpy=\"0 0 {yaw:.6}\"/>\n  </joint>\n",
        m / 12.0 * (w * w + h * h),
        m / 12.0 * (l * l + h * h),
        m / 12.0 * (l * l + w * w),
        n = a.name,
        class = a.class.name(),
        yaw = a.yaw,
    ));
}

impl Exporter for Urdf {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the URDF exporter needs geometry: add a [tileset] to the pipeline (or drop --no-mesh)".into(),
            ));
        };
        let parts = parts(world, mesh, self.split);
        let files = write_part_meshes(out, mesh, self.split, &parts)?;
        let mut s = format!(
            "<?xml version=\"1.0\"?>\n<!-- subtgraph world, seed {}: metres, x east, y north, z up. PyBullet: loadURDF(\"urdf/world.urdf\", useFixedBase=True) -->\n<robot name=\"subtgraph_world\">\n  <link name=\"world\" concave=\"yes\">\n    <inertial>\n      <mass value=\"0\"/>\n      <inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>\n    </inertial>\n",
            world.resolved.seed
        );
        let patches = survey.patches().unwrap_or(&[]);
        let mut patch_links = Vec::new();
        for (part, file) in parts.iter().zip(&files) {
            let name = xml_escape(&part.name);
            let [r, g, b] = part_colour(mesh, part);
            s.push_str(&format!(
                "    <visual name=\"{name}\">\n      <geometry>\n        <mesh filename=\"../{}\"/>\n      </geometry>\n      <material name=\"{name}-rock\">\n        <color rgba=\"{r:.4} {g:.4} {b:.4} 1\"/>\n      </material>\n    </visual>\n",
                xml_escape(&file.visual)
            ));
            let collision = match crate::hazards::split_collision(patches, mesh, part) {
                None => file.collision.clone(),
                Some(groups) => {
                    // Floor patches: PyBullet's friction is per link, so each material's
                    // floors are a link of their own (below); the world keeps the rest.
                    let mut rock = String::new();
                    for (m, path) in
                        crate::hazards::write_split_meshes(out, mesh, self.split, part, groups)?
                    {
                        match m {
                            None => rock = path,
                            Some(m) => {
                                patch_links.push((format!("{}-{}", part.name, m.name()), m, path))
                            }
                        }
                    }
                    rock
                }
            };
            s.push_str(&format!(
                "    <collision name=\"{name}\" concave=\"yes\">\n      <geometry>\n        <mesh filename=\"../{}\"/>\n      </geometry>\n    </collision>\n",
                xml_escape(&collision)
            ));
        }
        // The services: a visual per material (a URDF visual has one colour), no
        // collision (they are mounted above a robot).
        for (m, path) in crate::services::write_material_objs(out, mesh)? {
            let name = xml_escape(&m.name);
            let [r, g, b] = m.colour;
            s.push_str(&format!(
                "    <visual name=\"services-{name}\">\n      <geometry>\n        <mesh filename=\"../{}\"/>\n      </geometry>\n      <material name=\"{name}\">\n        <color rgba=\"{r:.4} {g:.4} {b:.4} 1\"/>\n      </material>\n    </visual>\n",
                xml_escape(&path)
            ));
        }
        let artifacts = crate::artifacts_of(survey);
        for a in artifacts.iter() {
            // Its pad (`Artifact::pad`), part of the fixed world.
            let ([x, y, z], [l, w, h]) = a.pad();
            s.push_str(&format!(
                "    <collision name=\"artifact-pad-{n}\">\n      <origin xyz=\"{x:.4} {y:.4} {z:.4}\" rpy=\"0 0 {yaw:.6}\"/>\n      <geometry>\n        <box size=\"{l:.4} {w:.4} {h:.4}\"/>\n      </geometry>\n    </collision>\n",
                n = a.name,
                yaw = a.yaw
            ));
        }
        s.push_str("  </link>\n");
        for (name, m, path) in &patch_links {
            let name = xml_escape(name);
            s.push_str(&format!(
                "  <link name=\"hazard-{name}\" concave=\"yes\">\n    <contact>\n      <lateral_friction value=\"{mu}\"/>\n    </contact>\n    <inertial>\n      <mass value=\"0\"/>\n      <inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>\n    </inertial>\n    <collision name=\"hazard-{name}\" concave=\"yes\">\n      <geometry>\n        <mesh filename=\"../{path}\"/>\n      </geometry>\n    </collision>\n  </link>\n  <joint name=\"hazard-{name}\" type=\"fixed\">\n    <parent link=\"world\"/>\n    <child link=\"hazard-{name}\"/>\n  </joint>\n",
                mu = m.friction(),
                path = xml_escape(path),
            ));
        }
        for a in artifacts.iter() {
            artifact_link(&mut s, a);
        }
        s.push_str("</robot>\n");
        write_file(out, "urdf/world.urdf", s.as_bytes())
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
    fn every_mesh_path_resolves_from_the_urdf_folder_to_a_written_file() {
        let world = crate::test_world_with_mesh();
        let mut out = MemoryWriter::default();
        Urdf::default()
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let text = String::from_utf8(out.get("urdf/world.urdf").unwrap().to_vec()).unwrap();
        let meshes: Vec<&str> = text
            .split("filename=\"")
            .skip(1)
            .map(|s| &s[..s.find('"').unwrap()])
            .collect();
        // A visual and a collision per level.
        assert_eq!(meshes.len(), 2 * world.occupancy.levels());
        for m in meshes {
            let from_root = m.strip_prefix("../").expect("relative to urdf/");
            assert!(out.contains(from_root), "{m} written");
        }
        assert_eq!(
            text.matches("concave=\"yes\"").count(),
            1 + world.occupancy.levels()
        );
    }
}

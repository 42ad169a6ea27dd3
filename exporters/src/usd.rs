//! `usd/world.usda` (+ `usd/parts/<part>.usda`): the world as USD for Isaac Sim and
//! Omniverse, in the text form usd-core and every USD tool open.
//!
//! The root layer states the units (`metersPerUnit = 1`, `upAxis = "Z"`), holds `/World` with
//! a `UsdPhysics` scene and the `UsdPreviewSurface` materials, and sublayers one layer per part
//! (so a large world's parts can be loaded or muted one at a time). Each part has a visual mesh
//! (points, vertex normals, `primvars:st`, extent, a `GeomSubset` per material bound with
//! `familyName = "materialBind"`) and a collision mesh (`purpose = "guide"`, so it is not
//! rendered) with `PhysicsCollisionAPI` + `PhysicsMeshCollisionAPI` and
//! `physics:approximation = "none"`: a triangle mesh, since the convex hull Isaac Sim uses by
//! default would fill the cave; it is bound (purpose `physics`) to the root layer's
//! `PhysicsMaterialAPI` material `/World/PhysicsMaterials/Rock` (friction 0.8 static, 0.7
//! dynamic; restitution 0.1). There is no rigid body: the cave is static. The root layer also
//! states `kilogramsPerUnit = 1`.
//!
//! Tiles whose visual geometry repeats up to a translation (the same mesh file placed with
//! the same rotation, as with the DARPA tiles) become `instanceable` references to one
//! prototype under `/Prototypes` (an abstract `class`, so not drawn itself), placed by
//! `xformOp:translate`: see [`instances`](crate::instances). Their collision triangles stay
//! in the part's collision mesh.
//!
//! A world's fixtures (a mine's bolts, duct, pipes, cable and lights) are one
//! `PointInstancer`, `/World/Services` in `usd/parts/services.usda`: each prototype once,
//! each copy a position, orientation and scale, so the file grows by one line's worth per
//! bolt. They are visual only (mounted above a ground robot; no collider).
//!
//! Floor patches (`[hazards] friction`): the patched tiles' floors are colliders of their
//! own (`collision_mud`, ...) bound to a `PhysicsMaterialAPI` material per hazard material
//! (`/World/PhysicsMaterials/Mud`, ...); the rest of the part stays `collision` on the rock.
//!
//! ```toml
//! [[export]]
//! type = "usd"
//! split = "level"      # one layer per part: "level" (default), "region" or "whole"
//! instancing = true    # repeated tiles as instanceable references (default true)
//! ```

use std::io::Write;

use subtgraph_core::World;
use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, stream_file, write_file};
use subtgraph_core::hazards::FloorMaterial;
use subtgraph_core::mesh::{Material, Mesh};
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

use crate::instances::{Instances, find_instances};
use crate::parts::{Split, parts};
use crate::text::{push_fixed, push_uint, write_lines};

/// Writes the world as USD layers.
#[derive(Clone, Copy, Debug)]
pub struct Usd {
    /// One layer per part cut this way.
    pub split: Split,
    /// Repeated tiles as instanceable references.
    pub instancing: bool,
}

impl Usd {
    /// The keys of an `[[export]] type = "usd"` table.
    pub const KEYS: [&'static str; 3] = ["split", "region_tiles", "instancing"];

    /// From an `[[export]] type = "usd"` table.
    pub fn from_params(params: &Params) -> Result<Usd, ConfigError> {
        params.expect_known(&Self::KEYS)?;
        let instancing = match params.raw("instancing") {
            None => true,
            Some(toml::Value::Boolean(b)) => *b,
            Some(_) => {
                return Err(params.error(
                    "instancing",
                    "instancing must be true (repeated tiles as instanceable references) or false",
                ));
            }
        };
        Ok(Usd {
            split: Split::from_params(params)?,
            instancing,
        })
    }
}

/// A USD prim name from ours: letters, digits and `_` only, not starting with a digit.
pub(crate) fn prim_name(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    s
}

const HEADER: &str =
    "#usda 1.0\n(\n    metersPerUnit = 1\n    kilogramsPerUnit = 1\n    upAxis = \"Z\"\n)\n\n";

/// Writes `name = [a, b, ...]` with `count` elements, formatted in parallel.
fn array(
    w: &mut dyn Write,
    indent: &str,
    decl: &str,
    count: usize,
    element: impl Fn(&mut Vec<u8>, usize) + Sync,
) -> std::io::Result<()> {
    write!(w, "{indent}{decl} = [")?;
    write_lines(w, count, |b, i| {
        if i > 0 {
            b.extend_from_slice(b", ");
        }
        element(b, i);
    })?;
    w.write_all(b"]")
}

fn tuple(b: &mut Vec<u8>, v: &[f32]) {
    b.push(b'(');
    for (k, x) in v.iter().enumerate() {
        if k > 0 {
            b.extend_from_slice(b", ");
        }
        push_fixed(b, *x);
    }
    b.push(b')');
}

/// What a mesh prim is for.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Visual,
    /// A collider bound to a floor material, or to the rock (`None`).
    Collision(Option<FloorMaterial>),
}

/// The prim name of a floor patch material's physics material: `WetRock` for `wet-rock`.
fn material_prim(m: FloorMaterial) -> String {
    m.name()
        .split('-')
        .map(|w| w[..1].to_uppercase() + &w[1..])
        .collect()
}

/// The path of that physics material: `</World/PhysicsMaterials/WetRock>`.
fn physics_material(m: FloorMaterial) -> String {
    format!("</World/PhysicsMaterials/{}>", material_prim(m))
}

/// The physics material every collider is bound to (defined in the root layer).
const ROCK: &str = "</World/PhysicsMaterials/Rock>";

/// Writes one `Mesh` prim (its points relative to `origin`).
fn write_mesh(
    w: &mut dyn Write,
    indent: &str,
    name: &str,
    mesh: &Mesh,
    role: Role,
    materials: &[String],
    origin: [f32; 3],
) -> std::io::Result<()> {
    let schemas = match role {
        Role::Visual => "\"MaterialBindingAPI\"",
        Role::Collision(_) => {
            "\"PhysicsCollisionAPI\", \"PhysicsMeshCollisionAPI\", \"MaterialBindingAPI\""
        }
    };
    writeln!(
        w,
        "{indent}def Mesh \"{name}\" (\n{indent}    prepend apiSchemas = [{schemas}]\n{indent})\n{indent}{{"
    )?;
    let inner = format!("{indent}    ");
    let at = |i: usize| {
        let p = mesh.positions[i];
        [p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]]
    };
    if let Some((lo, hi)) = mesh.bounds() {
        let mut b = Vec::new();
        b.extend_from_slice(inner.as_bytes());
        b.extend_from_slice(b"float3[] extent = [");
        tuple(
            &mut b,
            &[lo[0] - origin[0], lo[1] - origin[1], lo[2] - origin[2]],
        );
        b.extend_from_slice(b", ");
        tuple(
            &mut b,
            &[hi[0] - origin[0], hi[1] - origin[1], hi[2] - origin[2]],
        );
        b.extend_from_slice(b"]\n");
        w.write_all(&b)?;
    }
    let n = mesh.triangles.len();
    array(w, &inner, "int[] faceVertexCounts", n, |b, _| b.push(b'3'))?;
    writeln!(w)?;
    array(w, &inner, "int[] faceVertexIndices", n * 3, |b, i| {
        push_uint(b, u64::from(mesh.triangles[i / 3][i % 3]));
    })?;
    writeln!(w)?;
    array(
        w,
        &inner,
        "point3f[] points",
        mesh.positions.len(),
        |b, i| tuple(b, &at(i)),
    )?;
    writeln!(w)?;
    writeln!(w, "{inner}uniform token subdivisionScheme = \"none\"")?;
    match role {
        Role::Collision(m) => {
            writeln!(w, "{inner}uniform token purpose = \"guide\"")?;
            writeln!(w, "{inner}bool physics:collisionEnabled = 1")?;
            writeln!(w, "{inner}uniform token physics:approximation = \"none\"")?;
            match m {
                None => writeln!(w, "{inner}rel material:binding:physics = {ROCK}")?,
                Some(m) => writeln!(
                    w,
                    "{inner}rel material:binding:physics = {}",
                    physics_material(m)
                )?,
            }
        }
        Role::Visual => {
            if mesh.normals.len() == mesh.positions.len() {
                array(
                    w,
                    &inner,
                    "normal3f[] normals",
                    mesh.normals.len(),
                    |b, i| tuple(b, &mesh.normals[i]),
                )?;
                writeln!(w, " (\n{inner}    interpolation = \"vertex\"\n{inner})")?;
            }
            if mesh.uvs.len() == mesh.positions.len() {
                array(
                    w,
                    &inner,
                    "texCoord2f[] primvars:st",
                    mesh.uvs.len(),
                    |b, i| tuple(b, &mesh.uvs[i]),
                )?;
                writeln!(w, " (\n{inner}    interpolation = \"vertex\"\n{inner})")?;
            }
            write_bindings(w, &inner, mesh, materials)?;
        }
    }
    writeln!(w, "{indent}}}")
}

/// Binds the materials: the whole mesh when it has one, else a `GeomSubset` per material.
fn write_bindings(
    w: &mut dyn Write,
    inner: &str,
    mesh: &Mesh,
    materials: &[String],
) -> std::io::Result<()> {
    let material_of = |t: usize| usize::from(mesh.materials.get(t).copied().unwrap_or(0));
    let mut used = vec![false; materials.len().max(1)];
    for t in 0..mesh.triangles.len() {
        if let Some(u) = used.get_mut(material_of(t)) {
            *u = true;
        }
    }
    let look = |m: usize| {
        format!(
            "</World/Looks/{}>",
            materials.get(m).map_or("default", |s| s)
        )
    };
    let present: Vec<usize> = (0..used.len()).filter(|&m| used[m]).collect();
    if present.len() <= 1 {
        let m = present.first().copied().unwrap_or(0);
        return writeln!(w, "{inner}rel material:binding = {}", look(m));
    }
    writeln!(
        w,
        "{inner}uniform token subsetFamily:materialBind:familyType = \"partition\""
    )?;
    for m in present {
        let faces: Vec<u32> = (0..mesh.triangles.len())
            .filter(|&t| material_of(t) == m)
            .map(|t| t as u32)
            .collect();
        writeln!(
            w,
            "\n{inner}def GeomSubset \"{name}\" (\n{inner}    prepend apiSchemas = [\"MaterialBindingAPI\"]\n{inner})\n{inner}{{\n{inner}    uniform token elementType = \"face\"\n{inner}    uniform token familyName = \"materialBind\"",
            name = materials.get(m).map_or("default", |s| s),
        )?;
        array(
            w,
            &format!("{inner}    "),
            "int[] indices",
            faces.len(),
            |b, i| push_uint(b, u64::from(faces[i])),
        )?;
        writeln!(
            w,
            "\n{inner}    rel material:binding = {}\n{inner}}}",
            look(m)
        )?;
    }
    Ok(())
}

/// A `UsdPreviewSurface` reading its images through `UsdUVTexture`s at the meshes'
/// `primvars:st` (a `UsdPrimvarReader_float2`): the albedo as sRGB, the normal map raw and
/// scaled from `[0, 1]` to `[-1, 1]`, the roughness raw from its red channel. Asset paths are
/// relative to `usd/world.usda`.
fn textured_material(s: &mut String, name: &str, m: &Material) {
    use std::fmt::Write as _;
    let at = format!("/World/Looks/{name}");
    let _ = write!(
        s,
        "        def Material \"{name}\"\n        {{\n            token outputs:surface.connect = <{at}/Surface.outputs:surface>\n\n            def Shader \"Surface\"\n            {{\n                uniform token info:id = \"UsdPreviewSurface\"\n"
    );
    let [r, g, b] = m.colour;
    let _ = match &m.texture {
        Some(_) => writeln!(
            s,
            "                color3f inputs:diffuseColor.connect = <{at}/Albedo.outputs:rgb>"
        ),
        None => writeln!(
            s,
            "                color3f inputs:diffuseColor = ({r:.4}, {g:.4}, {b:.4})"
        ),
    };
    s.push_str("                float inputs:metallic = 0\n");
    if m.normal_map.is_some() {
        let _ = writeln!(
            s,
            "                normal3f inputs:normal.connect = <{at}/Normal.outputs:rgb>"
        );
    }
    let _ = match &m.roughness_map {
        Some(_) => writeln!(
            s,
            "                float inputs:roughness.connect = <{at}/Roughness.outputs:r>"
        ),
        None => writeln!(s, "                float inputs:roughness = 0.9"),
    };
    s.push_str("                token outputs:surface\n            }\n\n            def Shader \"St\"\n            {\n                uniform token info:id = \"UsdPrimvarReader_float2\"\n                string inputs:varname = \"st\"\n                float2 outputs:result\n            }\n");
    for (shader, file, space, extra, output) in [
        ("Albedo", &m.texture, "sRGB", "", "float3 outputs:rgb"),
        (
            "Normal",
            &m.normal_map,
            "raw",
            "                float4 inputs:scale = (2, 2, 2, 1)\n                float4 inputs:bias = (-1, -1, -1, 0)\n",
            "float3 outputs:rgb",
        ),
        ("Roughness", &m.roughness_map, "raw", "", "float outputs:r"),
    ] {
        if let Some(f) = file {
            let _ = write!(
                s,
                "\n            def Shader \"{shader}\"\n            {{\n                uniform token info:id = \"UsdUVTexture\"\n                asset inputs:file = @../mesh/{f}@\n                float2 inputs:st.connect = <{at}/St.outputs:result>\n                token inputs:sourceColorSpace = \"{space}\"\n                token inputs:wrapS = \"repeat\"\n                token inputs:wrapT = \"repeat\"\n{extra}                {output}\n            }}\n"
            );
        }
    }
    s.push_str("        }\n");
}

/// The root layer: units, physics scene, materials, and the part layers as sublayers.
fn root_layer(
    mesh: &WorldMesh,
    layers: &[String],
    materials: &[String],
    artifacts: &[subtgraph_core::artifacts::Artifact],
    patches: &[subtgraph_core::hazards::Patch],
) -> String {
    let mut s = String::from(
        "#usda 1.0\n(\n    defaultPrim = \"World\"\n    doc = \"subtgraph world: metres, x east, y north, z up\"\n    metersPerUnit = 1\n    kilogramsPerUnit = 1\n    upAxis = \"Z\"\n    subLayers = [\n",
    );
    for (i, l) in layers.iter().enumerate() {
        let comma = if i + 1 < layers.len() { "," } else { "" };
        s.push_str(&format!("        @./{l}@{comma}\n"));
    }
    s.push_str("    ]\n)\n\ndef Xform \"World\"\n{\n");
    s.push_str("    def PhysicsScene \"PhysicsScene\"\n    {\n        vector3f physics:gravityDirection = (0, 0, -1)\n        float physics:gravityMagnitude = 9.81\n    }\n\n");
    // The rock's contact properties, which Isaac Sim (PhysX) reads from the collider's
    // physics-purpose binding.
    s.push_str("    def Scope \"PhysicsMaterials\"\n    {\n        def Material \"Rock\" (\n            prepend apiSchemas = [\"PhysicsMaterialAPI\"]\n        )\n        {\n            float physics:dynamicFriction = 0.7\n            float physics:restitution = 0.1\n            float physics:staticFriction = 0.8\n        }\n");
    // Floor patches (`[hazards]`): a material each, bound to the colliders of those floors.
    let used: std::collections::BTreeSet<FloorMaterial> =
        patches.iter().map(|p| p.material).collect();
    for m in used {
        let name = material_prim(m);
        let mu = m.friction();
        s.push_str(&format!(
            "\n        def Material \"{name}\" (\n            prepend apiSchemas = [\"PhysicsMaterialAPI\"]\n        )\n        {{\n            custom string subtgraph:hazard = \"{}\"\n            float physics:dynamicFriction = {mu}\n            float physics:restitution = 0.1\n            float physics:staticFriction = {mu}\n        }}\n",
            m.name()
        ));
    }
    s.push_str("    }\n\n");
    s.push_str("    def Scope \"Looks\"\n    {\n");
    let mut all: Vec<(String, Material)> = materials
        .iter()
        .zip(&mesh.materials)
        .map(|(n, m)| (n.clone(), m.clone()))
        .collect();
    if all.is_empty() {
        all.push(("default".into(), Material::coloured("default", [0.5; 3])));
    }
    for (name, m) in all {
        if m.texture.is_some() {
            textured_material(&mut s, &name, &m);
            continue;
        }
        let [r, g, b] = m.colour;
        s.push_str(&format!(
            "        def Material \"{name}\"\n        {{\n            token outputs:surface.connect = </World/Looks/{name}/Surface.outputs:surface>\n\n            def Shader \"Surface\"\n            {{\n                uniform token info:id = \"UsdPreviewSurface\"\n                color3f inputs:diffuseColor = ({r:.4}, {g:.4}, {b:.4})\n                float inputs:metallic = 0\n                float inputs:roughness = 0.9\n                token outputs:surface\n            }}\n        }}\n"
        ));
    }
    s.push_str("    }\n");
    artifact_prims(&mut s, artifacts);
    s.push_str("}\n");
    s
}

/// The artifacts under `/World/Artifacts`: an `Xform` per artifact at its recorded pose (a
/// rigid body with its mass, `subtgraph:class` naming its class) holding a `Cube` scaled to
/// its box, a collider, resting on the floor; beside it `<name>_pad`, its pad
/// ([`Artifact::pad`](subtgraph_core::artifacts::Artifact::pad)), a static cube collider of rock.
fn artifact_prims(s: &mut String, artifacts: &[subtgraph_core::artifacts::Artifact]) {
    if artifacts.is_empty() {
        return;
    }
    s.push_str("\n    def Scope \"Artifacts\"\n    {\n");
    for a in artifacts {
        let [x, y, z] = a.position;
        let [l, w, h] = a.size;
        let [r, g, b] = a.class.colour();
        let ([px, py, pz], [pl, pw, ph]) = a.pad();
        s.push_str(&format!(
            "        def Cube \"{prim}_pad\" (\n            prepend apiSchemas = [\"PhysicsCollisionAPI\", \"MaterialBindingAPI\"]\n        )\n        {{\n            double size = 1\n            color3f[] primvars:displayColor = [(0.35, 0.33, 0.3)]\n            double3 xformOp:translate = ({px:.4}, {py:.4}, {pz:.4})\n            float xformOp:rotateZ = {deg:.4}\n            float3 xformOp:scale = ({pl:.4}, {pw:.4}, {ph:.4})\n            uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:rotateZ\", \"xformOp:scale\"]\n            rel material:binding:physics = {ROCK}\n        }}\n",
            prim = a.name.replace('-', "_"),
            deg = a.yaw.to_degrees(),
        ));
        s.push_str(&format!(
            "        def Xform \"{prim}\" (\n            prepend apiSchemas = [\"PhysicsRigidBodyAPI\", \"PhysicsMassAPI\"]\n        )\n        {{\n            custom string subtgraph:class = \"{class}\"\n            custom string subtgraph:name = \"{name}\"\n            float physics:mass = {mass}\n            double3 xformOp:translate = ({x:.4}, {y:.4}, {z:.4})\n            float xformOp:rotateZ = {deg:.4}\n            uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:rotateZ\"]\n\n            def Cube \"box\" (\n                prepend apiSchemas = [\"PhysicsCollisionAPI\"]\n            )\n            {{\n                double size = 1\n                color3f[] primvars:displayColor = [({r:.3}, {g:.3}, {b:.3})]\n                double3 xformOp:translate = (0, 0, {hz:.4})\n                float3 xformOp:scale = ({l:.4}, {w:.4}, {h:.4})\n                uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:scale\"]\n            }}\n        }}\n",
            prim = a.name.replace('-', "_"),
            class = a.class.name(),
            name = a.name,
            mass = a.class.mass(),
            deg = a.yaw.to_degrees(),
            hz = 0.5 * h,
        ));
    }
    s.push_str("    }\n");
}

/// The fixtures (a mine's services) as one `PointInstancer`, `/World/Services`: each
/// prototype a mesh under it (drawn only through the instancer), each copy an entry of
/// `protoIndices`, `positions`, `orientations` (half-precision quaternions, real part first)
/// and `scales`.
fn write_fixtures(
    w: &mut dyn Write,
    mesh: &WorldMesh,
    materials: &[String],
) -> std::io::Result<()> {
    let f = &mesh.fixtures;
    w.write_all(HEADER.as_bytes())?;
    writeln!(
        w,
        "over \"World\"\n{{\n    def PointInstancer \"Services\"\n    {{"
    )?;
    let names: Vec<String> = f
        .prototypes
        .iter()
        .map(|p| format!("</World/Services/Prototypes/{}>", prim_name(p.name)))
        .collect();
    writeln!(w, "        rel prototypes = [{}]", names.join(", "))?;
    let ps = &f.placements;
    let inner = "        ";
    array(w, inner, "int[] protoIndices", ps.len(), |b, i| {
        push_uint(b, u64::from(ps[i].prototype));
    })?;
    writeln!(w)?;
    array(w, inner, "point3f[] positions", ps.len(), |b, i| {
        tuple(b, &ps[i].translation.map(|v| v as f32));
    })?;
    writeln!(w)?;
    array(w, inner, "quath[] orientations", ps.len(), |b, i| {
        let [x, y, z, r] = ps[i].rotation;
        tuple(b, &[r, x, y, z].map(|v| v as f32));
    })?;
    writeln!(w)?;
    array(w, inner, "float3[] scales", ps.len(), |b, i| {
        tuple(b, &ps[i].scale.map(|v| v as f32));
    })?;
    writeln!(w, "\n\n        def Scope \"Prototypes\"\n        {{")?;
    for k in 0..f.prototypes.len() {
        let m = crate::fixtures::prototype_mesh(f, k);
        let name = prim_name(f.prototypes[k].name);
        write_mesh(
            w,
            "            ",
            &name,
            &m,
            Role::Visual,
            materials,
            [0.0; 3],
        )?;
    }
    writeln!(w, "        }}\n    }}\n}}")
}

impl Exporter for Usd {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the USD exporter needs geometry: add a [tileset] to the pipeline (or drop --no-mesh)".into(),
            ));
        };
        let materials: Vec<String> = mesh.materials.iter().map(|m| prim_name(&m.name)).collect();
        let instances = if self.instancing {
            find_instances(mesh)
        } else {
            Instances::none(mesh)
        };
        let mut layers = Vec::new();
        if !instances.prototypes.is_empty() {
            let path = "usd/parts/prototypes.usda";
            stream_file(out, path, |w| {
                w.write_all(HEADER.as_bytes())?;
                writeln!(w, "class Scope \"Prototypes\"\n{{")?;
                for (k, p) in instances.prototypes.iter().enumerate() {
                    let m = mesh
                        .visual
                        .extract(std::slice::from_ref(&mesh.tiles[p.tile].visual_triangles));
                    writeln!(w, "    def Xform \"tile_{k}\"\n    {{")?;
                    write_mesh(
                        w,
                        "        ",
                        "visual",
                        &m,
                        Role::Visual,
                        &materials,
                        p.origin,
                    )?;
                    writeln!(w, "    }}\n")?;
                }
                writeln!(w, "}}")
            })?;
            layers.push("parts/prototypes.usda".to_owned());
        }
        let patches = survey.patches().unwrap_or(&[]);
        for part in parts(world, mesh, self.split) {
            let name = prim_name(&part.name);
            let file = format!("parts/{}.usda", part.name);
            let path = format!("usd/{file}");
            let own: Vec<std::ops::Range<usize>> = part
                .tiles
                .iter()
                .filter(|&&t| instances.of_tile[t].is_none())
                .map(|&t| mesh.tiles[t].visual_triangles.clone())
                .collect();
            let visual = mesh.visual.extract(&own);
            // Floor patches: the patched floors as colliders of their own, bound to their
            // material ("collision_mud"); without patches the one "collision" as before.
            let colliders: Vec<(String, Option<FloorMaterial>, Mesh)> =
                match crate::hazards::split_collision(patches, mesh, &part) {
                    None => vec![("collision".into(), None, part.collision(mesh))],
                    Some(groups) => groups
                        .into_iter()
                        .map(|(m, r)| {
                            let name = match m {
                                None => "collision".to_owned(),
                                Some(m) => format!("collision_{}", prim_name(m.name())),
                            };
                            (name, m, mesh.collision.extract(&r))
                        })
                        .collect(),
                };
            stream_file(out, &path, |w| {
                w.write_all(HEADER.as_bytes())?;
                writeln!(w, "over \"World\"\n{{\n    def Xform \"{name}\"\n    {{")?;
                if !visual.triangles.is_empty() {
                    write_mesh(
                        w,
                        "        ",
                        "visual",
                        &visual,
                        Role::Visual,
                        &materials,
                        [0.0; 3],
                    )?;
                }
                for (name, m, collision) in &colliders {
                    if !collision.triangles.is_empty() {
                        write_mesh(
                            w,
                            "        ",
                            name,
                            collision,
                            Role::Collision(*m),
                            &materials,
                            [0.0; 3],
                        )?;
                    }
                }
                for &t in &part.tiles {
                    if let Some((k, at)) = instances.of_tile[t] {
                        let c = mesh.tiles[t].cell;
                        let mut b = Vec::new();
                        tuple(&mut b, &at);
                        writeln!(
                            w,
                            "\n        def Xform \"tile_{}_{}_{}\" (\n            instanceable = true\n            prepend references = </Prototypes/tile_{k}>\n        )\n        {{\n            double3 xformOp:translate = {}\n            uniform token[] xformOpOrder = [\"xformOp:translate\"]\n        }}",
                            c.level,
                            c.row,
                            c.col,
                            String::from_utf8_lossy(&b)
                        )?;
                    }
                }
                writeln!(w, "    }}\n}}")
            })?;
            drop(visual);
            layers.push(file);
        }
        if !mesh.fixtures.is_empty() {
            stream_file(out, "usd/parts/services.usda", |w| {
                write_fixtures(w, mesh, &materials)
            })?;
            layers.push("parts/services.usda".to_owned());
        }
        let artifacts = crate::artifacts_of(survey);
        let root = root_layer(mesh, &layers, &materials, artifacts, patches);
        crate::text::write_textures(out, mesh)?;
        write_file(out, "usd/world.usda", root.as_bytes())
    }

    fn needs_geometry(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prim_names_are_identifiers() {
        assert_eq!(prim_name("level-0-r1-c2"), "level_0_r1_c2");
        assert_eq!(prim_name("3d"), "_3d");
        assert_eq!(prim_name("cave-wall"), "cave_wall");
    }
}

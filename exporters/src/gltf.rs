//! `mesh/world.glb`: the visual world as binary glTF 2.0, for Blender, Unity, Unreal and web
//! viewers.
//!
//! A world's fixtures (a mine's services) are instanced: one mesh per prototype (a bolt, a
//! duct segment...) and a node per copy naming it with its translation, rotation and scale,
//! so the file grows by a node, not a mesh, per bolt.
//!
//! One node and one mesh per part, one primitive per material (the primitives of a mesh share
//! its POSITION, NORMAL and TEXCOORD_0 accessors and differ by their `u32` indices), and a
//! `pbrMetallicRoughness` material per tile set material from its colour, or from its images
//! (referenced beside the GLB under `mesh/textures/`) when it has them. glTF is Y up in
//! metres, so a point (x east, y north, z up) is written as (x, z, -y): a rotation, which keeps
//! the triangles' winding (front faces seen from inside the passage). Texture coordinates are
//! flipped to glTF's top-left image origin (v becomes 1 - v).
//!
//! Written by hand (a GLB is a 12-byte header, a JSON chunk and a binary chunk) and streamed:
//! a first pass cuts each part once to size its arrays, a second cuts it again and writes it,
//! so memory holds one part at a time, never a second copy of the world. The JSON is a
//! `serde_json` value with `gltf-json`'s named constants for the GL enums; `gltf-json`'s own
//! `Root` is not used to write it, because its serialization is not ours: it writes keys in
//! struct order and writes defaults we leave out (`alphaMode`, `doubleSided`,
//! `emissiveFactor` on every material) while dropping the `mode` we state, so every GLB would
//! change for no reader's benefit (the test reads the document back with `gltf-json`).
//!
//! ```toml
//! [[export]]
//! type = "gltf"
//! split = "level"      # a node per part: "level" (default), "region" or "whole"
//! ```

use std::io::Write;

use gltf_json::accessor::{FLOAT, UNSIGNED_INT};
use gltf_json::buffer::{ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER};
use gltf_json::mesh::TRIANGLES;
use gltf_json::texture::{LINEAR, LINEAR_MIPMAP_LINEAR, REPEAT};
use serde_json::{Value, json};
use subtgraph_core::World;
use subtgraph_core::artifacts::Artifact;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, stream_file};
use subtgraph_core::mesh::{Material, Mesh};
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

use crate::fixtures;
use crate::parts::{Part, Split, parts};

/// Writes `mesh/world.glb`.
#[derive(Clone, Copy, Debug)]
pub struct Gltf {
    /// A node per part cut this way.
    pub split: Split,
}

impl Gltf {
    /// From an `[[export]] type = "gltf"` table: `split` and `region_tiles` only.
    pub fn from_params(params: &Params) -> Result<Gltf, ConfigError> {
        params.expect_known(&Split::KEYS)?;
        Ok(Gltf {
            split: Split::from_params(params)?,
        })
    }
}

/// Our frame (x east, y north, z up) to glTF's (y up, -z north).
fn y_up(p: [f32; 3]) -> [f32; 3] {
    [p[0], p[2], -p[1]]
}

/// What the first pass learns about a part.
struct Sizes {
    vertices: usize,
    normals: bool,
    uvs: bool,
    /// Triangles per material index.
    per_material: Vec<usize>,
    min: [f32; 3],
    max: [f32; 3],
}

fn material_of(mesh: &Mesh, t: usize) -> usize {
    usize::from(mesh.materials.get(t).copied().unwrap_or(0))
}

fn sizes(m: &Mesh, materials: usize) -> Sizes {
    let mut per_material = vec![0; materials.max(1)];
    for t in 0..m.triangles.len() {
        let k = material_of(m, t).min(per_material.len() - 1);
        per_material[k] += 1;
    }
    let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for &p in &m.positions {
        let q = y_up(p);
        for k in 0..3 {
            min[k] = min[k].min(q[k]);
            max[k] = max[k].max(q[k]);
        }
    }
    Sizes {
        vertices: m.positions.len(),
        normals: m.normals.len() == m.positions.len(),
        uvs: m.uvs.len() == m.positions.len(),
        per_material,
        min,
        max,
    }
}

/// A tile set material as glTF PBR: its colour, or with images its albedo
/// (`baseColorTexture`), roughness (`metallicRoughnessTexture`'s green; metallic 0) and
/// normal map, each added to `images` (URIs relative to the GLB) once.
fn material<'a>(m: &'a Material, images: &mut Vec<&'a str>) -> Value {
    let [r, g, b] = m.colour;
    let mut index = |uri: &'a str| match images.iter().position(|u| *u == uri) {
        Some(i) => i,
        None => {
            images.push(uri);
            images.len() - 1
        }
    };
    let mut pbr =
        json!({"baseColorFactor": [r, g, b, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9});
    let mut out = json!({"name": m.name});
    if let Some(t) = &m.texture {
        pbr["baseColorFactor"] = json!([1.0, 1.0, 1.0, 1.0]);
        pbr["baseColorTexture"] = json!({"index": index(t)});
    }
    if let Some(t) = &m.roughness_map {
        pbr["roughnessFactor"] = json!(1.0);
        pbr["metallicRoughnessTexture"] = json!({"index": index(t)});
    }
    if let Some(t) = &m.normal_map {
        out["normalTexture"] = json!({"index": index(t)});
    }
    out["pbrMetallicRoughness"] = pbr;
    out
}

/// The JSON document and the binary chunk's length.
/// `names` and `sizes` are per mesh: the first `parts` the parts, each with a node, then the
/// fixtures' prototypes, placed by the `instances` nodes.
fn document(
    names: &[&str],
    sizes: &[Sizes],
    parts: usize,
    materials: &[Value],
    instances: Vec<Value>,
    artifacts: &[Artifact],
) -> (Value, usize) {
    let mut materials = materials.to_vec();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut meshes = Vec::new();
    let mut offset = 0usize;
    let mut view = |len: usize, target: u32, views: &mut Vec<Value>| {
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": len, "target": target}));
        offset += len;
        views.len() - 1
    };
    for (part, s) in names.iter().zip(sizes) {
        let mut attributes = serde_json::Map::new();
        let v = view(s.vertices * 12, ARRAY_BUFFER, &mut views);
        accessors.push(
            json!({"bufferView": v, "componentType": FLOAT, "count": s.vertices,
            "type": "VEC3", "min": s.min, "max": s.max}),
        );
        attributes.insert("POSITION".into(), json!(accessors.len() - 1));
        if s.normals {
            let v = view(s.vertices * 12, ARRAY_BUFFER, &mut views);
            accessors.push(json!({"bufferView": v, "componentType": FLOAT, "count": s.vertices, "type": "VEC3"}));
            attributes.insert("NORMAL".into(), json!(accessors.len() - 1));
        }
        if s.uvs {
            let v = view(s.vertices * 8, ARRAY_BUFFER, &mut views);
            accessors.push(json!({"bufferView": v, "componentType": FLOAT, "count": s.vertices, "type": "VEC2"}));
            attributes.insert("TEXCOORD_0".into(), json!(accessors.len() - 1));
        }
        let mut primitives = Vec::new();
        for (m, &n) in s.per_material.iter().enumerate().filter(|(_, n)| **n > 0) {
            let v = view(n * 12, ELEMENT_ARRAY_BUFFER, &mut views);
            accessors.push(
                json!({"bufferView": v, "componentType": UNSIGNED_INT, "count": n * 3, "type": "SCALAR"}),
            );
            let mut p = json!({"attributes": attributes.clone(), "indices": accessors.len() - 1, "mode": TRIANGLES});
            if m < materials.len() {
                p["material"] = json!(m);
            }
            primitives.push(p);
        }
        meshes.push(json!({"name": part, "primitives": primitives}));
    }
    let mut nodes: Vec<Value> = names[..parts]
        .iter()
        .enumerate()
        .map(|(i, p)| json!({"name": p, "mesh": i}))
        .collect();
    nodes.extend(instances);
    if !artifacts.is_empty() {
        // One unit cube (24 vertices with flat normals, 36 indices), a mesh per class using
        // it with the class's material, and a node per artifact scaling it to its box.
        let v = view(24 * 12, 34962, &mut views);
        accessors.push(json!({"bufferView": v, "componentType": 5126, "count": 24,
            "type": "VEC3", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}));
        let position = accessors.len() - 1;
        let v = view(24 * 12, 34962, &mut views);
        accessors
            .push(json!({"bufferView": v, "componentType": 5126, "count": 24, "type": "VEC3"}));
        let normal = accessors.len() - 1;
        let v = view(36 * 4, 34963, &mut views);
        accessors
            .push(json!({"bufferView": v, "componentType": 5125, "count": 36, "type": "SCALAR"}));
        let indices = accessors.len() - 1;
        let mut mesh_of = std::collections::BTreeMap::new();
        for a in artifacts {
            let mesh = *mesh_of.entry(a.class).or_insert_with(|| {
                let [r, g, b] = a.class.colour();
                materials.push(json!({"name": format!("artifact-{}", a.class.name()),
                    "pbrMetallicRoughness": {"baseColorFactor": [r, g, b, 1.0],
                    "metallicFactor": 0.0, "roughnessFactor": 0.6}}));
                meshes.push(
                    json!({"name": format!("artifact-{}", a.class.name()), "primitives": [{
                    "attributes": {"POSITION": position, "NORMAL": normal},
                    "indices": indices, "mode": 4, "material": materials.len() - 1}]}),
                );
                meshes.len() - 1
            });
            let [x, y, z] = a.centre();
            let [l, w, h] = a.size;
            let half = 0.5 * a.yaw;
            // Z up to Y up: a turn about z is the same turn about Y.
            nodes.push(json!({"name": format!("artifact-{}", a.name), "mesh": mesh,
                "translation": [x, z, -y], "rotation": [0.0, half.sin(), 0.0, half.cos()],
                "scale": [l, h, w], "extras": {"class": a.class.name()}}));
        }
    }
    let doc = json!({
        "asset": {
            "version": "2.0",
            "generator": format!("subtgraph {}", env!("CARGO_PKG_VERSION")),
        },
        "scene": 0,
        "scenes": [{"name": "subtgraph", "nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": offset}],
    });
    (doc, offset)
}

/// Writes little-endian `f32`s, a buffer's worth at a time.
fn floats(
    w: &mut dyn Write,
    count: usize,
    per: usize,
    value: impl Fn(usize, &mut [f32]),
) -> std::io::Result<()> {
    const BATCH: usize = 1 << 14;
    let mut buf = Vec::with_capacity(BATCH * per * 4);
    let mut v = vec![0f32; per];
    for i in 0..count {
        value(i, &mut v);
        for x in &v {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        if buf.len() >= BATCH * per * 4 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

fn write_part(w: &mut dyn Write, m: &Mesh, s: &Sizes) -> std::io::Result<()> {
    floats(w, s.vertices, 3, |i, v| {
        v.copy_from_slice(&y_up(m.positions[i]))
    })?;
    if s.normals {
        floats(w, s.vertices, 3, |i, v| {
            v.copy_from_slice(&y_up(m.normals[i]))
        })?;
    }
    if s.uvs {
        floats(w, s.vertices, 2, |i, v| {
            v.copy_from_slice(&[m.uvs[i][0], 1.0 - m.uvs[i][1]]);
        })?;
    }
    let last = s.per_material.len() - 1;
    for (k, &n) in s.per_material.iter().enumerate().filter(|(_, n)| **n > 0) {
        let mut buf = Vec::with_capacity(n * 12);
        for (t, tri) in m.triangles.iter().enumerate() {
            if material_of(m, t).min(last) == k {
                for i in tri {
                    buf.extend_from_slice(&i.to_le_bytes());
                }
            }
        }
        w.write_all(&buf)?;
    }
    Ok(())
}

/// The unit cube of the artifacts, in glTF's Y-up frame: positions, normals, indices.
fn write_cube(w: &mut dyn Write) -> std::io::Result<()> {
    let mut positions = Vec::with_capacity(24);
    let mut normals = Vec::with_capacity(24);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            // Corners counter-clockwise seen from outside.
            let corners: [[f32; 2]; 4] = if sign > 0.0 {
                [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]
            } else {
                [[-0.5, -0.5], [-0.5, 0.5], [0.5, 0.5], [0.5, -0.5]]
            };
            for [a, b] in corners {
                let mut p = [0f32; 3];
                p[axis] = 0.5 * sign;
                p[u] = a;
                p[v] = b;
                positions.push(p);
                let mut n = [0f32; 3];
                n[axis] = sign;
                normals.push(n);
            }
        }
    }
    floats(w, 24, 3, |i, v| v.copy_from_slice(&positions[i]))?;
    floats(w, 24, 3, |i, v| v.copy_from_slice(&normals[i]))?;
    let mut buf = Vec::with_capacity(36 * 4);
    for f in 0..6u32 {
        for k in [0, 1, 2, 0, 2, 3] {
            buf.extend_from_slice(&(4 * f + k).to_le_bytes());
        }
    }
    w.write_all(&buf)
}

impl Exporter for Gltf {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the glTF exporter needs geometry: add a [tileset] to the pipeline (or drop --no-mesh)".into(),
            ));
        };
        let ps: Vec<Part> = parts(world, mesh, self.split)
            .into_iter()
            .filter(|p| p.visual_triangles() > 0)
            .collect();
        let f = &mesh.fixtures;
        let prototypes: Vec<Mesh> = (0..f.prototypes.len())
            .map(|k| fixtures::prototype_mesh(f, k))
            .collect();
        let sized: Vec<Sizes> = ps
            .iter()
            .map(|p| p.visual(mesh))
            .chain(prototypes.iter().cloned())
            .map(|m| sizes(&m, mesh.materials.len()))
            .collect();
        let names: Vec<&str> = ps
            .iter()
            .map(|p| p.name.as_str())
            .chain(f.prototypes.iter().map(|p| p.name))
            .collect();
        // A node per copy naming its prototype's mesh (after the parts' meshes).
        let instances: Vec<Value> = f
            .placements
            .iter()
            .map(|p| {
                // As f32, the precision of the meshes (and a third of the JSON).
                let (t, r, s) = fixtures::y_up(p);
                let (t, r, s) = (
                    t.map(|v| v as f32),
                    r.map(|v| v as f32),
                    s.map(|v| v as f32),
                );
                let name = f.prototypes[p.prototype as usize].name;
                json!({"name": name, "mesh": ps.len() + p.prototype as usize,
                    "translation": t, "rotation": r, "scale": s})
            })
            .collect();
        let mut images: Vec<&str> = Vec::new();
        let materials: Vec<Value> = mesh
            .materials
            .iter()
            .map(|m| material(m, &mut images))
            .collect();
        let artifacts = crate::artifacts_of(survey);
        let (mut doc, bin_len) =
            document(&names, &sized, ps.len(), &materials, instances, artifacts);
        if !images.is_empty() {
            // Referenced beside the GLB (`mesh/textures/`), not embedded: the images are
            // shared with the other formats and the GLB stays the geometry.
            doc["images"] = json!(images.iter().map(|u| json!({"uri": u})).collect::<Vec<_>>());
            doc["textures"] = json!(
                (0..images.len())
                    .map(|i| json!({"source": i, "sampler": 0}))
                    .collect::<Vec<_>>()
            );
            doc["samplers"] = json!([{"magFilter": LINEAR, "minFilter": LINEAR_MIPMAP_LINEAR,
                "wrapS": REPEAT, "wrapT": REPEAT}]);
            crate::text::write_textures(out, mesh)?;
        }
        let mut text = serde_json::to_vec(&doc).expect("JSON of plain values");
        while text.len() % 4 != 0 {
            text.push(b' ');
        }
        let total = 12 + 8 + text.len() + 8 + bin_len;
        let too_big = || {
            ExportError::Unsupported(format!(
                "the world is {total} bytes as GLB, over the format's 4 GiB; use split = \"region\" with fewer tiles or another format"
            ))
        };
        let total32 = u32::try_from(total).map_err(|_| too_big())?;
        stream_file(out, "mesh/world.glb", |w| {
            w.write_all(b"glTF")?;
            w.write_all(&2u32.to_le_bytes())?;
            w.write_all(&total32.to_le_bytes())?;
            w.write_all(&(text.len() as u32).to_le_bytes())?;
            w.write_all(b"JSON")?;
            w.write_all(&text)?;
            w.write_all(&(bin_len as u32).to_le_bytes())?;
            w.write_all(b"BIN\0")?;
            for (p, s) in ps.iter().zip(&sized) {
                write_part(w, &p.visual(mesh), s)?;
            }
            for (m, s) in prototypes.iter().zip(&sized[ps.len()..]) {
                write_part(w, m, s)?;
            }
            if !artifacts.is_empty() {
                write_cube(w)?;
            }
            Ok(())
        })
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
    fn chunks_are_aligned_and_the_buffer_is_as_long_as_declared() {
        let world = crate::test_world_with_mesh();
        let mut out = MemoryWriter::default();
        Gltf {
            split: Split::Level,
        }
        .export(&world, &crate::survey_of(&world), &mut out)
        .unwrap();
        let glb = out.get("mesh/world.glb").unwrap();
        let u32_at = |i: usize| u32::from_le_bytes(glb[i..i + 4].try_into().unwrap()) as usize;
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(u32_at(8), glb.len());
        let json_len = u32_at(12);
        assert_eq!(json_len % 4, 0);
        let doc: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        let bin_len = u32_at(20 + json_len);
        assert_eq!(&glb[24 + json_len..28 + json_len], b"BIN\0");
        assert_eq!(28 + json_len + bin_len, glb.len());
        assert_eq!(doc["buffers"][0]["byteLength"], bin_len);
        assert_eq!(
            doc["nodes"].as_array().unwrap().len(),
            2,
            "a node per level"
        );
        // The document is glTF as gltf-json reads it, and valid by its checks.
        let root: gltf_json::Root =
            gltf_json::deserialize::from_slice(&glb[20..20 + json_len]).unwrap();
        let mut problems = Vec::new();
        gltf_json::validation::Validate::validate(
            &root,
            &root,
            gltf_json::Path::new,
            &mut |p, e| problems.push(format!("{}: {e}", p())),
        );
        assert!(problems.is_empty(), "{problems:?}");
        assert_eq!(root.meshes.len(), 2);
    }
}

//! Reading mesh files in pure Rust: Wavefront OBJ, Collada and STL through `mesh-loader`,
//! glTF and GLB through `gltf`. Every part keeps its name, so materials can be matched.

use std::path::Path;

/// One named part of a mesh file, in the file's own frame and units.
#[derive(Clone, Debug, Default)]
pub struct Part {
    /// Object, mesh or material name.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Vertex normals, if the file has them.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates, if the file has them.
    pub uvs: Vec<[f32; 2]>,
    /// Triangles.
    pub triangles: Vec<[u32; 3]>,
}

/// Loads every part of a mesh file. The error says what is wrong and with which file.
pub fn load(path: &Path) -> Result<Vec<Part>, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let parts = match ext.as_str() {
        "obj" | "dae" | "stl" => load_with_mesh_loader(path)?,
        "glb" | "gltf" => load_gltf(path)?,
        other => {
            return Err(format!(
                "{}: unsupported mesh format '.{other}'; use OBJ, Collada (.dae), STL, glTF or GLB \
                 (formats only assimp reads, like FBX, need the `assimp` feature)",
                path.display()
            ));
        }
    };
    // Indices come from the file: one past the vertices would panic later, not here.
    for p in &parts {
        let n = p.positions.len();
        if let Some(t) = p
            .triangles
            .iter()
            .find(|t| t.iter().any(|&i| i as usize >= n))
        {
            return Err(format!(
                "{}: part '{}' has a triangle {t:?} that refers past its {n} vertices; the file is corrupt",
                path.display(),
                subtgraph_core::error::excerpt(&p.name)
            ));
        }
    }
    if parts.iter().all(|p| p.triangles.is_empty()) {
        return Err(format!("{}: the file has no triangles", path.display()));
    }
    Ok(parts)
}

fn load_with_mesh_loader(path: &Path) -> Result<Vec<Part>, String> {
    if !path.is_file() {
        return Err(format!("{}: no such file", path.display()));
    }
    // Read once: the bytes feed both mesh-loader and the material names below (what
    // `Loader::load` does, reading the file itself, would read an OBJ twice).
    let bytes =
        std::fs::read(path).map_err(|e| format!("{}: cannot be read: {e}", path.display()))?;
    let scene = mesh_loader::Loader::default()
        .load_from_slice(&bytes, path)
        .map_err(|e| format!("{}: cannot be read: {e}", path.display()))?;
    let mut parts: Vec<Part> = scene
        .meshes
        .into_iter()
        .map(|m| Part {
            name: m.name,
            positions: m.vertices,
            normals: m.normals,
            uvs: m.texcoords[0].clone(),
            triangles: m.faces,
        })
        .collect();
    // mesh-loader splits an OBJ by material but does not name the parts: take the material
    // names in the order they first appear.
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
    {
        let text = std::str::from_utf8(&bytes).unwrap_or_default();
        let mut names: Vec<&str> = Vec::new();
        for line in text.lines() {
            if let Some(n) = line.strip_prefix("usemtl ") {
                let n = n.trim();
                if !names.contains(&n) {
                    names.push(n);
                }
            }
        }
        if names.len() == parts.len() {
            for (p, n) in parts.iter_mut().zip(names) {
                p.name = n.to_owned();
            }
        }
    }
    Ok(parts)
}

fn load_gltf(path: &Path) -> Result<Vec<Part>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let gltf = gltf::Gltf::from_slice(&bytes)
        .map_err(|e| format!("{}: not valid glTF: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for b in gltf.buffers() {
        buffers.push(match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| format!("{}: missing binary chunk", path.display()))?,
            gltf::buffer::Source::Uri(uri) => {
                if uri.starts_with("data:") {
                    return Err(format!(
                        "{}: embedded data URIs are not supported; save as GLB or with a .bin file",
                        path.display()
                    ));
                }
                let p = dir.join(uri);
                std::fs::read(&p)
                    .map_err(|e| format!("{}: buffer {}: {e}", path.display(), p.display()))?
            }
        });
    }
    let mut parts = Vec::new();
    let scene = gltf
        .default_scene()
        .or_else(|| gltf.scenes().next())
        .ok_or_else(|| format!("{}: no scene", path.display()))?;
    let mut stack: Vec<(gltf::Node, [[f32; 4]; 4])> =
        scene.nodes().map(|n| (n, identity())).collect();
    while let Some((node, parent)) = stack.pop() {
        let m = mul(parent, node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
                let positions: Vec<[f32; 3]> = reader
                    .read_positions()
                    .ok_or_else(|| format!("{}: a primitive has no positions", path.display()))?
                    .map(|p| transform(m, p, 1.0))
                    .collect();
                let normals = reader
                    .read_normals()
                    .map(|n| n.map(|v| transform(m, v, 0.0)).collect())
                    .unwrap_or_default();
                let uvs = reader
                    .read_tex_coords(0)
                    .map(|t| t.into_f32().collect())
                    .unwrap_or_default();
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                parts.push(Part {
                    name: prim
                        .material()
                        .name()
                        .or(mesh.name())
                        .unwrap_or("")
                        .to_owned(),
                    positions,
                    normals,
                    uvs,
                    triangles: indices
                        .chunks_exact(3)
                        .map(|c| [c[0], c[1], c[2]])
                        .collect(),
                });
            }
        }
        for child in node.children() {
            stack.push((child, m));
        }
    }
    Ok(parts)
}

fn identity() -> [[f32; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

/// Column-major 4x4 product `a * b`, as glTF stores matrices.
fn mul(a: [[f32; 4]; 4], b: [[f32; 4]; 4]) -> [[f32; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for (c, col) in out.iter_mut().enumerate() {
        for (r, v) in col.iter_mut().enumerate() {
            *v = (0..4).map(|k| a[k][r] * b[c][k]).sum();
        }
    }
    out
}

fn transform(m: [[f32; 4]; 4], p: [f32; 3], w: f32) -> [f32; 3] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r] * w)
}

//! Reading mesh files in pure Rust: Wavefront OBJ, Collada and STL through `mesh-loader`,
//! glTF and GLB through `gltf`. Every part keeps its name, so materials can be matched.

use std::path::{Path, PathBuf};

/// Why a mesh file cannot be loaded. Each message names the file and what to do.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshFileError {
    /// The file is not there.
    #[error("{}: no such file", path.display())]
    Missing {
        /// The file.
        path: PathBuf,
    },
    /// The file (or a glTF's buffer) could not be read or parsed: `reason` is the reader's.
    #[error("{}: cannot be read: {reason}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// What the reader reported.
        reason: String,
    },
    /// A format we have no reader for.
    #[error(
        "{}: unsupported mesh format '.{extension}'; use OBJ, Collada (.dae), STL, glTF or GLB \
         (formats only assimp reads, like FBX, need the `assimp` feature)",
        path.display()
    )]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// Its extension, lower case.
        extension: String,
    },
    /// A glTF file whose JSON or GLB container is not valid glTF.
    #[error("{}: not valid glTF: {reason}", path.display())]
    InvalidGltf {
        /// The file.
        path: PathBuf,
        /// What the glTF reader reported.
        reason: String,
    },
    /// A glTF feature we do not read (embedded data URIs, no scene, no binary chunk, a
    /// primitive without positions): `what` says which and how to save the file instead.
    #[error("{}: {what}", path.display())]
    UnsupportedGltf {
        /// The file.
        path: PathBuf,
        /// What is missing or unsupported, and what to do.
        what: &'static str,
    },
    /// A glTF buffer file that cannot be read.
    #[error("{}: buffer {}: {reason}", path.display(), buffer.display())]
    Buffer {
        /// The glTF file.
        path: PathBuf,
        /// The buffer's file.
        buffer: PathBuf,
        /// Why it cannot be read.
        reason: String,
    },
    /// A triangle refers to a vertex the part does not have.
    #[error(
        "{}: part '{}' has a triangle {triangle:?} that refers past its {vertices} vertices; the \
         file is corrupt",
        path.display(),
        subtgraph_core::error::excerpt(part)
    )]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// The part's name.
        part: String,
        /// The triangle.
        triangle: [u32; 3],
        /// How many vertices the part has.
        vertices: usize,
    },
    /// Nothing to place.
    #[error("{}: the file has no triangles", path.display())]
    NoTriangles {
        /// The file.
        path: PathBuf,
    },
}

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
pub fn load(path: &Path) -> Result<Vec<Part>, MeshFileError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let parts = match ext.as_str() {
        "obj" | "dae" | "stl" => load_with_mesh_loader(path)?,
        "glb" | "gltf" => load_gltf(path)?,
        other => {
            return Err(MeshFileError::Unsupported {
                path: path.to_owned(),
                extension: other.to_owned(),
            });
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
            return Err(MeshFileError::Corrupt {
                path: path.to_owned(),
                part: p.name.clone(),
                triangle: *t,
                vertices: n,
            });
        }
    }
    if parts.iter().all(|p| p.triangles.is_empty()) {
        return Err(MeshFileError::NoTriangles {
            path: path.to_owned(),
        });
    }
    Ok(parts)
}

fn load_with_mesh_loader(path: &Path) -> Result<Vec<Part>, MeshFileError> {
    if !path.is_file() {
        return Err(MeshFileError::Missing {
            path: path.to_owned(),
        });
    }
    let unreadable = |e: std::io::Error| MeshFileError::Unreadable {
        path: path.to_owned(),
        reason: e.to_string(),
    };
    // Read once: the bytes feed both mesh-loader and the material names below (what
    // `Loader::load` does, reading the file itself, would read an OBJ twice).
    let bytes = std::fs::read(path).map_err(unreadable)?;
    let scene = mesh_loader::Loader::default()
        .load_from_slice(&bytes, path)
        .map_err(unreadable)?;
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

fn load_gltf(path: &Path) -> Result<Vec<Part>, MeshFileError> {
    let unsupported = |what: &'static str| MeshFileError::UnsupportedGltf {
        path: path.to_owned(),
        what,
    };
    let bytes = std::fs::read(path).map_err(|e| MeshFileError::Unreadable {
        path: path.to_owned(),
        reason: e.to_string(),
    })?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| MeshFileError::InvalidGltf {
        path: path.to_owned(),
        reason: e.to_string(),
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for b in gltf.buffers() {
        buffers.push(match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| unsupported("missing binary chunk"))?,
            gltf::buffer::Source::Uri(uri) => {
                if uri.starts_with("data:") {
                    return Err(unsupported(
                        "embedded data URIs are not supported; save as GLB or with a .bin file",
                    ));
                }
                let p = dir.join(uri);
                std::fs::read(&p).map_err(|e| MeshFileError::Buffer {
                    path: path.to_owned(),
                    buffer: p.clone(),
                    reason: e.to_string(),
                })?
            }
        });
    }
    let mut parts = Vec::new();
    let scene = gltf
        .default_scene()
        .or_else(|| gltf.scenes().next())
        .ok_or_else(|| unsupported("no scene"))?;
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
                    .ok_or_else(|| unsupported("a primitive has no positions"))?
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

//! Text the writers share: numbers formatted without `format!` (the mesh formats write
//! hundreds of millions of them), lines formatted in parallel and written in order, and XML
//! escaping, and the OBJ text that the OBJ exporter and every per-part mesh use. They live here, not in one format's module, so that no writer imports another.

use rayon::prelude::*;
use subtgraph_core::mesh::{Material, Mesh};

/// Appends `v` with four decimals.
pub(crate) fn push_fixed(buf: &mut Vec<u8>, v: f32) {
    let x = f64::from(v) * 10_000.0;
    // Round half away from zero; `as` truncates toward zero (and is far cheaper than `round`).
    let scaled = (x + if x >= 0.0 { 0.5 } else { -0.5 }) as i64;
    if scaled < 0 {
        buf.push(b'-');
    }
    let a = scaled.unsigned_abs();
    push_uint(buf, a / 10_000);
    let frac = a % 10_000;
    buf.push(b'.');
    buf.extend_from_slice(&[
        b'0' + (frac / 1000) as u8,
        b'0' + (frac / 100 % 10) as u8,
        b'0' + (frac / 10 % 10) as u8,
        b'0' + (frac % 10) as u8,
    ]);
}

/// Appends an unsigned integer in decimal.
pub(crate) fn push_uint(buf: &mut Vec<u8>, v: u64) {
    buf.extend_from_slice(itoa::Buffer::new().format(v).as_bytes());
}

/// Lines formatted per parallel chunk; chunks are written in order as they are formatted, so
/// memory stays bounded by a few chunks whatever the mesh size.
const CHUNK: usize = 1 << 16;

/// Formats `count` lines in parallel, `CHUNK` at a time, and writes them in order: the output
/// does not depend on the thread count. The next batch is formatted while the current one is
/// written, so the cores keep formatting while the kernel copies bytes. Other text formats use
/// it too.
pub(crate) fn write_lines(
    w: &mut dyn std::io::Write,
    count: usize,
    line: impl Fn(&mut Vec<u8>, usize) + Sync,
) -> std::io::Result<()> {
    let batch = CHUNK * rayon::current_num_threads().max(1) * 2;
    let format = |start: usize| -> Vec<Vec<u8>> {
        let end = (start + batch).min(count);
        (start..end)
            .step_by(CHUNK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|from| {
                let to = (from + CHUNK).min(end);
                let mut buf = Vec::with_capacity((to - from) * 48);
                for i in from..to {
                    line(&mut buf, i);
                }
                buf
            })
            .collect()
    };
    if count == 0 {
        return Ok(());
    }
    std::thread::scope(|scope| {
        let mut start = 0;
        let mut ready = Some(format(0));
        while let Some(chunks) = ready.take() {
            let next = start + batch;
            let pending = (next < count).then(|| scope.spawn(move || format(next)));
            for c in &chunks {
                w.write_all(c)?;
            }
            ready = pending.map(|h| h.join().expect("formatting a batch of lines panicked"));
            start = next;
        }
        Ok(())
    })
}

/// Escapes text for an XML attribute or element (names come from tile sets and part names).
/// Text without `&`, `<`, `>` or `\"` comes back unchanged.
pub(crate) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The MTL text for a tile set's materials, its image paths prefixed by `to_mesh` (the way
/// from the MTL's folder to the world folder's `mesh/`: `""` beside `world.obj`).
///
/// Textured materials keep their mean colour as `Kd` (what a reader without textures shows)
/// and name the albedo `map_Kd`, the tangent-space normal map `norm` and the roughness
/// `map_Pr` (the PBR extension of MTL that Blender, tinyobjloader and assimp read).
pub(crate) fn mtl(materials: &[Material], to_mesh: &str) -> String {
    let mut s = String::from("# subtgraph materials\n");
    for m in materials {
        let [r, g, b] = m.colour;
        s.push_str(&format!(
            "\nnewmtl {}\nKa 0 0 0\nKd {r:.4} {g:.4} {b:.4}\nKs 0.05 0.05 0.05\nNs 10\nd 1\nillum 2\n",
            m.name
        ));
        for (tag, map) in [
            ("map_Kd", &m.texture),
            ("norm", &m.normal_map),
            ("map_Pr", &m.roughness_map),
        ] {
            if let Some(t) = map {
                s.push_str(&format!("{tag} {to_mesh}{t}\n"));
            }
        }
    }
    s
}

/// Writes `mesh/world.mtl` and the texture images it names, unless an earlier exporter of the
/// same world folder already did: the OBJ exporter, and the SDF exporter's services, name it.
pub(crate) fn write_world_mtl(
    out: &mut dyn subtgraph_core::export::WorldWriter,
    mesh: &subtgraph_core::assembly::WorldMesh,
) -> Result<(), subtgraph_core::export::ExportError> {
    if !out.contains("mesh/world.mtl") {
        subtgraph_core::export::write_file(
            out,
            "mesh/world.mtl",
            mtl(&mesh.materials, "").as_bytes(),
        )?;
        write_textures(out, mesh)?;
    }
    Ok(())
}

/// Writes the world's texture images under `mesh/`, unless an earlier exporter of the same
/// world folder already did: every format that names them calls this.
pub(crate) fn write_textures(
    out: &mut dyn subtgraph_core::export::WorldWriter,
    mesh: &subtgraph_core::assembly::WorldMesh,
) -> Result<(), subtgraph_core::export::ExportError> {
    for f in &mesh.textures {
        let path = format!("mesh/{}", f.path);
        if !out.contains(&path) {
            subtgraph_core::export::write_file(out, &path, &f.bytes)?;
        }
    }
    Ok(())
}

/// Writes one mesh as one OBJ object, with `(materials, mtllib file name)` when its triangles
/// are to be grouped by material.
pub(crate) fn write_obj(
    w: &mut dyn std::io::Write,
    mesh: &Mesh,
    name: &str,
    materials: Option<(&[Material], &str)>,
) -> std::io::Result<()> {
    w.write_all(b"# subtgraph world mesh: metres, x east, y north, z up\n")?;
    if let Some((_, lib)) = materials {
        w.write_all(format!("mtllib {lib}\n").as_bytes())?;
    }
    w.write_all(format!("o {name}\n").as_bytes())?;
    let line3 = |buf: &mut Vec<u8>, tag: &[u8], v: &[f32]| {
        buf.extend_from_slice(tag);
        for (i, x) in v.iter().enumerate() {
            if i > 0 {
                buf.push(b' ');
            }
            push_fixed(buf, *x);
        }
        buf.push(b'\n');
    };
    write_lines(w, mesh.positions.len(), |b, i| {
        line3(b, b"v ", &mesh.positions[i])
    })?;
    let with_uv = mesh.uvs.len() == mesh.positions.len();
    let with_n = mesh.normals.len() == mesh.positions.len();
    if with_uv {
        write_lines(w, mesh.uvs.len(), |b, i| line3(b, b"vt ", &mesh.uvs[i]))?;
    }
    if with_n {
        write_lines(w, mesh.normals.len(), |b, i| {
            line3(b, b"vn ", &mesh.normals[i])
        })?;
    }
    // Faces grouped by material, in a stable order.
    let mut order: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
    let material_of = |i: u32| mesh.materials.get(i as usize).copied().unwrap_or(0);
    if materials.is_some() {
        order.sort_by_key(|&i| material_of(i));
    }
    let face = |buf: &mut Vec<u8>, k: usize| {
        buf.extend_from_slice(b"f");
        for &v in &mesh.triangles[order[k] as usize] {
            buf.push(b' ');
            let start = buf.len();
            push_uint(buf, u64::from(v) + 1);
            let end = buf.len();
            // The same index serves position, texture coordinate and normal.
            if with_uv || with_n {
                buf.push(b'/');
                if with_uv {
                    buf.extend_from_within(start..end);
                }
                if with_n {
                    buf.push(b'/');
                    buf.extend_from_within(start..end);
                }
            }
        }
        buf.push(b'\n');
    };
    let mut k = 0;
    while k < order.len() {
        let m = material_of(order[k]);
        let run = if materials.is_some() {
            order[k..].partition_point(|&i| material_of(i) == m) + k
        } else {
            order.len()
        };
        if let Some((mats, _)) = materials {
            let name = mats
                .get(usize::from(m))
                .map_or("default", |m| m.name.as_str());
            w.write_all(format!("usemtl {name}\n").as_bytes())?;
        }
        write_lines(w, run - k, |b, i| face(b, k + i))?;
        k = run;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_escapes() {
        let mut b = Vec::new();
        push_fixed(&mut b, -1.23456);
        b.push(b' ');
        push_uint(&mut b, 18_446_744_073_709_551_615);
        b.push(b' ');
        push_fixed(&mut b, 0.00004);
        assert_eq!(
            String::from_utf8(b).unwrap(),
            "-1.2346 18446744073709551615 0.0000"
        );
        assert_eq!(xml_escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
        assert_eq!(xml_escape("tile-3_b"), "tile-3_b");
    }

    #[test]
    fn fixed_point_numbers_read_back() {
        for v in [0.0f32, 1.5, -2.25, 1234.5678, -0.00004, 0.99996, -1e-9] {
            let mut b = Vec::new();
            push_fixed(&mut b, v);
            let s = String::from_utf8(b).unwrap();
            let back: f64 = s.parse().unwrap();
            assert!((back - f64::from(v)).abs() <= 0.00005 + 1e-9, "{v} -> {s}");
        }
    }
}

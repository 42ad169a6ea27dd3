//! Digests of a world folder's files, recorded in its `.subtgraph-files` list: what tells a
//! `world.toml` or a ground-truth file edited after the world was made.
//!
//! Why: `sense` rebuilds a world from its `world.toml` (the seed and the whole resolved
//! pipeline) rather than reading its meshes, and plans its route on `ground_truth/graph.json`.
//! An edited `world.toml` makes another world than the folder's meshes and ground truth, and
//! an edited graph sends the route elsewhere (a point moved 10,000 km once cost 4 GB). The
//! list's sizes catch a cut file, not an edit of the same length (`seed = 5` to `seed = 6`).
//!
//! So a world folder's list also carries a CRC-32 of every file of at most [`MAX_DIGESTED`]
//! bytes, one line each: `# crc32 HEX PATH`. They are comment lines on purpose: a version that
//! does not know digests reads the list as before. Larger files (meshes, scene files) keep
//! their size alone: they are written around the page cache, reading them back would cost a
//! generate its time, and `sense` does not read them. The check is independent of what
//! `world.toml` holds or how it is laid out: it compares bytes.

use std::path::Path;

use super::manifest;

/// Files up to this size get a digest: 16 MiB (a `world.toml`, the JSON ground truth, the
/// maps and grids of every preset).
pub const MAX_DIGESTED: u64 = 16 << 20;

/// How a digest line starts.
const PREFIX: &str = "# crc32 ";

/// The digest lines of the `files` under `root` (those of at most [`MAX_DIGESTED`] bytes).
pub fn lines(root: &Path, files: &[(String, u64)]) -> std::io::Result<String> {
    let mut text = String::new();
    for (path, size) in files.iter().filter(|(_, s)| *s <= MAX_DIGESTED) {
        let bytes = std::fs::read(root.join(path))?;
        if bytes.len() as u64 != *size {
            // Listed a moment ago: only another program could change it meanwhile.
            return Err(std::io::Error::other(format!(
                "{path} changed while the folder was being sealed"
            )));
        }
        text.push_str(&format!("{PREFIX}{:08x} {path}\n", crc32fast::hash(&bytes)));
    }
    Ok(text)
}

/// The digests a folder's list records, `(path, CRC-32)`; `None` when it records none (a
/// folder of another kind, or made by a version before digests).
pub fn recorded(dir: &Path) -> Option<Vec<(String, u32)>> {
    let text = std::fs::read_to_string(dir.join(manifest::FILE)).ok()?;
    let found: Vec<(String, u32)> = text
        .lines()
        .filter_map(|l| {
            let (hex, path) = l.strip_prefix(PREFIX)?.split_once(' ')?;
            Some((path.to_owned(), u32::from_str_radix(hex, 16).ok()?))
        })
        .collect();
    (!found.is_empty()).then_some(found)
}

/// The recorded files of `dir` for which `among` holds that are missing or whose bytes are not
/// the ones recorded, in the list's order (only those files are read); `None` when the folder
/// records no digests.
pub fn changed(dir: &Path, among: impl Fn(&str) -> bool) -> Option<Vec<String>> {
    let recorded = recorded(dir)?;
    Some(
        recorded
            .into_iter()
            .filter(|(path, _)| among(path))
            .filter(|(path, crc)| {
                std::fs::read(dir.join(path)).map_or(true, |b| crc32fast::hash(&b) != *crc)
            })
            .map(|(path, _)| path)
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edit_of_the_same_length_is_seen_and_old_lists_record_none() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("world.toml"), b"seed = 5\n").unwrap();
        std::fs::create_dir(dir.path().join("ground_truth")).unwrap();
        std::fs::write(dir.path().join("ground_truth/graph.json"), b"{}").unwrap();
        let files = manifest::list_files(dir.path()).unwrap();
        let text = manifest::complete_text(manifest::Kind::World, &files)
            + &lines(dir.path(), &files).unwrap();
        std::fs::write(dir.path().join(manifest::FILE), &text).unwrap();
        // The list still reads as a list of files (the digests are comments).
        assert_eq!(
            manifest::parse(&text),
            Some(manifest::Manifest::Complete(
                Some(manifest::Kind::World),
                files
            ))
        );
        assert_eq!(changed(dir.path(), |_| true), Some(vec![]));
        std::fs::write(dir.path().join("world.toml"), b"seed = 6\n").unwrap();
        assert_eq!(
            changed(dir.path(), |_| true),
            Some(vec!["world.toml".to_owned()])
        );
        std::fs::remove_file(dir.path().join("ground_truth/graph.json")).unwrap();
        assert_eq!(
            changed(dir.path(), |_| true),
            Some(vec![
                "ground_truth/graph.json".to_owned(),
                "world.toml".to_owned()
            ])
        );
        // A list written before digests.
        std::fs::write(
            dir.path().join(manifest::FILE),
            "complete world\n9 world.toml\n",
        )
        .unwrap();
        assert_eq!(changed(dir.path(), |_| true), None);
    }
}

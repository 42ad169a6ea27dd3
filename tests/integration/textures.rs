//! Textures (`[tileset] textures`): the images every format names, checked by the programs
//! that read them (trimesh, usd-core, MuJoCo, Pillow, OpenCV in `tests/readers/textures_check.py`);
//! `textures = "none"` giving the plain-colour files; the same bytes on one and three
//! threads; the user's own images copied, and bad ones refused with the key and the file.

use std::path::Path;

use crate::common::{
    arg, assert_same_on_one_and_three_threads, fails, folder_files, ok, read_with_python,
    small_cave_pipeline,
};

const READERS: [&str; 6] = ["numpy", "PIL", "trimesh", "pxr", "mujoco", "cv2"];

#[test]
fn every_format_names_images_its_reader_finds_and_the_bytes_do_not_depend_on_threads() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    let folders = assert_same_on_one_and_three_threads(dir.path(), &pipeline, "gltf,usd,mjcf,sdf");
    let world = &folders[0];
    let files = folder_files(world);
    for look in ["cave-wall", "cave-floor", "rock-pile", "striated-rock"] {
        for map in ["albedo", "normal", "roughness"] {
            let f = format!("mesh/textures/{look}-{map}.png");
            assert!(files.contains(&f), "{f} missing: {files:?}");
        }
    }
    read_with_python(&READERS, "textures_check.py", &[arg(world)]);
}

/// The files of `dir` but the pipeline record and the file list, which name the knob.
fn geometry_files(dir: &Path) -> Vec<String> {
    folder_files(dir)
        .into_iter()
        .filter(|f| f != "world.toml" && f != ".subtgraph-files")
        .collect()
}

#[test]
fn textures_none_writes_the_plain_colour_files_and_the_same_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let plain = small_cave_pipeline(dir.path(), 1, "textures = \"none\"\n");
    let plain_out = dir.path().join("plain");
    ok(&["generate", arg(&plain), "--out", arg(&plain_out)]);
    let textured = small_cave_pipeline(dir.path(), 1, "");
    let textured_out = dir.path().join("textured");
    ok(&["generate", arg(&textured), "--out", arg(&textured_out)]);

    let plain_files = geometry_files(&plain_out);
    assert!(
        !plain_files.iter().any(|f| f.starts_with("mesh/textures")),
        "{plain_files:?}"
    );
    let mtl = std::fs::read_to_string(plain_out.join("mesh/world.mtl")).unwrap();
    assert!(!mtl.contains("map_") && !mtl.contains("norm "), "{mtl}");
    // Every file of the plain world is in the textured one with the same bytes, but the MTL,
    // which adds only the maps' lines.
    for f in &plain_files {
        let a = std::fs::read(plain_out.join(f)).unwrap();
        let b = std::fs::read(textured_out.join(f)).unwrap();
        if f == "mesh/world.mtl" {
            let b = String::from_utf8(b).unwrap();
            let stripped: String = b
                .lines()
                .filter(|l| {
                    !l.starts_with("map_Kd ")
                        && !l.starts_with("map_Pr ")
                        && !l.starts_with("norm ")
                })
                .map(|l| format!("{l}\n"))
                .collect();
            assert_eq!(stripped, mtl);
            assert_eq!(b.matches("map_Kd textures/").count(), 4, "{b}");
        } else {
            assert!(a == b, "{f} differs with textures on");
        }
    }
    let extra: Vec<String> = geometry_files(&textured_out)
        .into_iter()
        .filter(|f| !plain_files.contains(f))
        .collect();
    assert_eq!(extra.len(), 12, "{extra:?}");
    assert!(extra.iter().all(|f| f.starts_with("mesh/textures/")));
}

/// A small PNG of `size` pixels, grey ramp.
fn png_file(path: &Path, size: u32) {
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, size, size);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let data: Vec<u8> = (0..size * size * 3).map(|i| (i % 251) as u8).collect();
        enc.write_header().unwrap().write_image_data(&data).unwrap();
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn a_users_images_are_copied_and_bad_ones_refused_naming_the_key_and_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("images")).unwrap();
    png_file(&dir.path().join("images/wall.png"), 32);
    png_file(&dir.path().join("images/floor-normal.png"), 16);
    let pipeline = small_cave_pipeline(
        dir.path(),
        1,
        "[tileset.textures]\ncave-wall = \"images/wall.png\"\ncave-floor = { normal = \"images/floor-normal.png\" }\n",
    );
    let out = dir.path().join("w");
    ok(&["generate", arg(&pipeline), "--out", arg(&out)]);
    let copied = |f: &str| std::fs::read(out.join("mesh/textures").join(f)).unwrap();
    assert_eq!(
        copied("cave-wall-albedo.png"),
        std::fs::read(dir.path().join("images/wall.png")).unwrap()
    );
    assert_eq!(
        copied("cave-floor-normal.png"),
        std::fs::read(dir.path().join("images/floor-normal.png")).unwrap()
    );
    // The maps not given stay procedural (a 256-pixel repeat by default).
    let floor = copied("cave-floor-albedo.png");
    let info = png::Decoder::new(std::io::Cursor::new(floor))
        .read_info()
        .unwrap();
    assert_eq!(info.info().width, 256);

    // A missing file, a file that is not a PNG, a material the tile set lacks.
    std::fs::write(dir.path().join("images/notes.png"), "not an image").unwrap();
    for (extra, says) in [
        (
            "[tileset.textures]\ncave-wall = \"images/missing.png\"\n",
            &["tileset.textures.cave-wall", "missing.png", "cannot read"][..],
        ),
        (
            "[tileset.textures]\ncave-wall = { albedo = \"images/notes.png\" }\n",
            &[
                "tileset.textures.cave-wall.albedo",
                "notes.png",
                "not a PNG",
            ][..],
        ),
        (
            "[tileset.textures]\nmine-wall = \"images/wall.png\"\n",
            &["tileset.textures.mine-wall", "cave-wall, cave-floor"][..],
        ),
        (
            "textures = \"photographic\"\n",
            &["tileset.textures", "\"none\""][..],
        ),
        (
            "texture_size = 3\n",
            &["tileset.texture_size", "16 to 4096"][..],
        ),
    ] {
        let sub = tempfile::tempdir_in(dir.path()).unwrap();
        let p = small_cave_pipeline(dir.path(), 1, extra);
        // The pipeline sits in `dir`, so `images/` resolves beside it.
        let message = fails(&["generate", arg(&p), "--out", arg(&sub.path().join("w"))]);
        for s in says {
            assert!(message.contains(s), "{extra}: {message}");
        }
        assert!(!sub.path().join("w").exists(), "nothing half-written");
    }
}

#[test]
fn preview_draws_the_albedo_and_a_camera_finds_far_more_corners() {
    let dir = tempfile::tempdir().unwrap();
    let mut pictures = Vec::new();
    for (name, extra) in [("plain", "textures = \"none\"\n"), ("textured", "")] {
        let p = small_cave_pipeline(dir.path(), 1, extra);
        let out = dir.path().join(name);
        ok(&["generate", arg(&p), "--out", arg(&out)]);
        let png = dir.path().join(format!("{name}.png"));
        ok(&[
            "preview",
            arg(&out),
            "--inside",
            "--size",
            "640x480",
            "--out",
            arg(&png),
        ]);
        pictures.push(png);
    }
    assert_ne!(
        std::fs::read(&pictures[0]).unwrap(),
        std::fs::read(&pictures[1]).unwrap()
    );
    // OpenCV's ORB on both pictures: at least ten times the keypoints with textures.
    read_with_python(
        &READERS,
        "textures_check.py",
        &["--orb", arg(&pictures[0]), arg(&pictures[1]), "10"],
    );
}

//! The mesh-file tile set: manifests, the errors bad ones get, and the DARPA SubT tiles when
//! `../shared/darpa-subt-tiles` is present (skipped with a message otherwise).

use std::path::{Path, PathBuf};

use subtgraph::core::assembly::assemble;
use subtgraph::core::grid::Direction;
use subtgraph::core::tileset::TileSet;
use subtgraph::core::{World, layout};
use subtgraph::tilesets::mesh_files::{MeshFiles, load};

/// A tile mesh for tests: a square tube (4 x 4 m) from the centre to each opening, 80 m pitch,
/// Z up.
fn tube_obj(openings: &[Direction]) -> String {
    let mut v = Vec::new();
    let mut f = Vec::new();
    for d in openings {
        let (r, c) = d.step();
        let (ax, ay) = (f64::from(c), -f64::from(r));
        let (px, py) = (-ay, ax);
        let base = v.len();
        for t in [0.0, 40.0] {
            for (s, z) in [(-2.0, 0.0), (2.0, 0.0), (2.0, 4.0), (-2.0, 4.0)] {
                v.push(format!("v {} {} {}", ax * t + px * s, ay * t + py * s, z));
            }
        }
        for k in 0..4 {
            let (a, b) = (base + k + 1, base + (k + 1) % 4 + 1);
            f.push(format!("f {a} {b} {}", b + 4));
            f.push(format!("f {a} {} {}", b + 4, a + 4));
        }
    }
    format!("o Tube\n{}\n{}\n", v.join("\n"), f.join("\n"))
}

fn write_tiles(dir: &Path) {
    use Direction::*;
    for (name, openings) in [
        ("dead.obj", vec![East]),
        ("straight.obj", vec![East, West]),
        ("corner.obj", vec![East, South]),
        ("tee.obj", vec![East, North, South]),
        ("cross.obj", vec![East, North, West, South]),
        // A straight written north-south: read as turned a quarter.
        ("straight-ns.obj", vec![North, South]),
    ] {
        std::fs::write(dir.join(name), tube_obj(&openings)).unwrap();
    }
}

fn manifest(dir: &Path, body: &str) -> PathBuf {
    let p = dir.join("tiles.toml");
    std::fs::write(&p, format!("pitch = 80.0\nup = \"z\"\n{body}")).unwrap();
    p
}

const ALL_KINDS: &str = r#"
[[tile]]
kind = "dead-end"
files = ["dead.obj"]
[[tile]]
kind = "straight"
files = ["straight.obj", "straight-ns.obj"]
[[tile]]
kind = "corner"
files = ["corner.obj"]
[[tile]]
kind = "t-junction"
files = ["tee.obj"]
[[tile]]
kind = "intersection"
files = ["cross.obj"]
"#;

fn cave(pitch: f64) -> World {
    let mut p = subtgraph::presets::load("cave").unwrap();
    p.world.tile_pitch = pitch;
    p.tileset = None;
    World::from(layout(&p, &subtgraph::registry()).unwrap())
}

#[test]
fn a_manifest_places_one_tile_per_cell_with_each_file_loaded_once() {
    let dir = tempfile::tempdir().unwrap();
    write_tiles(dir.path());
    let m = MeshFiles::open(&manifest(dir.path(), ALL_KINDS)).unwrap();
    assert_eq!(m.files_loaded(), 6, "six distinct files");
    assert_eq!(m.pitch(), Some(80.0));
    let world = cave(25.0);
    let mesh = assemble(&world, &m).unwrap();
    assert_eq!(mesh.tiles.len(), world.occupancy.occupied_count());
    // Scaled to the world's pitch: every vertex within half a pitch of its tile centre.
    for t in &mesh.tiles {
        let c = world.cell_position(t.cell);
        for tri in &mesh.visual.triangles[t.visual_triangles.clone()] {
            for &i in tri {
                let p = mesh.visual.positions[i as usize];
                assert!((f64::from(p[0]) - c[0]).abs() <= 12.5 + 1e-3);
                assert!((f64::from(p[1]) - c[1]).abs() <= 12.5 + 1e-3);
            }
        }
    }
    // Each tube end of a tile lands exactly on a tube end of its neighbour: the openings meet.
    assert!(mesh.visual.triangle_count() >= 8 * world.occupancy.occupied_count());
}

#[test]
fn bad_manifests_are_refused_naming_the_file_and_what_to_change() {
    let dir = tempfile::tempdir().unwrap();
    write_tiles(dir.path());
    std::fs::write(dir.path().join("broken.obj"), "v 1 2\nf 1 2 9\n").unwrap();
    std::fs::write(dir.path().join("mesh.fbx"), "binary").unwrap();
    // (manifest body, in the message, the error's variant)
    let cases: [(&str, &str, &str); 6] = [
        (
            "[[tile]]\nkind = \"straight\"\nfiles = [\"nope.obj\"]\n",
            "does not exist",
            "MissingFile",
        ),
        (
            "[[tile]]\nkind = \"spiral\"\nfiles = [\"straight.obj\"]\n",
            "unknown tile kind 'spiral'",
            "UnknownKind",
        ),
        (
            "[[tile]]\nkind = \"straight\"\nfiles = [\"broken.obj\"]\n",
            "broken.obj",
            "Mesh { path: \"",
        ),
        (
            "[[tile]]\nkind = \"straight\"\nfiles = [\"mesh.fbx\"]\n",
            "assimp",
            "Mesh { path: \"",
        ),
        (
            "[[tile]]\nkind = \"corner\"\nfiles = [\"straight.obj\"]\n",
            "listed as corner but opens east and west",
            "Openings",
        ),
        (
            "[[tile]]\nkind = \"straight\"\nfiles = [\"straight.obj\"]\n[[tile]]\nkind = \"straight\"\nfiles = [\"straight.obj\"]\n",
            "two [[tile]] entries",
            "DuplicateKind",
        ),
    ];
    for (body, want, variant) in cases {
        let err = MeshFiles::open(&manifest(dir.path(), body))
            .err()
            .expect(body);
        assert!(
            format!("{err:?}").starts_with(variant),
            "{variant}: {err:?}"
        );
        let err = err.to_string();
        assert!(err.contains(want), "want '{want}' in: {err}");
        assert!(err.contains("tiles.toml"), "names the manifest: {err}");
    }
    // A pitch that does not match the meshes: no openings where the manifest says they are.
    let p = dir.path().join("wrong-pitch.toml");
    std::fs::write(&p, format!("pitch = 60.0\nup = \"z\"\n{ALL_KINDS}")).unwrap();
    let err = MeshFiles::open(&p).err().unwrap().to_string();
    assert!(err.contains("±30 m") && err.contains("`pitch`"), "{err}");
    // A kind the world needs but the manifest lacks.
    let m = MeshFiles::open(&manifest(
        dir.path(),
        "[[tile]]\nkind = \"straight\"\nfiles = [\"straight.obj\"]\n",
    ))
    .unwrap();
    let err = assemble(&cave(25.0), &m).unwrap_err().to_string();
    assert!(
        err.contains("has no tile for") && err.contains("corner"),
        "{err}"
    );
}

fn darpa() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/darpa-subt-tiles/cave-type-b");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "skipping: {} is absent (the DARPA tiles live in ../shared)",
            dir.display()
        );
        None
    }
}

#[test]
fn the_darpa_tiles_load_as_measured() {
    let Some(dir) = darpa() else { return };
    // Triangle counts per file, as the data's README reports them.
    for (file, triangles) in [
        ("cave_straight_01_type_b/cavestraight01.obj", 29_597),
        ("cave_corner_02_type_b/cavecorner02.obj", 11_616),
        ("cave_3_way_01_type_b/cave3way.obj", 25_967),
        ("cave_cap_type_b/cavecap.obj", 4_350),
        ("cave_vertical_shaft_type_b/caveverticalshaft.obj", 17_528),
    ] {
        let parts = load(&dir.join(file)).unwrap();
        let n: usize = parts.iter().map(|p| p.triangles.len()).sum();
        assert_eq!(n, triangles, "{file}");
    }
    // The Collada original of the same straight, declared in centimetres and Z up, read in
    // metres: it runs along its y axis, 25 m between openings (the OBJ is 3.2 times larger).
    let dae = load(&dir.join("cave_straight_02_type_b/cavestraight02.dae")).unwrap();
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for v in dae.iter().flat_map(|p| &p.positions) {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    assert!(
        (25.0..25.3).contains(&(hi[1] - lo[1])),
        "y span {}",
        hi[1] - lo[1]
    );
    assert!(
        hi[0] - lo[0] < 17.0 && (14.0..15.0).contains(&hi[2]),
        "{lo:?} {hi:?}"
    );
    assert!(dae.iter().any(|p| p.name.starts_with("CaveWall")));
}

#[test]
fn the_darpa_manifest_builds_the_papers_worlds() {
    let Some(_) = darpa() else { return };
    let manifest =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tilesets/manifests/darpa-cave-type-b.toml");
    let m = MeshFiles::open(&manifest).unwrap();
    assert_eq!(m.files_loaded(), 12, "12 distinct files, each read once");
    // A two-level world at the original's 80 m pitch: shafts climb 64 m, as the tiles do.
    let mut p = subtgraph::presets::load("mine").unwrap();
    p.world.levels = subtgraph::core::config::IntRange::Fixed(2);
    p.world.tile_pitch = 80.0;
    p.tileset = None;
    // The DARPA tiles have shafts, not the mine preset's ramps.
    p.world.connections = Some(subtgraph::core::config::Connections::Shaft);
    let world = layout(&p, &subtgraph::registry()).unwrap();
    assert_eq!(world.resolved.level_height, 64.0);
    let mesh = assemble(&world, &m).unwrap();
    assert_eq!(mesh.tiles.len(), world.occupancy.occupied_count());
    let used: std::collections::BTreeSet<u8> = mesh.visual.materials.iter().copied().collect();
    assert!(
        used.len() >= 2,
        "cave wall, rock pile and striated rock are told apart: {used:?}"
    );
    assert!(mesh.collision.triangle_count() * 3 < mesh.visual.triangle_count());
    // A tile's geometry stays around its cell (the rock of these meshes reaches 17 m past the
    // tile boundary, and a cap sits outside the opening it closes, 21 m deep).
    for t in mesh.tiles.iter().step_by(7) {
        let c = world.cell_position(t.cell);
        for tri in &mesh.visual.triangles[t.visual_triangles.clone()] {
            let v = mesh.visual.positions[tri[0] as usize];
            assert!((f64::from(v[0]) - c[0]).abs() < 62.0 && (f64::from(v[1]) - c[1]).abs() < 62.0);
        }
    }
    // Levels 64 m apart but a pitch for which the shafts climb 20 m: refused with the fix.
    let mut p2 = p.clone();
    p2.world.tile_pitch = 25.0;
    p2.world.level_height = Some(64.0);
    let w2 = layout(&p2, &subtgraph::registry()).unwrap();
    let err = assemble(&w2, &m).unwrap_err().to_string();
    assert!(err.contains("set world.level_height = 20"), "{err}");
}

/// Straights, T-junctions and intersections with their rotations given (as the DARPA
/// manifest gives them), so openings are not read at the manifest's pitch.
const THROUGH_KINDS: &str = r#"
[[tile]]
kind = "straight"
rotation = 0
files = ["straight.obj"]
[[tile]]
kind = "t-junction"
rotation = 0
files = ["tee.obj"]
[[tile]]
kind = "intersection"
rotation = 0
files = ["cross.obj"]
"#;

#[test]
fn a_pitch_the_meshes_contradict_is_refused_with_the_measured_one() {
    let dir = tempfile::tempdir().unwrap();
    write_tiles(dir.path());
    let open = |head: &str, body: &str| {
        let p = dir.path().join("pitch.toml");
        std::fs::write(&p, format!("{head}\nup = \"z\"\n{body}")).unwrap();
        MeshFiles::open(&p).map_err(|e| e.to_string())
    };
    // The meshes' openings are 80 m apart: the right pitch loads.
    assert_eq!(
        open("pitch = 80.0", THROUGH_KINDS).unwrap().pitch(),
        Some(80.0)
    );
    // Half of it, and an absurd one: refused with what the meshes measure, never a level
    // height to go with the wrong pitch (issue 10, item 12).
    for pitch in ["40", "1e30", "0.001"] {
        let err = open(&format!("pitch = {pitch}"), THROUGH_KINDS)
            .err()
            .unwrap_or_else(|| panic!("pitch = {pitch} is accepted"));
        assert!(
            err.contains("the meshes' openings are 80 m apart") && err.contains("set pitch = 80"),
            "{pitch}: {err}"
        );
        assert!(!err.contains("level_height"), "{err}");
    }
    // In file units when the files are scaled.
    let err = open("pitch = 40.0\nscale = 0.5", THROUGH_KINDS)
        .err()
        .unwrap();
    assert!(
        err.contains("openings are 40 m apart") && err.contains("set pitch = 80 (in file units"),
        "{err}"
    );
    assert!(open("pitch = 80.0\nscale = 0.5", THROUGH_KINDS).is_ok());
    // A rotation is a quarter-turn count, not taken modulo 4.
    for r in [4, 7, 255] {
        let body = THROUGH_KINDS.replacen("rotation = 0", &format!("rotation = {r}"), 1);
        let err = open("pitch = 80.0", &body).err().unwrap();
        assert!(
            err.contains(&format!("rotation = {r}")) && err.contains("0, 1, 2 or 3"),
            "{err}"
        );
    }
}

#[test]
fn the_darpa_manifest_with_a_wrong_pitch_is_told_the_real_one() {
    let Some(tiles) = darpa() else { return };
    let shipped = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tilesets/manifests/darpa-cave-type-b.toml"),
    )
    .unwrap();
    let root = format!("root = {:?}", tiles.display().to_string());
    let dir = tempfile::tempdir().unwrap();
    for (from, to, want) in [
        (
            "pitch = 80.0",
            "pitch = 40.0",
            "openings are 80 m apart; set pitch = 80",
        ),
        (
            "pitch = 80.0",
            "pitch = 1e30",
            "openings are 80 m apart; set pitch = 80",
        ),
        (
            "rotation = 1",
            "rotation = 7",
            "rotation = 7: give the quarter turns as 0, 1, 2 or 3",
        ),
    ] {
        let text = shipped
            .lines()
            .map(|l| {
                if l.starts_with("root =") {
                    root.clone()
                } else {
                    l.to_owned()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
            .replace(from, to);
        let p = dir.path().join("darpa.toml");
        std::fs::write(&p, text).unwrap();
        let err = MeshFiles::open(&p)
            .err()
            .unwrap_or_else(|| panic!("{to} is accepted"))
            .to_string();
        assert!(err.contains(want), "{to}: {err}");
        assert!(!err.contains("level_height"), "{err}");
    }
}

/// The shaft's `top` and `split` keys: refused on other kinds, with an unknown direction, a
/// split outside the climb, or no `shaft_rise` to place the landing's part by; each message
/// names the key and what to write. `top = "none"` needs no rise (the shaft is not cut).
#[test]
fn bad_shaft_keys_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    write_tiles(dir.path());
    let shaft = |head: &str, keys: &str| {
        format!(
            "{head}\n[[tile]]\nkind = \"shaft-up\"\nrotation = 0\nfiles = [\"dead.obj\"]\n{keys}\n"
        )
    };
    for (body, want) in [
        (
            "[[tile]]\nkind = \"straight\"\nfiles = [\"straight.obj\"]\ntop = \"west\"".to_string(),
            "tile 'straight': `top` and `split` describe a shaft",
        ),
        (
            shaft("shaft_rise = 64.0", "top = \"up\""),
            "top = \"up\": use east, north, west, south or none",
        ),
        (
            shaft("shaft_rise = 64.0", "split = 64.0"),
            "split = 64: cut the shaft between its foot and its top, above 0 and below \
             shaft_rise = 64",
        ),
        (shaft("", ""), "set shaft_rise"),
        (
            shaft("", "top = \"none\"\nsplit = 10.0"),
            "a shaft with top = \"none\" is not cut",
        ),
    ] {
        let err = MeshFiles::open(&manifest(dir.path(), &body))
            .err()
            .unwrap_or_else(|| panic!("accepted:\n{body}"))
            .to_string();
        assert!(err.contains(want), "{body}\n{err}");
    }
    assert!(MeshFiles::open(&manifest(dir.path(), &shaft("", "top = \"none\""))).is_ok());
    assert!(MeshFiles::open(&manifest(dir.path(), &shaft("shaft_rise = 3.0", ""))).is_ok());
}

/// Issue 21 item 18: a manifest's message names the key that is wrong and a value that works.
/// Before, `rise` on the straight tile was "two [[tile]] entries for 'elevation'", `scale =
/// 1e-45` said "set pitch = 112" and `scale = 1e39` "set pitch = inf", and `shaft_rise = 1e12`
/// was blamed on `world.tile_pitch` (at generation, after the tiles were loaded).
#[test]
fn manifest_messages_name_the_wrong_key_and_a_value_that_works() {
    let dir = tempfile::tempdir().unwrap();
    write_tiles(dir.path());
    let elevation =
        "[[tile]]\nkind = \"elevation\"\nfiles = [\"straight.obj\"]\nrise = 32.0\nrate = 0.3\n";
    let with_rise = ALL_KINDS.replace(
        "files = [\"straight.obj\", \"straight-ns.obj\"]",
        "files = [\"straight.obj\", \"straight-ns.obj\"]\nrise = 32.0",
    );
    let shaft = |rise: &str| {
        format!(
            "shaft_rise = {rise}\n{ALL_KINDS}\n[[tile]]\nkind = \"shaft-up\"\nrotation = 0\nfiles = [\"dead.obj\"]\n"
        )
    };
    for (head, body, want, not) in [
        (
            "",
            format!("{with_rise}{elevation}"),
            vec![
                "tile 'straight': rise = 32",
                "give it on the kind = \"elevation\" tile",
            ],
            "two [[tile]] entries",
        ),
        (
            "scale = 1e-45",
            ALL_KINDS.to_owned(),
            vec![
                "scale = 1e-45: scale turns file units into metres",
                "like scale = 1",
            ],
            "set pitch",
        ),
        (
            "scale = 1e39",
            ALL_KINDS.to_owned(),
            vec!["scale = 1e39", "from 0.0001 to 10000", "like scale = 1"],
            "set pitch",
        ),
        (
            "",
            shaft("1e12"),
            vec!["shaft_rise = 1e12", "4 file units tall", "below 4"],
            "tile_pitch",
        ),
        (
            "",
            shaft("-3"),
            vec!["shaft_rise = -3", "a positive number"],
            "tile_pitch",
        ),
    ] {
        let p = dir.path().join("keys.toml");
        std::fs::write(&p, format!("pitch = 80.0\nup = \"z\"\n{head}\n{body}")).unwrap();
        let err = MeshFiles::open(&p)
            .err()
            .unwrap_or_else(|| panic!("accepted: {head} {want:?}"))
            .to_string();
        for w in want {
            assert!(err.contains(w), "want '{w}' in: {err}");
        }
        assert!(!err.contains(not), "{err}");
        assert!(err.contains("keys.toml"), "names the manifest: {err}");
    }
    // The values the messages suggest are accepted.
    let p = dir.path().join("fixed.toml");
    for body in [format!("scale = 1\n{ALL_KINDS}"), shaft("3")] {
        std::fs::write(&p, format!("pitch = 80.0\nup = \"z\"\n{body}")).unwrap();
        MeshFiles::open(&p).unwrap_or_else(|e| panic!("{body}: {e}"));
    }
}

#[test]
fn a_manifest_material_may_name_its_albedo_image_which_the_world_carries() {
    let dir = tempfile::tempdir().unwrap();
    write_tiles(dir.path());
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, 4, 4);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let data: Vec<u8> = (0..48).map(|i| (i * 5) as u8).collect();
        enc.write_header().unwrap().write_image_data(&data).unwrap();
    }
    std::fs::write(dir.path().join("rock.png"), &png_bytes).unwrap();
    let body = format!(
        "[[material]]\nname = \"rock wall\"\ncolour = [0.5, 0.5, 0.5]\ntexture = \"rock.png\"\n{ALL_KINDS}"
    );
    let m = MeshFiles::open(&manifest(dir.path(), &body)).unwrap();
    let mesh = assemble(&cave(25.0), &m).unwrap();
    assert_eq!(
        mesh.materials[0].texture.as_deref(),
        Some("textures/rock_wall-albedo.png")
    );
    assert_eq!(mesh.textures.len(), 1);
    assert_eq!(mesh.textures[0].path, "textures/rock_wall-albedo.png");
    assert_eq!(mesh.textures[0].bytes, png_bytes);

    // Not an image: refused naming the material, the key and the file.
    std::fs::write(dir.path().join("notes.png"), "text").unwrap();
    let body = format!("[[material]]\nname = \"rock\"\ntexture = \"notes.png\"\n{ALL_KINDS}");
    let e = MeshFiles::open(&manifest(dir.path(), &body))
        .err()
        .expect("refused")
        .to_string();
    for s in [
        "tiles.toml",
        "material 'rock'",
        "texture = \"notes.png\"",
        "not a PNG",
    ] {
        assert!(e.contains(s), "{e}");
    }
}

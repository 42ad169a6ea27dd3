//! `subtgraph preview`'s lights and views, measured on the pictures it writes: the lamp
//! lights near rock brighter than far rock of the same facing (the sun does not), a camera
//! inside a passage sees rock all round, bad options are refused naming what to pass, and the
//! same world gives the same bytes.

use crate::common::{self, arg, fails, ok};

use std::path::Path;

/// The background colour `preview` leaves where no surface is drawn.
const BACKGROUND: [u8; 3] = [18, 18, 22];

/// The pixels of an RGB PNG, row by row.
fn pixels(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let mut reader = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let px = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width as usize, info.height as usize, px)
}

/// A world folder holding only a mesh: a flat floor 200 m square of 20 x 20 cells, every
/// triangle facing up (the side `preview` draws from above).
fn flat_floor(dir: &Path) -> std::path::PathBuf {
    let world = dir.join("floor");
    std::fs::create_dir_all(world.join("mesh")).unwrap();
    let mut obj = String::new();
    let n = 20;
    for j in 0..=n {
        for i in 0..=n {
            obj += &format!("v {} {} 0\n", 10 * i, 10 * j);
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            // Counter-clockwise seen from above: normals up.
            obj += &format!("f {} {} {}\n", at(i, j), at(i + 1, j), at(i + 1, j + 1));
            obj += &format!("f {} {} {}\n", at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    std::fs::write(world.join("mesh/world.obj"), obj).unwrap();
    world
}

/// Mean brightness (sum of R, G, B) of the drawn pixels in rows `rows` of a picture.
fn mean_drawn(w: usize, px: &[[u8; 3]], rows: std::ops::Range<usize>) -> f64 {
    let drawn: Vec<u32> = rows
        .flat_map(|y| px[y * w..(y + 1) * w].iter())
        .filter(|p| **p != BACKGROUND)
        .map(|p| p.iter().map(|&c| u32::from(c)).sum())
        .collect();
    assert!(!drawn.is_empty(), "no floor drawn in those rows");
    f64::from(drawn.iter().sum::<u32>()) / drawn.len() as f64
}

/// The camera looks at the floor from the south-west and above, so its near edge is at the
/// bottom of the picture and its far edge at the top. Under the lamp the near quarter is
/// clearly brighter than the far quarter; under the sun every pixel of the floor (one facing)
/// has the same colour.
#[test]
fn the_lamp_lights_near_rock_brighter_than_far_rock_of_the_same_facing() {
    let dir = tempfile::tempdir().unwrap();
    let world = flat_floor(dir.path());
    let lamp = dir.path().join("lamp.png");
    let sun = dir.path().join("sun.png");
    ok(&[
        "preview",
        arg(&world),
        "--size",
        "160x120",
        "--light",
        "lamp",
        "--out",
        arg(&lamp),
    ]);
    ok(&[
        "preview",
        arg(&world),
        "--size",
        "160x120",
        "--light",
        "sun",
        "--out",
        arg(&sun),
    ]);

    let (w, h, px) = pixels(&lamp);
    let rows: Vec<usize> = (0..h)
        .filter(|&y| px[y * w..(y + 1) * w].iter().any(|p| *p != BACKGROUND))
        .collect();
    let (top, bottom) = (rows[0], rows[rows.len() - 1] + 1);
    let quarter = (bottom - top) / 4;
    let far = mean_drawn(w, &px, top..top + quarter);
    let near = mean_drawn(w, &px, bottom - quarter..bottom);
    assert!(near > 1.2 * far, "near {near:.1} vs far {far:.1}");
    // Nothing pure black: the ambient light reaches the farthest floor.
    assert!(
        px.iter()
            .filter(|p| **p != BACKGROUND)
            .all(|p| p.iter().all(|&c| c >= 40))
    );

    let (_, _, px) = pixels(&sun);
    let floor: std::collections::BTreeSet<[u8; 3]> =
        px.iter().filter(|p| **p != BACKGROUND).copied().collect();
    assert_eq!(floor.len(), 1, "the sun lights one facing alike: {floor:?}");
}

/// From inside the passage at the start (with the ground-truth graph, and without it, where
/// the floor is found on the mesh), the camera sees rock in every direction: a camera outside
/// the passage or under its floor would see the background. The lamp and the sun both draw,
/// differently, and every picture is the same bytes when drawn again.
#[test]
fn inside_views_see_rock_all_round_and_draw_the_same_bytes_again() {
    let dir = tempfile::tempdir().unwrap();
    let p = common::small_cave_pipeline(dir.path(), 1, "");
    for (name, format) in [("gt", "obj,ground-truth"), ("plain", "obj")] {
        let w = dir.path().join(name);
        ok(&["generate", arg(&p), "--format", format, "--out", arg(&w)]);
        assert_eq!(w.join("ground_truth/graph.json").is_file(), name == "gt");
        let mut drawn = Vec::new();
        for (light, run) in [("lamp", 1), ("lamp", 2), ("sun", 1)] {
            let out = dir.path().join(format!("{name}-{light}-{run}.png"));
            let said = ok(&[
                "preview",
                arg(&w),
                "--inside",
                "--light",
                light,
                "--size",
                "96x64",
                "--out",
                arg(&out),
            ]);
            assert!(said.contains("triangles drawn"), "{said}");
            let (_, _, px) = pixels(&out);
            let rock = px.iter().filter(|p| **p != BACKGROUND).count();
            assert!(
                rock * 100 >= px.len() * 99,
                "{name}, {light}: only {rock} of {} pixels show rock",
                px.len()
            );
            drawn.push(std::fs::read(&out).unwrap());
        }
        assert_eq!(
            drawn[0], drawn[1],
            "{name}: the lamp picture changed between runs"
        );
        assert_ne!(
            drawn[0], drawn[2],
            "{name}: the lamp and the sun drew the same picture"
        );
        // --inside defaults to the lamp.
        let default = dir.path().join(format!("{name}-default.png"));
        ok(&[
            "preview",
            arg(&w),
            "--inside",
            "--size",
            "96x64",
            "--out",
            arg(&default),
        ]);
        assert_eq!(std::fs::read(&default).unwrap(), drawn[0]);
    }
    // The whole world and a close-up at another node, drawn twice, are the same bytes.
    let w = dir.path().join("gt");
    for view in [&[][..], &["--close-up", "--at", "1"][..]] {
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        for out in [&a, &b] {
            let mut args = vec!["preview", arg(&w), "--size", "120x80", "--out", arg(out)];
            args.extend_from_slice(view);
            ok(&args);
        }
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{view:?}"
        );
    }
}

/// Bad options are refused before anything is written, saying what to pass instead.
#[test]
fn preview_refuses_an_unknown_light_and_a_node_that_is_not_there() {
    let dir = tempfile::tempdir().unwrap();
    let p = common::small_cave_pipeline(dir.path(), 1, "");
    let w = dir.path().join("w");
    ok(&["generate", arg(&p), "--format", "obj", "--out", arg(&w)]);
    let out = dir.path().join("x.png");
    let run = |extra: &[&str]| {
        let mut args = vec!["preview", arg(&w), "--size", "32x32", "--out", arg(&out)];
        args.extend_from_slice(extra);
        fails(&args)
    };
    let e = run(&["--light", "torch"]);
    assert!(
        e.contains("--light must be lamp") && e.contains("or sun") && e.contains("not 'torch'"),
        "{e}"
    );
    let e = run(&["--inside", "--at", "9999"]);
    assert!(e.contains("--at 9999") && e.contains("nodes 0 to"), "{e}");
    let e = run(&["--at", "0"]);
    assert!(e.contains("--close-up or --inside"), "{e}");
    let e = run(&["--inside", "--close-up"]);
    assert!(e.contains("--inside") && e.contains("--close-up"), "{e}");
    assert!(!out.exists());
}
